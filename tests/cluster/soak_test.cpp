// The soak (label long: not in the default suite). A few thousand bodies for LPSS_SOAK_MINUTES (30 by
// default): resting boxes, and balls bouncing between two walls across sector and worker borders for ever.
// Every few minutes a worker is killed outright and started again under its id; halfway, the coordinator
// is killed and its standby takes over. A client checks every frame it sees: every body once. The
// resident memory of every process is read every 30 s (a twelfth of a shorter run): each that lives through
// the run must end within 10% (or 8 MiB) of what it held 60% of the way in (after the coordinator's death,
// so that the standby is measured as the coordinator it became).
//   cd build && LPSS_SOAK_MINUTES=30 ctest -L long -V
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>

#include <cstdlib>
#include <fstream>
#include <set>

#include "cluster_harness.hpp"
#include "lpss/common/process_memory.hpp"
#include "scenes.hpp"

namespace lpss {
namespace {

using testing::connect;
using testing::processes_of;
using testing::start_cluster;
using testing::worker_process;
using testing::write_scene;
using Clock = std::chrono::steady_clock;

constexpr double kL = 32.0;
/// The pen the balls bounce in: x in (-100, 100), y in (-57.5, 62.5), z in (-55, 65), closed on all six
/// sides by static tiles 4 thick (a ball would need 300 units/s to pass one in a step; all the balls' energy
/// in one gives 283). The tiles' seams lie halfway between the balls' lanes (y every 5, z every 10), so that
/// the balls fly straight for long; they still drift sideways by float noise at each bounce, meet, and
/// scatter. With walls on two sides only, 145 of 200 balls had flown off by frame 6,000 (in plain Bullet
/// too), into ever new sectors: the world, and every process's memory with it, grew for as long as it ran.
constexpr double kPenLow[3] = {-100.0, -57.5, -55.0};
constexpr double kPenSide = 200.0, kPenHeight = 120.0;  ///< along x; along y and z
constexpr double kWallHalfThickness = 2.0, kTileHalf = 10.0;
constexpr int kTilesAlongX = 10, kTilesAcross = 6;
constexpr BodyId kWallTiles = 2 * (kTilesAcross * kTilesAcross + 2 * kTilesAlongX * kTilesAcross);
constexpr BodyId kBalls = 200;  ///< ids kWallTiles + 1 to kWallTiles + kBalls

bool in_pen(const Eigen::Vector3d& at) {
    return at.x() > kPenLow[0] && at.x() < kPenLow[0] + kPenSide && at.y() > kPenLow[1] &&
           at.y() < kPenLow[1] + kPenHeight && at.z() > kPenLow[2] && at.z() < kPenLow[2] + kPenHeight;
}

/// 2,000 boxes at rest far from a pen where 200 balls bounce for ever (no gravity, no friction, restitution
/// 1), through the borders of the sectors and workers they cross: 2,512 bodies with the pen's tiles.
Scene soak_scene() {
    Scene scene;
    scene.settings.sector_size = kL;
    scene.settings.gravity = Eigen::Vector3d::Zero();
    scene.settings.sleeping = true;
    BodyId id = 1;
    // Each wall in tiles no larger than a sector (a body larger than a sector is refused). `across` and
    // `along` count tiles from the pen's low corner; `normal` is the axis the wall faces.
    auto tile = [&](int normal, bool high, int a, int b) {
        const int u = (normal + 1) % 3, v = (normal + 2) % 3;
        Eigen::Vector3d half = Eigen::Vector3d::Constant(kTileHalf), at;
        half[normal] = kWallHalfThickness;
        const double extent[3] = {kPenSide, kPenHeight, kPenHeight};
        at[normal] = high ? kPenLow[normal] + extent[normal] + kWallHalfThickness
                          : kPenLow[normal] - kWallHalfThickness;
        at[u] = kPenLow[u] + kTileHalf * (2 * a + 1);
        at[v] = kPenLow[v] + kTileHalf * (2 * b + 1);
        BodyDesc body = scenes::box_body(id++, half, 0.0, at);
        body.material = Material{0, 1};
        scene.bodies.push_back(body);
    };
    for (int normal = 0; normal < 3; ++normal) {
        const int along_u = normal == 2 ? kTilesAlongX : kTilesAcross;  // u is x for the z walls
        const int along_v = normal == 1 ? kTilesAlongX : kTilesAcross;  // v is x for the y walls
        for (bool high : {false, true}) {
            for (int a = 0; a < along_u; ++a) {
                for (int b = 0; b < along_v; ++b)
                    tile(normal, high, a, b);
            }
        }
    }
    for (int n = 0; n < static_cast<int>(kBalls); ++n) {
        const double y = -50.0 + 5.0 * (n % 21), z = -50.0 + 10.0 * (n / 21);
        BodyDesc ball = scenes::sphere_body(id++, 0.5, 1.0, Eigen::Vector3d(-90.0 + 0.9 * n, y, z));
        ball.linear_velocity = Eigen::Vector3d((n % 2 ? -1 : 1) * (10.0 + n % 20), 0, 0);
        ball.material = Material{0, 1};
        scene.bodies.push_back(ball);
    }
    for (int n = 0; n < 2000; ++n) {
        BodyDesc box = scenes::box_body(id++, Eigen::Vector3d::Constant(0.5), 1.0,
                                        Eigen::Vector3d(3.0 * (n % 50), 3.0 * (n / 50), 400.0));
        box.asleep = true;
        scene.bodies.push_back(box);
    }
    return scene;
}

TEST(Soak, KilledWorkersAndAKilledCoordinatorLoseNoBodyAndNoProcessGrows) {
    const char* minutes_env = std::getenv("LPSS_SOAK_MINUTES");
    const double minutes = minutes_env ? std::atof(minutes_env) : 30.0;
    ASSERT_GT(minutes, 0.0);
    const auto length =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(60.0 * minutes));
    const int domain = 160;
    const testing::DomainCleanup cleanup(domain);
    const Scene scene = soak_scene();
    const std::string path = write_scene(scene, "soak");
    auto client = connect(domain, "soak");
    ASSERT_TRUE(client);
    auto cluster = start_cluster(path, domain, 3, 0, {"--rebalance-every", "600"});
    ASSERT_TRUE(cluster.process);

    // The workers this test started again, by id (one taken as gone, a lease missed on a loaded machine,
    // joins again by itself).
    std::map<std::uint32_t, runtime::ChildProcess> restarted;
    std::size_t starts = 0;
    auto start_worker = [&](std::uint32_t w) {
        auto again = runtime::ChildProcess::start(
            LPSS_WORKER, {"--domain", std::to_string(domain), "--id", std::to_string(w), "--threads", "1"},
            cluster.log_dir + "/soak-worker-" + std::to_string(w) + "-" + std::to_string(++starts) + ".log");
        if (!again) return false;
        restarted.erase(w);
        restarted.emplace(w, std::move(*again));
        return true;
    };
    std::size_t frames_seen = 0, wrong = 0, kills = 0, skips_told = 0, escaped = 0;
    std::string first_escape;
    double longest_wait = 0.0;
    std::uint64_t last_frame = 0;
    std::string first_wrong;
    // pid -> (name, samples of resident MiB taken at seconds since the start)
    std::map<int, std::pair<std::string, std::vector<std::pair<double, double>>>> memory;
    const auto start = Clock::now();
    auto last_seen = start, last_sample = start;
    const auto kill_every = length / 10;
    // Every 30 s, or a twelfth of a short run: memory is compared 60% of the way in and at the end.
    const auto sample_every = std::min<Clock::duration>(std::chrono::seconds(30), length / 12);
    auto next_kill = start + kill_every;
    bool coordinator_killed = false;
    std::vector<std::pair<std::uint32_t, Clock::time_point>> restart_due;  // killed workers, when to start
    std::uint32_t next_victim = 1;
    while (Clock::now() - start < length) {
        ASSERT_TRUE(cluster.process->running()) << "logs: " << cluster.log_dir;
        for (const WorldFrame& f : client->poll(std::chrono::milliseconds(20))) {
            const auto now = Clock::now();
            if (frames_seen > 0)
                longest_wait = std::max(longest_wait, std::chrono::duration<double>(now - last_seen).count());
            last_seen = now;
            ++frames_seen;
            // The client skips to the next frame it can show whole: say where, for the first few skips.
            if (frames_seen > 1 && f.frame > last_frame + 1 && skips_told < 20) {
                ++skips_told;
                std::printf("%.1f s: the client skipped from frame %llu to %llu\n",
                            std::chrono::duration<double>(now - start).count(),
                            static_cast<unsigned long long>(last_frame),
                            static_cast<unsigned long long>(f.frame));
            }
            last_frame = f.frame;
            std::map<BodyId, const BodyView*> ids;
            std::string twice;
            for (const BodyView& b : f.bodies) {
                const auto [it, fresh] = ids.emplace(b.id, &b);
                if (!fresh && twice.size() < 400)
                    twice +=
                        fmt::format(" body {} in sector ({},{},{}) of worker {} and ({},{},{}) of worker {};",
                                    b.id, it->second->position.sector.i, it->second->position.sector.j,
                                    it->second->position.sector.k, it->second->worker, b.position.sector.i,
                                    b.position.sector.j, b.position.sector.k, b.worker);
            }
            // The balls stay in their pen: one outside it went through a wall or over it (and the world
            // then grows by the sectors it flies into).
            for (const BodyView& b : f.bodies) {
                if (b.id > kWallTiles && b.id <= kWallTiles + kBalls && !in_pen(b.global) && escaped++ == 0)
                    first_escape = fmt::format("frame {}: ball {} at ({:.1f}, {:.1f}, {:.1f})", f.frame, b.id,
                                               b.global.x(), b.global.y(), b.global.z());
            }
            if (ids.size() != scene.bodies.size() || f.bodies.size() != scene.bodies.size()) {
                if (wrong++ == 0)
                    first_wrong = "frame " + std::to_string(f.frame) + ": " +
                                  std::to_string(f.bodies.size()) + " bodies, " + std::to_string(ids.size()) +
                                  " distinct;" + twice;
            }
        }
        const auto now = Clock::now();
        const double t = std::chrono::duration<double>(now - start).count();
        if (now - last_sample > sample_every) {
            last_sample = now;
            for (const auto& [pid, name] : processes_of(domain)) {
                if (auto use = memory_use(pid)) {
                    auto& series = memory[pid];
                    series.first = name;
                    series.second.emplace_back(t, static_cast<double>(use->resident_bytes) / 1048576.0);
                }
            }
        }
        if (now >= next_kill && last_frame > 0) {
            next_kill += kill_every;
            if (!coordinator_killed && now - start >= length / 2) {
                coordinator_killed = true;
                for (const auto& [pid, name] : processes_of(domain)) {
                    if (name == "coordinator") ::kill(pid, SIGKILL);
                }
                std::printf("%.0f s: the coordinator killed\n", t);
            } else {
                const std::uint32_t w = next_victim;
                next_victim = next_victim % 3 + 1;
                const int killed =
                    std::system(("pkill -KILL -f " + worker_process(domain, static_cast<int>(w))).c_str());
                ++kills;
                // Started again 3 s later; the client is read meanwhile (a test that slept here measured its
                // own sleep as the client's wait for a frame).
                restart_due.emplace_back(w, now + std::chrono::seconds(3));
                std::printf("%.0f s: worker %u %s\n", t, w, killed == 0 ? "killed" : "not there");
            }
            std::fflush(stdout);
        }
        for (auto it = restart_due.begin(); it != restart_due.end();) {
            if (now < it->second) {
                ++it;
                continue;
            }
            ASSERT_TRUE(start_worker(it->first));
            std::printf("%.0f s: worker %u started again\n", t, it->first);
            it = restart_due.erase(it);
        }
    }
    // A client that stopped seeing frames before the end waited that long too.
    if (frames_seen > 0)
        longest_wait =
            std::max(longest_wait, std::chrono::duration<double>(Clock::now() - last_seen).count());
    EXPECT_EQ(cluster.process->stop(std::chrono::seconds(30)), 0) << "logs: " << cluster.log_dir;
    for (auto& [w, process] : restarted) {
        if (!process.wait(std::chrono::seconds(10))) process.stop();
    }
    // Workers taken as gone (a lease missed on a loaded machine) that joined again by themselves.
    std::size_t rejoins = 0;
    for (const auto& entry : std::filesystem::directory_iterator(cluster.log_dir)) {
        const std::string text = testing::read_file(entry.path().string());
        for (std::size_t at = text.find("joins again as a fresh worker"); at != std::string::npos;
             at = text.find("joins again as a fresh worker", at + 1))
            ++rejoins;
    }

    std::printf(
        "%.1f min: %zu frames seen (the last %llu), %zu with a body missing or twice%s%s; %zu balls seen out "
        "of their pen%s%s; the longest wait for a frame %.2f s; %zu workers killed and started again, %zu "
        "taken as gone that joined again, the coordinator %s\n",
        minutes, frames_seen, static_cast<unsigned long long>(last_frame), wrong, wrong ? ", first: " : "",
        first_wrong.c_str(), escaped, escaped ? ", first: " : "", first_escape.c_str(), longest_wait, kills,
        rejoins, coordinator_killed ? "killed once" : "not killed");
    EXPECT_EQ(wrong, 0u) << first_wrong;
    EXPECT_EQ(escaped, 0u) << "balls out of their pen, first: " << first_escape;
    EXPECT_GT(frames_seen, 0u);
    EXPECT_TRUE(coordinator_killed);
    EXPECT_LT(longest_wait, 5.0) << "a pause beyond what a fault costs";
    // Every process's resident memory as sampled, for a reader looking for when a process grew.
    for (const auto& [pid, series] : memory) {
        std::string line;
        for (const auto& [t, mib] : series.second)
            line += fmt::format(" {:.0f}:{:.1f}", t, mib);
        std::printf("  %s (pid %d), seconds:MiB%s\n", series.first.c_str(), pid, line.c_str());
    }
    // Resident memory of each process that lived through most of the run: 60% of the way in, and last.
    std::size_t compared = 0;
    for (const auto& [pid, series] : memory) {
        const auto& [name, samples] = series;
        if (samples.size() < 4 || samples.front().first > 0.2 * 60.0 * minutes) continue;
        const auto settled = std::find_if(samples.begin(), samples.end(),
                                          [&](const auto& s) { return s.first >= 0.6 * 60.0 * minutes; });
        if (settled == samples.end() || samples.back().first < 0.9 * 60.0 * minutes) continue;
        ++compared;
        std::printf("  %s (pid %d): %.0f MiB at %.0f s, %.0f MiB at %.0f s\n", name.c_str(), pid,
                    settled->second, settled->first, samples.back().second, samples.back().first);
        EXPECT_LE(samples.back().second, std::max(settled->second * 1.10, settled->second + 8.0))
            << name << " grew";
    }
    EXPECT_GE(compared, 1u) << "a process lived through the run";
}

}  // namespace
}  // namespace lpss
