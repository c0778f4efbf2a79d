// lpss-view in a real browser: a cluster runs a scene with every shape and a body 10^12 units out,
// lpss-view serves it, and Debian's chromium (driven by tests/view/check_page.js through puppeteer-core)
// opens the page. The page's own state says what it drew; a screenshot is kept in the build folder.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

#include "cluster_harness.hpp"
#include "node_tools.hpp"

namespace lpss {
namespace {

using testing::read_file;
using testing::start_cluster;

/// The numbers of a flat JSON array field ("drawnGlobal":[1,2,3]) of check_page.js's line; empty if absent.
std::vector<double> numbers_of(const std::string& json, const std::string& key) {
    const std::string tag = "\"" + key + "\":[";
    const std::size_t at = json.find(tag);
    std::vector<double> out;
    if (at == std::string::npos) return out;
    const char* p = json.c_str() + at + tag.size();
    for (;;) {
        char* end = nullptr;
        const double v = std::strtod(p, &end);
        if (end == p) break;
        out.push_back(v);
        p = end;
        if (*p != ',') break;
        ++p;
    }
    return out;
}

/// Runs check_page.js with `arguments`; returns its JSON line (and the exit code in `code`).
std::string check_page(const std::string& arguments, const std::string& log, int& code) {
    const std::string command = "node " + std::string(LPSS_SOURCE_DIR) + "/tests/view/check_page.js " +
                                arguments + " > " + log + " 2>&1";
    const int status = std::system(command.c_str());
    code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return read_file(log);
}

constexpr const char* kScene = R"(sector_size: 64
gravity { y: -9.81 }
bodies { id: 1 name: "ground" shape { plane { normal { y: 1 } offset: 0 } } mass: 0 position { global { x: 0 y: 0 z: 0 } } }
bodies { id: 2 name: "crate" shape { box { half_extents { x: 0.5 y: 0.5 z: 0.5 } } } mass: 1 position { global { x: 0 y: 0.5 z: 0 } } }
bodies { id: 3 name: "ball" shape { sphere { radius: 0.5 } } mass: 1 position { global { x: 3 y: 4 z: 0 } } linear_velocity { x: -1 } }
bodies { id: 4 name: "pill" shape { capsule { radius: 0.3 height: 1 } } mass: 1 position { global { x: -3 y: 2 z: 1 } } }
bodies { id: 5 name: "rock" shape { convex_hull { points { x: 0 y: 0 z: 0 } points { x: 1 y: 0 z: 0 } points { x: 0 y: 1 z: 0 } points { x: 0 y: 0 z: 1 } } } mass: 1 position { global { x: 2 y: 1 z: -2 } } }
bodies { id: 6 name: "runner" shape { box { half_extents { x: 0.5 y: 0.5 z: 0.5 } } } mass: 1 position { global { x: -40 y: 0.5 z: 0 } } linear_velocity { x: 2 } material { friction: 0 } }
bodies { id: 100 name: "far-plinth" shape { box { half_extents { x: 2 y: 0.5 z: 2 } } } mass: 0 position { global { x: 1000000000000.375 y: 2.5 z: -3.25 } } }
bodies { id: 101 name: "far-ball" shape { sphere { radius: 0.5 } } mass: 1 position { global { x: 1000000000000.375 y: 4 z: -3.25 } } }
)";

TEST(View, ChromiumDrawsEveryBodyAndOneTenToTheTwelveOutWhereItIs) {
    if (const std::string missing = testing::node_tool_missing("puppeteer-core"); !missing.empty())
        GTEST_SKIP() << missing;
    constexpr int kDomain = 147;
    const testing::DomainCleanup cleanup(kDomain);
    const std::string dir = testing::workspace_path("view");
    testing::remove_stale(dir);
    std::filesystem::create_directories(dir);
    const std::string scene = dir + "/view.textproto";
    std::ofstream(scene) << kScene;
    // Block size 1: sectors alternate between the two workers, so both own bodies.
    auto cluster = start_cluster(scene, kDomain, 2, 60 * 90, {"--block-size", "1"});
    ASSERT_TRUE(cluster.process);
    const std::string view_log = dir + "/lpss-view.log";
    auto view = runtime::ChildProcess::start(LPSS_VIEW, {"--domain", std::to_string(kDomain), "--port", "0"},
                                             view_log);
    ASSERT_TRUE(view);
    std::string url;
    const std::regex address(R"((http://127\.0\.0\.1:[0-9]+/))");
    for (int n = 0; n < 300 && url.empty(); ++n) {
        std::smatch m;
        const std::string text = read_file(view_log);
        if (std::regex_search(text, m, address)) url = m[1];
        if (url.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ASSERT_FALSE(url.empty()) << read_file(view_log);

    int code = 0;
    const std::string overview = check_page("--url " + url + " --screenshot " + std::string(LPSS_BINARY_DIR) +
                                                "/lpss-view-overview.png --expect-bodies 8 --min-frames 10 "
                                                "--timeout-s 90",
                                            dir + "/overview.json", code);
    std::printf("overview: %s", overview.c_str());
    ASSERT_EQ(code, 0) << overview;
    EXPECT_NE(overview.find("\"ok\":true"), std::string::npos);
    EXPECT_NE(overview.find("\"bodies\":8"), std::string::npos);
    // Drawn by owner: the plane belongs to no worker (0); each worker owns some of the other seven.
    const std::regex per_worker(R"re("workers":\{"0":1,"1":([0-9]+),"2":([0-9]+)\})re");
    std::smatch owners;
    ASSERT_TRUE(std::regex_search(overview, owners, per_worker)) << overview;
    EXPECT_EQ(std::stoi(owners[1]) + std::stoi(owners[2]), 7);
    EXPECT_GE(std::stoi(owners[1]), 1);
    EXPECT_GE(std::stoi(owners[2]), 1);

    // The static plinth 10^12 out: its position is exact, so the page must draw it there (a double holds
    // 1e12 to 1.2e-4) and on screen after "go to body".
    const std::string shot = std::string(LPSS_BINARY_DIR) + "/lpss-view-far.png";
    const std::string far =
        check_page("--url " + url + " --screenshot " + shot +
                       " --goto 100 --expect-at 1000000000000.375,2.5,-3.25 --tolerance 1e-3 "
                       "--min-frames 10 --timeout-s 90",
                   dir + "/far.json", code);
    std::printf("far: %s", far.c_str());
    ASSERT_EQ(code, 0) << far;
    const std::vector<double> drawn = numbers_of(far, "drawnGlobal");
    ASSERT_EQ(drawn.size(), 3u) << far;
    EXPECT_NEAR(drawn[0], 1000000000000.375, 1e-3);
    EXPECT_NEAR(drawn[1], 2.5, 1e-3);
    EXPECT_NEAR(drawn[2], -3.25, 1e-3);
    EXPECT_NE(far.find("\"visible\":true"), std::string::npos) << far;
    // Drawn around a floating origin near the camera, not in raw global coordinates.
    const std::vector<double> origin = numbers_of(far, "origin");
    ASSERT_EQ(origin.size(), 3u) << far;
    EXPECT_LT(std::abs(origin[0] - 1000000000000.375), 1e4) << "the page's origin did not follow the camera";
    const std::vector<double> screen = numbers_of(far, "screen");
    ASSERT_EQ(screen.size(), 2u) << far;
    EXPECT_NEAR(screen[0], 640.0, 64.0) << "go to body centres it";
    EXPECT_NEAR(screen[1], 400.0, 40.0);
    EXPECT_GT(std::filesystem::file_size(shot), 10000u);
    view->stop();
    cluster.process->stop();
}

}  // namespace
}  // namespace lpss
