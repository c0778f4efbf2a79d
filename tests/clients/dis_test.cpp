// lpss-dis against an implementation no one here wrote: a cluster runs the ECEF convoy scene, lpss-dis puts
// it on a DIS exercise on 127.0.0.1, and npm's open-dis (run by Node) decodes every datagram. The PDUs are
// checked against lpss-sim's run of the same scene: ids, positions to DIS precision, the dead-reckoned
// position at every frame between updates within the threshold, and the heartbeat of bodies at rest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <thread>

#include "cluster_harness.hpp"
#include "dis/dead_reckoning.hpp"
#include "dis/entity_state_pdu.hpp"
#include "dis/geodesy.hpp"
#include "lpss/common/scene.hpp"
#include "node_tools.hpp"

namespace lpss {
namespace {

using testing::read_file;
using testing::run_sim;
using testing::start_cluster;

/// The numbers of a flat JSON array field ("location":[1,2,3]) or a number field ("entity":7) of one of
/// decode_pdus.js's lines; empty if absent.
std::vector<double> field(const std::string& line, const std::string& key) {
    const std::string tag = "\"" + key + "\":";
    const std::size_t at = line.find(tag);
    if (at == std::string::npos) return {};
    std::size_t pos = at + tag.size();
    std::vector<double> out;
    const bool array = line[pos] == '[';
    if (array) ++pos;
    for (;;) {
        char* end = nullptr;
        const double v = std::strtod(line.c_str() + pos, &end);
        if (end == line.c_str() + pos) break;
        out.push_back(v);
        pos = static_cast<std::size_t>(end - line.c_str());
        if (!array || line[pos] != ',') break;
        ++pos;
    }
    return out;
}

std::string text_field(const std::string& line, const std::string& key) {
    const std::string tag = "\"" + key + "\":\"";
    const std::size_t at = line.find(tag);
    if (at == std::string::npos) return {};
    const std::size_t start = at + tag.size();
    return line.substr(start, line.find('"', start) - start);
}

struct Received {
    std::uint64_t frame = 0;
    dis::DeadReckoningState state;
    std::uint8_t algorithm = 0;
    std::uint32_t appearance = 0;
    std::string marking;
};

TEST(Dis, OpenDisDecodesTheGatewaysPdusAndTheirDeadReckoningFollowsTheWorld) {
    if (const std::string missing = testing::node_tool_missing("open-dis"); !missing.empty())
        GTEST_SKIP() << missing;
    constexpr int kDomain = 192;
    constexpr int kFrames = 720;  // 12 s at 60 Hz: two heartbeats of a body at rest, and the convoys meet
    const testing::DomainCleanup cleanup(kDomain);
    const std::string scene_path = std::string(LPSS_SOURCE_DIR) + "/deploy/scenes/ecef_convoy.textproto";
    auto scene = load_scene(scene_path);
    ASSERT_TRUE(scene) << scene.error().message;
    const double dt = scene->settings.dt;
    const std::string copy = testing::workspace_path("ecef_convoy.textproto");
    testing::remove_stale(copy);
    std::filesystem::copy_file(scene_path, copy, std::filesystem::copy_options::overwrite_existing);
    const auto sim = run_sim(copy, kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1u);

    const std::string out = copy + ".pdus.jsonl";
    const std::string err = copy + ".decoder.err";
    // The decoder listens before anything is sent; it stops on its own (--seconds) if the test fails.
    auto decoder = runtime::ChildProcess::start(
        "/bin/sh", {"-c", "exec node " + std::string(LPSS_SOURCE_DIR) +
                              "/tests/dis/decode_pdus.js 39146 --seconds 90 > " + out + " 2> " + err});
    ASSERT_TRUE(decoder);
    for (int n = 0; n < 100 && read_file(err).find("listening") == std::string::npos; ++n)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ASSERT_NE(read_file(err).find("listening"), std::string::npos) << read_file(err);

    // Two clients: lpss-dis, and this test's, which removes a crate mid-run.
    auto cluster = start_cluster(copy, kDomain, 2, kFrames, {"--await-clients", "2"});
    ASSERT_TRUE(cluster.process);
    auto remover = testing::connect(kDomain, "dis-test-remover", std::nullopt, FrameContent::changes);
    ASSERT_TRUE(remover);
    ASSERT_TRUE(remover->wait_for_cluster(std::chrono::seconds(60)));
    const std::string gateway_log = copy + ".lpss-dis.log";
    auto gateway = runtime::ChildProcess::start(
        LPSS_DIS,
        {"--domain", std::to_string(kDomain), "--dis-port", "39146", "--exercise", "7", "--site", "21",
         "--application", "5", "--relative-timestamps", "--frames", std::to_string(kFrames)},
        gateway_log);
    ASSERT_TRUE(gateway);
    constexpr BodyId kRemoved = 219;  // a crate at rest
    std::uint64_t newest = 0;
    for (auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
         newest < 240 && std::chrono::steady_clock::now() < end;) {
        for (const WorldFrame& f : remover->poll(std::chrono::milliseconds(20)))
            newest = f.frame;
    }
    const auto removal = remover->wait_outcome(remover->remove(kRemoved), std::chrono::seconds(10));
    ASSERT_TRUE(removal && removal->applied) << (removal ? removal->reason : "no answer");
    EXPECT_TRUE(gateway->wait(std::chrono::seconds(120))) << read_file(gateway_log);
    EXPECT_EQ(gateway->exit_code(), 0) << read_file(gateway_log);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the last datagrams reach the decoder
    decoder->stop();
    cluster.process->stop();

    // Each PDU's frame is its timestamp (the world's time with --relative-timestamps) over dt.
    const double unit = 3600.0 / 2147483647.0;
    std::map<std::uint16_t, std::vector<Received>> by_entity;
    std::istringstream lines(read_file(out));
    std::size_t pdus = 0;
    for (std::string line; std::getline(lines, line);) {
        ASSERT_EQ(line.find("\"error\""), std::string::npos) << line;
        ++pdus;
        ASSERT_EQ(field(line, "protocolVersion"), std::vector<double>{7}) << line;
        ASSERT_EQ(field(line, "pduType"), std::vector<double>{1}) << line;
        ASSERT_EQ(field(line, "exerciseID"), std::vector<double>{7}) << line;
        ASSERT_EQ(field(line, "site"), std::vector<double>{21}) << line;
        ASSERT_EQ(field(line, "application"), std::vector<double>{5}) << line;
        const std::uint32_t stamp = static_cast<std::uint32_t>(field(line, "timestamp").at(0));
        ASSERT_EQ(stamp & 1u, 0u) << "relative timestamps were asked for";
        Received r;
        r.frame = static_cast<std::uint64_t>(std::llround((stamp >> 1) * unit / dt));
        const auto location = field(line, "location"), velocity = field(line, "velocity");
        const auto angles = field(line, "orientation"), acceleration = field(line, "drLinearAcceleration");
        const auto spin = field(line, "drAngularVelocity");
        ASSERT_EQ(location.size(), 3u);
        r.state.location = Eigen::Vector3d(location[0], location[1], location[2]);
        r.state.velocity = Eigen::Vector3d(velocity.at(0), velocity.at(1), velocity.at(2));
        r.state.acceleration = Eigen::Vector3d(acceleration.at(0), acceleration.at(1), acceleration.at(2));
        r.state.orientation = dis::from_dis_euler_angles({angles.at(0), angles.at(1), angles.at(2)});
        r.state.angular_velocity_body = Eigen::Vector3d(spin.at(0), spin.at(1), spin.at(2));
        r.algorithm = static_cast<std::uint8_t>(field(line, "drAlgorithm").at(0));
        r.appearance = static_cast<std::uint32_t>(field(line, "appearance").at(0));
        r.marking = text_field(line, "marking");
        by_entity[static_cast<std::uint16_t>(field(line, "entity").at(0))].push_back(r);
    }

    // Every body but the ground plane is an entity, numbered by its id, marked with its name.
    std::set<std::uint16_t> expected_entities;
    std::map<std::uint16_t, std::string> names;
    for (const BodyDesc& b : scene->bodies) {
        if (is_plane(b.shape)) continue;
        expected_entities.insert(static_cast<std::uint16_t>(b.id));
        names[static_cast<std::uint16_t>(b.id)] = b.name;
    }
    std::set<std::uint16_t> seen;
    for (const auto& [entity, received] : by_entity)
        seen.insert(entity);
    EXPECT_EQ(seen, expected_entities);

    double worst_at_send = 0.0, worst_reckoned = 0.0, worst_angle = 0.0;
    std::size_t resting = 0;
    // Named, not bound: the lambda below reads the entity, and a C++17 lambda cannot capture a structured
    // binding (clang refuses it).
    for (const auto& entity_pdus : by_entity) {
        const auto entity = entity_pdus.first;
        const auto& received = entity_pdus.second;
        ASSERT_FALSE(received.empty());
        EXPECT_EQ(received.front().marking, names[entity]);
        const bool at_rest = [&] {
            const Eigen::Vector3d start = sim.at(0).at(entity).position.local;
            for (const auto& [f, bodies] : sim) {
                if ((bodies.at(entity).position.local - start).norm() > 0.0) return false;
            }
            return true;
        }();
        // Every entity's last PDU says it is deactivated: the removed crate's at the frame it was removed,
        // the others' at the gateway's last frame (it tells receivers before it stops). None before.
        const bool removed = entity == kRemoved;
        ASSERT_GE(received.size(), 2u) << "entity " << entity;
        EXPECT_EQ(received.back().appearance, dis::kAppearanceDeactivated) << "entity " << entity;
        EXPECT_EQ(received.back().frame, removed ? removal->frame : static_cast<std::uint64_t>(kFrames))
            << "entity " << entity;
        const std::size_t live = received.size() - 1;
        for (std::size_t n = 0; n < received.size(); ++n) {
            const Received& r = received[n];
            EXPECT_EQ(r.algorithm, dis::dead_reckoning_algorithm::kRvw);
            if (n < live) {
                EXPECT_EQ(r.appearance, 0u) << "entity " << entity << " at frame " << r.frame;
            }
            ASSERT_TRUE(sim.count(r.frame)) << "entity " << entity << " stamped at frame " << r.frame;
            const SectorGrid grid(scene->settings.sector_size);
            const testing::SimRow& truth = sim.at(r.frame).at(entity);
            worst_at_send =
                std::max(worst_at_send, (r.state.location - grid.to_global(truth.position)).norm());
            worst_angle = std::max(worst_angle, r.state.orientation.angularDistance(truth.orientation));
            // What a receiver shows at each frame until the next PDU: within the position threshold (1 m)
            // of the world, give or take the cluster's bound of lpss-sim (1e-3).
            const std::uint64_t until = n + 1 < received.size() ? received[n + 1].frame : kFrames + 1;
            for (std::uint64_t f = r.frame; f < until && sim.count(f); ++f) {
                const dis::DeadReckoningState shown =
                    dis::extrapolate(r.state, r.algorithm, static_cast<double>(f - r.frame) * dt);
                const double off = (shown.location - grid.to_global(sim.at(f).at(entity).position)).norm();
                worst_reckoned = std::max(worst_reckoned, off);
                ASSERT_LE(off, 1.0 + 1e-3)
                    << "entity " << entity << " at frame " << f << ", last PDU at " << r.frame;
            }
            if (at_rest && n > 0 && n < live) {
                // The heartbeat: every 5 s (300 frames), not more often.
                EXPECT_EQ(r.frame - received[n - 1].frame, 300u) << "entity " << entity;
            }
        }
        if (at_rest && !removed) {
            ++resting;
            EXPECT_GE(live, 2u) << "entity " << entity << " got no heartbeat in 12 s";
            EXPECT_EQ(received[live - 1].frame + 300 > kFrames, true)
                << "entity " << entity << " missed its last heartbeat";
        }
    }
    EXPECT_GE(resting, 10u) << "the crates should rest";
    EXPECT_LE(worst_at_send, 1e-3);
    EXPECT_LE(worst_angle, 1e-4);
    const double every_frame = static_cast<double>(expected_entities.size()) * kFrames;
    std::printf(
        "%zu PDUs for %zu entities over %d frames (%.1f%% of one per body per frame); worst position at "
        "send %.2g m, worst dead-reckoned position %.3g m, worst orientation %.2g rad; %zu entities at "
        "rest\n",
        pdus, expected_entities.size(), kFrames, 100.0 * static_cast<double>(pdus) / every_frame,
        worst_at_send, worst_reckoned, worst_angle, resting);
    EXPECT_LT(static_cast<double>(pdus), 0.25 * every_frame);
}

}  // namespace
}  // namespace lpss
