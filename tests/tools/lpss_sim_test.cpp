// lpss-sim as a user runs it: the CSV it writes, and the message and exit status of a refused scene.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <vector>

#include <sstream>
#include <string>
#include "lpss/common/scene.hpp"
#include "lpss/common/state_csv.hpp"
#include "test_workspace.hpp"

namespace {

struct Result {
    int status = -1;
    std::string output;
};

Result run(const std::string& command) {
    Result r;
    std::FILE* pipe = popen((command + " 2>&1").c_str(), "r");
    if (pipe == nullptr) return r;
    std::array<char, 4096> buffer{};
    while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr)
        r.output += buffer.data();
    int raw = pclose(pipe);
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return r;
}

const std::string kSim = LPSS_SIM;
const std::string kScene = std::string(LPSS_SOURCE_DIR) + "/deploy/scenes/two_spheres.textproto";

TEST(LpssSim, WritesTheStateCsv) {
    const std::string csv = lpss::testing::workspace_path("states.csv");
    Result r = run(kSim + " " + kScene + " --frames 180 --every 60 --csv " + csv);
    ASSERT_EQ(r.status, 0) << r.output;
    std::ifstream in(csv);
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header, "frame,id,x,y,z,qx,qy,qz,qw,vx,vy,vz,si,sj,sk,lx,ly,lz");
    std::vector<std::string> rows;
    for (std::string line; std::getline(in, line);)
        rows.push_back(line);
    ASSERT_EQ(rows.size(), 8u) << "frames 0, 60, 120, 180 of two bodies";
    EXPECT_EQ(rows.front().rfind("0,1,-2.0499999999999998,0,0,", 0), 0u) << "17 digits: " << rows.front();
    // The last row: body 2 after the bounce. An elastic head-on collision of equal masses swaps their
    // velocities: it moves right at 2 units/s (kinetic energy neither gained nor lost, within 0.5%), and at
    // 3 s it is where it would be had it bounced at contact: it met the other sphere at t = 3.1 / 4 s, at
    // x = 0.5, and has since moved 2 (3 - 0.775) = 4.45 units, to x = 4.95. Discrete collision detection
    // finds the contact up to one step late: each body may be off by one step of its motion (2/60).
    std::istringstream last(rows.back());
    std::vector<std::string> fields;
    for (std::string f; std::getline(last, f, ',');)
        fields.push_back(f);
    ASSERT_EQ(fields.size(), 18u);
    EXPECT_EQ(fields[0], "180");
    EXPECT_EQ(fields[1], "2");
    const double speed = 2.0, dt = 1.0 / 60.0, contact_time = (4.1 - 1.0) / (2 * speed);
    const double analytic_x = 0.5 + speed * (3.0 - contact_time);
    EXPECT_NEAR(std::stod(fields[2]), analytic_x, speed * dt + 1e-3);
    EXPECT_NEAR(std::stod(fields[9]), speed, 0.005 * speed);
    std::remove(csv.c_str());
}

TEST(LpssSim, PrintsASummaryWithoutCsv) {
    Result r = run(kSim + " " + kScene + " --frames 60");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("bodies       2"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("float Bullet, sectorized, L = 128"), std::string::npos) << r.output;
}

TEST(LpssSim, RefusesABadSceneWithANamedError) {
    const std::string path = lpss::testing::workspace_path("bad.textproto");
    std::ofstream(path) << "sector_size: 128\nbodies { id: 3 name: \"crate\" shape { box { half_extents { x: "
                           "1 y: 0 z: 1 } } } mass: 1 }\n";
    Result r = run(kSim + " " + path + " --frames 10");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("body 'crate' (id 3): shape.box.half_extents.y must be > 0, got 0"),
              std::string::npos)
        << r.output;
    std::remove(path.c_str());
    r = run(kSim + " /nonexistent.textproto");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.output.find("cannot open"), std::string::npos);
}

TEST(LpssSim, DoubleTwinRunsMonolithic) {
    Result r = run(std::string(LPSS_SIM_F64) + " " + kScene + " --frames 10 --monolithic");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("double Bullet, monolithic"), std::string::npos) << r.output;
}

}  // namespace

namespace {

/// Each body's height above the scene's ground plane in every frame of an lpss-sim CSV: id -> heights.
std::map<std::uint64_t, std::vector<double>> heights_above_ground(const std::string& csv,
                                                                  const lpss::Scene& scene) {
    const lpss::BodyDesc& ground = scene.bodies.front();
    const Eigen::Vector3d normal = std::get<lpss::Plane>(ground.shape).normal;
    const Eigen::Vector3d at = std::get<Eigen::Vector3d>(ground.position);
    std::map<std::uint64_t, std::vector<double>> out;
    const lpss::Expected<std::vector<lpss::StateCsvRow>> rows = lpss::read_state_csv(csv);
    EXPECT_TRUE(rows) << rows.error().message;
    if (!rows) return out;
    for (const lpss::StateCsvRow& r : rows.value())
        out[r.body.id].push_back(normal.dot(r.global - at));
    return out;
}

// Why lpss matters to a federation: vehicles on a road 6.4e6 m from the origin (ECEF), where a float's
// spacing is half a metre. lpss keeps them on it; plain float Bullet places and moves them in half-metre
// steps.
TEST(LpssSim, KeepsTheEcefConvoyOnItsRoadWherePlainFloatBulletCannot) {
    const std::string path = std::string(LPSS_SOURCE_DIR) + "/deploy/scenes/ecef_convoy.textproto";
    auto scene = lpss::load_scene(path);
    ASSERT_TRUE(scene) << scene.error().message;
    const std::string lpss_csv = lpss::testing::workspace_path("convoy.csv"),
                      plain_csv = lpss::testing::workspace_path("convoy_plain.csv");
    ASSERT_EQ(run(kSim + " " + path + " --frames 900 --csv " + lpss_csv).status, 0);
    ASSERT_EQ(run(kSim + " " + path + " --frames 900 --monolithic --csv " + plain_csv).status, 0);
    auto worst_off = [&](const std::string& csv) {
        // Vehicles (ids 100-111) rest 0.75 above the road, crates (200-219) 0.5; the first frames settle
        // the vehicles from the 5 cm they start above it.
        double worst = 0.0;
        for (const auto& [id, heights] : heights_above_ground(csv, *scene)) {
            if (id < 100) continue;  // the ground
            const double rest = id >= 200 ? 0.5 : 0.75;
            for (std::size_t f = 30; f < heights.size(); ++f)
                worst = std::max(worst, std::abs(heights[f] - rest));
        }
        return worst;
    };
    const double lpss_off = worst_off(lpss_csv), plain_off = worst_off(plain_csv);
    std::printf(
        "worst distance from resting on the road over 900 frames: lpss %.2g m, plain float Bullet %.2g m\n",
        lpss_off, plain_off);
    EXPECT_LT(lpss_off, 3e-3);
    EXPECT_GT(plain_off, 0.1);
}

}  // namespace
