// The distributed server as users run it: lpss-cluster with 1, 2 and 3 workers against lpss-sim, bodies
// crossing worker borders for thousands of frames, late and regional clients, commands from two clients.
// Each test uses a DDS domain of its own.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "cluster_harness.hpp"
#include "fake_hosts.hpp"
#include "leak_counter.hpp"
#include "lpss/common/border_reach.hpp"
#include "lpss/common/process_memory.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/sector_chain.hpp"
#include "lpss_dds/sector_mirror.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#include "lpss_dds/topics.hpp"
#include "lpss_dds/whole_sector_asks.hpp"
#include "scenes.hpp"

namespace lpss {
namespace {

using testing::collect;
using testing::collect_into;
using testing::connect;
using testing::FrameRecorder;
using testing::LeakCounter;
using testing::read_file;
using testing::run_sim;
using testing::SimFrames;
using testing::SimRow;
using testing::start_cluster;
using testing::worker_process;
using testing::write_scene;
using Clock = std::chrono::steady_clock;

constexpr double kL = 128.0;
const Eigen::IOFormat kFull(17);

/// Bodies crossing the borders between sectors 0, 1 and 2 along x in both directions, and two spheres
/// colliding exactly on the border between sectors 0 and 1. With block size 1 and 2 or 3 workers, those
/// sectors belong to different workers.
Scene crossing_scene() {
    Scene scene = scenes::sphere_pair(Eigen::Vector3d(0.5 * kL, 0, 0), kL);
    BodyDesc east = scenes::sphere_body(3, 0.5, 1.0, Eigen::Vector3d(40, 5, 0));
    east.linear_velocity = Eigen::Vector3d(30, 0, 0);
    BodyDesc west = scenes::sphere_body(4, 0.5, 1.0, Eigen::Vector3d(2.2 * kL, -5, 0));
    west.linear_velocity = Eigen::Vector3d(-35, 0, 0.5);
    BodyDesc box = scenes::box_body(5, Eigen::Vector3d(0.5, 0.5, 0.5), 2.0, Eigen::Vector3d(1.4 * kL, 3, 2));
    box.linear_velocity = Eigen::Vector3d(-25, 0, 0);
    box.angular_velocity = Eigen::Vector3d(0, 1, 0.3);
    scene.bodies.push_back(east);
    scene.bodies.push_back(west);
    scene.bodies.push_back(box);
    BodyDesc wall = scenes::box_body(6, Eigen::Vector3d(0.5, 20, 20), 0.0, Eigen::Vector3d(2.9 * kL, 0, 0));
    scene.bodies.push_back(wall);
    return scene;
}

std::string against_sim(const std::map<std::uint64_t, WorldFrame>& frames, const SimFrames& sim,
                        double& worst) {
    return testing::against_sim(frames, sim, worst, kL);
}

/// A scene in a file of the test's own and lpss-sim's run of it: what the cluster's frames are compared with.
struct SimulatedScene {
    std::string path;
    SimFrames sim;
};

/// Writes `scene` under `name` and runs lpss-sim on it for `frames` frames (every `every`-th kept, as
/// run_sim keeps them): the two go together in every test that compares the cluster with lpss-sim.
SimulatedScene simulate_scene(const Scene& scene, const std::string& name, std::uint64_t frames,
                              int every = 1) {
    SimulatedScene out;
    out.path = write_scene(scene, name);
    out.sim = run_sim(out.path, static_cast<int>(frames), every);
    return out;
}

/// Sends `signal` (KILL, STOP, CONT) to the processes that a pkill -f `pattern` matches, as a crash or a
/// stalled machine would; returns pkill's status (0: it matched one at least).
int pkill(const std::string& signal, const std::string& pattern) {
    return std::system(("pkill -" + signal + " -f " + pattern).c_str());
}

/// Stops lpss-cluster and expects it to stop cleanly, naming its logs if not: the end of most tests.
void expect_stopped_cleanly(testing::ClusterRun& cluster) {
    EXPECT_EQ(cluster.process->stop(std::chrono::seconds(20)), 0) << "logs: " << cluster.log_dir;
}

/// Waits for lpss-cluster to end on its own (its frames run out) and expects it to have ended cleanly: the
/// faults a test makes must not end the world.
void expect_ended_cleanly(testing::ClusterRun& cluster) {
    EXPECT_TRUE(cluster.process->wait(std::chrono::seconds(30)));
    EXPECT_EQ(cluster.process->exit_code().value_or(-1), 0) << "logs: " << cluster.log_dir;
}

/// Expects `words` in the cluster's log `log` (a file of its log folder), showing the whole log if not.
void expect_logged(const testing::ClusterRun& cluster, const std::string& log, const std::string& words) {
    const std::string text = read_file(cluster.log_dir + "/" + log);
    EXPECT_NE(text.find(words), std::string::npos) << text;
}

/// Starts lpss-worker `id` on `domain` outside lpss-cluster, as an operator restarts a worker or adds one;
/// its output in `log`.
std::optional<runtime::ChildProcess> start_worker(int domain, int id, const std::string& log) {
    return runtime::ChildProcess::start(
        LPSS_WORKER, {"--domain", std::to_string(domain), "--id", std::to_string(id)}, log);
}

void compare_with_sim(int workers, int domain) {
    const testing::DomainCleanup cleanup(domain);
    const Scene scene = crossing_scene();
    constexpr int kFrames = 240;
    const auto [path, sim] = simulate_scene(scene, "crossing" + std::to_string(workers), kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1u);
    auto client = connect(domain, "compare");
    // Frame 1 waits for this client: it compares every frame, the border collision and the handoffs the
    // scene was built for included (a client that matched late used to start as late as frame 170).
    auto cluster =
        start_cluster(path, domain, workers, kFrames, {"--block-size", "1", "--await-clients", "1"});
    ASSERT_TRUE(cluster.process);
    auto frames = collect(*client, kFrames);
    expect_stopped_cleanly(cluster);
    ASSERT_FALSE(frames.empty());
    EXPECT_EQ(frames.begin()->first, 1u) << "the first frame the client saw";
    EXPECT_EQ(frames.size(), static_cast<std::size_t>(kFrames)) << "every frame, none missing";
    double worst = 0.0;
    std::size_t bodies_compared = 0;
    const SectorGrid grid(kL);
    for (const auto& [f, frame] : frames) {
        const auto& expected = sim.at(f);
        ASSERT_EQ(frame.bodies.size(), expected.size()) << "frame " << f;
        for (const BodyView& b : frame.bodies) {
            const SimRow& want = expected.at(b.id);
            // The wire carries offsets as floats: the engine's double offsets, rounded.
            SectorPosition want_f = want.position;
            for (int a = 0; a < 3; ++a)
                want_f.local[a] = static_cast<double>(static_cast<float>(want.position.local[a]));
            if (workers == 1) {
                // One worker runs exactly the engine lpss-sim runs: equal to the last bit of the float sent.
                EXPECT_EQ(b.position.sector, want_f.sector) << "frame " << f << " body " << b.id;
                EXPECT_EQ((b.position.local - want_f.local).cwiseAbs().maxCoeff(), 0.0)
                    << "frame " << f << " body " << b.id << " local "
                    << b.position.local.transpose().format(kFull) << " lpss-sim "
                    << want.position.local.transpose().format(kFull);
            }
            worst = std::max(worst, (grid.to_global(b.position) - grid.to_global(want.position)).norm());
            ++bodies_compared;
        }
    }
    // Several workers: bodies near a worker border are cloned from ghosts that carry float offsets (the
    // wire), where one process clones from double positions: 4e-6 at most per axis for L = 128, grown by
    // the collision response (about 25x, docs/protocol.md). 1e-3 bounds it with margin.
    EXPECT_LE(worst, workers == 1 ? 1e-5 : 1e-3) << workers << " worker(s)";
    ::testing::Test::RecordProperty("worst_difference", std::to_string(worst));
    std::printf(
        "%d worker(s): %zu body states in %zu frames from frame %llu, largest difference from lpss-sim "
        "%.3g\n",
        workers, bodies_compared, frames.size(), static_cast<unsigned long long>(frames.begin()->first),
        worst);
}

TEST(Cluster, OneWorkerMatchesLpssSimBitForBit) { compare_with_sim(1, 120); }

/// What an answer to a flooding client's command says: applied, refused for the rate (as the coordinator
/// words it for client `name` at `rate` a second), lost on the way, or something else.
enum class FloodAnswer { applied, limited, lost, other };
FloodAnswer flood_answer(bool applied, const std::string& reason, const std::string& name, int rate) {
    if (applied) return FloodAnswer::applied;
    const std::string over_rate = "client '" + name + "' sends more than " + std::to_string(rate) +
                                  " commands a second: refused (rate limit)";
    if (reason.find(over_rate) != std::string::npos) return FloodAnswer::limited;
    if (reason.find(" were lost on the way (more than ") != std::string::npos) return FloodAnswer::lost;
    return FloodAnswer::other;
}

/// What a flooding client read of the answers to its requests [first, last], by kind; each unexpected
/// reason is a test failure.
struct FloodAnswers {
    std::size_t applied = 0, limited = 0, lost = 0, other_reason = 0;
};
FloodAnswers read_flood_answers(Client& flooder, const std::string& name, std::uint64_t first,
                                std::uint64_t last, int rate) {
    FloodAnswers got;
    for (std::uint64_t r = first; r <= last; ++r) {
        auto o = flooder.outcome(r);
        if (!o) continue;
        switch (flood_answer(o->applied, o->reason, name, rate)) {
            case FloodAnswer::applied:
                ++got.applied;
                break;
            case FloodAnswer::limited:
                ++got.limited;
                break;
            case FloodAnswer::lost:
                ++got.lost;
                break;
            case FloodAnswer::other:
                ++got.other_reason;
                ADD_FAILURE() << "request " << r << ": " << o->reason;
                break;
        }
    }
    return got;
}

TEST(Cluster, AClientFloodingCommandsIsRateLimitedAndTheOthersGoOn) {
    // One client writes 3,000 commands as fast as it can to a coordinator that takes 200 a second from
    // each client: past the burst, its commands are refused with the reason (over the rate, or lost on the
    // way: more in flight than its instance keeps); frames keep coming at the scene's rate, and another
    // client's command is applied within a few frames.
    const int domain = 145;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(crossing_scene(), "flood");
    auto flooder = connect(domain, "flooder");
    auto other = connect(domain, "other");
    ASSERT_TRUE(flooder && other);
    auto cluster = start_cluster(path, domain, 2, 600, {"--await-clients", "1", "--command-rate", "200"});
    ASSERT_TRUE(cluster.process);
    auto frames = collect(*other, 30, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    std::uint64_t first = 0, last = 0;
    const auto flood_start = Clock::now();  // the bucket refills from the first command on
    for (int n = 0; n < 3000; ++n) {
        last = flooder->set_velocity(1, {1.0 + 1e-4 * n, 0, 0}, {0, 0, 0});
        if (n == 0) first = last;
    }
    const auto sent = Clock::now();
    const std::uint64_t asked = other->set_velocity(2, {0, 0, 0}, {0, 0, 0});
    auto mine = other->wait_outcome(asked, std::chrono::seconds(10));
    const double answered = std::chrono::duration<double>(Clock::now() - sent).count();
    ASSERT_TRUE(mine);
    EXPECT_TRUE(mine->applied) << mine->reason;
    // The flood's answers: DDS may deliver a burst over seconds (shared-memory ports overflow and are
    // repaired), so the bucket refills meanwhile; and a client keeps the last 256 answers it has not read.
    // What must hold: refusals that name the limit, and no more applied than the limit lets through.
    flooder->wait_outcome(last, std::chrono::seconds(5));
    const auto [applied, limited, lost, other_reason] =
        read_flood_answers(*flooder, "flooder", first, last, 200);
    const double elapsed = std::chrono::duration<double>(Clock::now() - flood_start).count();
    std::printf(
        "flood answers read: %zu applied, %zu refused for the rate, %zu lost on the way, %zu otherwise, over "
        "%.1f s\n",
        applied, limited, lost, other_reason, elapsed);
    EXPECT_GE(limited, 1u);
    EXPECT_EQ(other_reason, 0u);
    EXPECT_LE(static_cast<double>(applied), 200.0 + 200.0 * elapsed + 1.0);
    // Frames go on at the scene's rate while the flood is refused.
    double longest = 0.0;
    auto previous = Clock::now();
    const std::uint64_t from = other->latest() ? other->latest()->frame : 0;
    while (true) {
        auto got = other->poll(std::chrono::milliseconds(5));
        if (got.empty()) {
            if (std::chrono::duration<double>(Clock::now() - previous).count() > 5.0) break;
            continue;
        }
        longest = std::max(longest, std::chrono::duration<double>(Clock::now() - previous).count());
        previous = Clock::now();
        if (got.back().frame >= from + 120) break;
    }
    std::printf(
        "3000 commands from one client: the other's command answered in %.3f s (frame %llu), the "
        "longest wait for a frame after %.3f s\n",
        answered, static_cast<unsigned long long>(mine->frame), longest);
    EXPECT_LT(longest, 0.25);
    expect_stopped_cleanly(cluster);
}

TEST(Cluster, AFloodOfCommandsAtAHundredThousandASecondIsAnsweredAndHoldsNoMemory) {
    // A peer on the domain writes commands under one client's name, paced at 10^5 a second for 3 s (issue
    // 11's flood), to a coordinator that takes 1,000 a second from each client (the default; 100 under
    // AddressSanitizer). It writes from two DDS writers in Fast DDS's asynchronous publish mode, whose thread
    // packs many commands into one datagram: lpss::Client writes each command synchronously, one datagram to
    // each coordinator, and reached only 10,000-19,000 a second here, so a flood of 10^5 is what a peer, not
    // the client library, can send. Meanwhile a client sends a command every 100 ms and waits for its answer.
    // What must hold: every command of that client is applied within 2 s; frames never wait a second; every
    // answer to the flood names the rate limit or commands lost on the way, no more are applied than the
    // limit lets through, and the coordinators do not grow with the commands sent (the standby kept the
    // commands of runs refused at once beyond their newest 4,096, until StandingCommands looked runs up by
    // range). Before the commands reader had a port of its own, a flood of 10,000 a second filled the
    // coordinators' one UDP port and frames stalled 1.5-4.2 s.
    const int domain = 161;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(crossing_scene(), "hundred_thousand");
    auto other = connect(domain, "other");
    ASSERT_TRUE(other);
    // The peer stands for a process on another machine: its threads (the flood's and those Fast DDS starts
    // for its participant, which inherit the priority of the thread that makes it) run at the lowest CPU
    // priority, so that what is measured is the flood arriving at the coordinator's socket, not a local
    // process taking the cluster's CPU (which no defence on the wire can answer). At equal priority on a CI
    // runner (held to a CPU quota, it seems), the whole cluster ran at 17 frames a second and an answer took
    // 4.9 s.
    auto lowest_priority = [] { ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), 19); };
    Expected<std::unique_ptr<dds::Participant>> peer = Error{"not made"};
    std::thread([&] {
        lowest_priority();
        peer = dds::Participant::create(domain, "", "a-peer-flooding-commands");
    }).join();
    ASSERT_TRUE(peer.ok());
    dds::fdds::DataWriterQos flood_qos = dds::writer_qos(dds::kCommandDelivery);
    flood_qos.publish_mode().kind = dds::fdds::ASYNCHRONOUS_PUBLISH_MODE;
    // Two writers, each in a thread of its own: one writer's writes reached 62,000-72,000 a second here.
    std::array<std::unique_ptr<dds::Writer<wire::Command>>, 2> flood_out;
    std::thread([&] {
        lowest_priority();  // the asynchronous writers' thread starts with the first of them
        for (auto& out : flood_out)
            out = std::make_unique<dds::Writer<wire::Command>>(
                **peer, (*peer)->topic<wire::CommandPubSubType>(dds::kCommands), flood_qos);
    }).join();
    dds::Inbox answers_inbox;
    dds::Reader<wire::CommandResult> answers(
        **peer, (*peer)->topic<wire::CommandResultPubSubType>(dds::kCommandResults),
        dds::reader_qos(dds::kResultDelivery), &answers_inbox);
    ASSERT_TRUE(flood_out[0]->ok() && flood_out[1]->ok() && answers.ok());
#if defined(__SANITIZE_ADDRESS__)
    // Under AddressSanitizer the peer writes a few thousand a second and the coordinator receives fewer than
    // 1,000 (seen: 2,837 in 3.2 s beside another test): a limit of 100 a second keeps the flood over it.
    const int rate = 100;
#else
    const int rate = 1000;  // the default
#endif
    auto cluster = start_cluster(path, domain, 2, 100000,
                                 {"--await-clients", "1", "--command-rate", std::to_string(rate)});
    ASSERT_TRUE(cluster.process);
    ASSERT_FALSE(collect(*other, 30, std::chrono::seconds(60)).empty());
    auto coordinators_mib = [&] {
        std::map<std::string, double> mib;
        for (const auto& [pid, name] : testing::processes_of(domain)) {
            if (name.rfind("worker", 0) == 0) continue;
            if (auto use = memory_use(pid)) mib[name] = double(use->resident_bytes) / (1024.0 * 1024.0);
        }
        return mib;
    };
    const auto mib_before = coordinators_mib();
    ASSERT_EQ(mib_before.size(), 2u) << "the coordinator and its standby";

    // The answers to the flood, each standing for a run of requests (first_request to request).
    std::atomic<bool> flooding{true}, answering{true};
    std::atomic<std::uint64_t> requests{0}, written{0}, applied{0}, limited{0}, lost{0}, other_reason{0};
    std::string first_other_reason;
    std::thread answer_reader([&] {
        while (answering.load()) {
            answers_inbox.wait(std::chrono::milliseconds(10));
            answers.take_all([&](const wire::CommandResult& r, const dds::fdds::SampleInfo& info) {
                if (!info.valid_data || r.client() != "flooder") return;
                const std::uint64_t run = r.first_request() != 0 ? r.request() - r.first_request() + 1 : 1;
                switch (flood_answer(r.applied(), r.reason(), "flooder", rate)) {
                    case FloodAnswer::applied:
                        applied += run;
                        break;
                    case FloodAnswer::limited:
                        limited += run;
                        break;
                    case FloodAnswer::lost:
                        lost += run;
                        break;
                    case FloodAnswer::other:
                        if (other_reason++ == 0) first_other_reason = r.reason();
                        break;
                }
            });
        }
    });
    auto flood = [&](dds::Writer<wire::Command>& out) {
        // Paced at 5 x 10^4 a second: 500 commands every 10 ms (fewer if the writes take longer). The
        // writers share the client's request numbers, so that the coordinator reads them about in order:
        // not quite, and it answers as lost the gaps it sees that a number read later fills (a pattern a
        // hostile peer may send anyway; those answers name the loss, and count here as such).
        wire::Command c;
        c.client("flooder");
        c.kind(wire::kCommandSetVelocity);
        c.body(1);
        lowest_priority();
        auto next = Clock::now();
        while (flooding.load()) {
            for (int n = 0; n < 500; ++n) {
                const std::uint64_t request = ++requests;
                c.request(request);
                c.vector1(dds::to_wire(Eigen::Vector3d(1.0 + 1e-6 * double(request), 0, 0)));
                if (out.write(c)) ++written;
            }
            next += std::chrono::milliseconds(10);
            std::this_thread::sleep_until(next);
        }
    };
    std::thread flood_1(flood, std::ref(*flood_out[0])), flood_2(flood, std::ref(*flood_out[1]));
    const auto flood_start = Clock::now();
    double longest_frame_wait = 0.0, slowest_answer = 0.0;
    int asked = 0, applied_in_time = 0;
    auto previous_frame = Clock::now();
    auto poll_frames = [&] {
        if (!other->poll(std::chrono::milliseconds(2)).empty()) {
            longest_frame_wait = std::max(
                longest_frame_wait, std::chrono::duration<double>(Clock::now() - previous_frame).count());
            previous_frame = Clock::now();
        }
    };
    // LPSS_FLOOD_S: a longer flood, to see memory level off (12 s: the standby grew 7.4 MiB, as in 3 s).
    const char* flood_s_env = std::getenv("LPSS_FLOOD_S");
    const auto flood_length = std::chrono::seconds(flood_s_env ? std::atoi(flood_s_env) : 3);
    while (Clock::now() - flood_start < flood_length) {
        const auto t = Clock::now();
        const std::uint64_t r = other->set_velocity(2, {0, 0, 0}, {0, 0, 0});
        ++asked;
        while (!other->outcome(r) && Clock::now() - t < std::chrono::seconds(20))
            poll_frames();
        slowest_answer = std::max(slowest_answer, std::chrono::duration<double>(Clock::now() - t).count());
        if (other->outcome(r) && other->outcome(r)->applied) ++applied_in_time;
        while (Clock::now() - t < std::chrono::milliseconds(100))
            poll_frames();
    }
    flooding = false;
    flood_1.join();
    flood_2.join();
    const double flood_s = std::chrono::duration<double>(Clock::now() - flood_start).count();
    // The last commands are answered once the writer's thread has sent them and the coordinator read them:
    // until the answers stop for a second (those the writer dropped unsent at the end are never answered).
    const auto drain_end = Clock::now() + std::chrono::seconds(10);
    for (auto [answered, since] = std::pair(std::uint64_t{0}, Clock::now());
         Clock::now() - since < std::chrono::seconds(1) && Clock::now() < drain_end;) {
        poll_frames();
        if (const std::uint64_t now_answered = applied + limited + lost; now_answered != answered)
            std::tie(answered, since) = std::pair(now_answered, Clock::now());
    }
    answering = false;
    answer_reader.join();
    const double elapsed = std::chrono::duration<double>(Clock::now() - flood_start).count();
    const auto mib_after = coordinators_mib();
    ASSERT_EQ(mib_after.size(), 2u) << "the coordinator or its standby is gone: logs in " << cluster.log_dir;
    // Two writers' requests interleave: a gap the coordinator saw and answered as lost may fill later, so
    // what it received is what it applied or refused for the rate, and the rest never reached it.
    const double received = double(applied + limited);
    std::printf(
        "the peer wrote %llu commands in %.2f s (%.0f a second); the coordinator received %.0f of them: "
        "%llu applied, %llu refused for the rate, the rest lost on the way; the other client: %d of %d "
        "applied, the slowest answer %.3f s; the longest wait for a frame %.3f s; resident memory before "
        "and after: coordinator %.1f and %.1f MiB, standby %.1f and %.1f MiB\n",
        static_cast<unsigned long long>(written.load()), flood_s, double(written) / flood_s, received,
        static_cast<unsigned long long>(applied.load()), static_cast<unsigned long long>(limited.load()),
        applied_in_time, asked, slowest_answer, longest_frame_wait, mib_before.at("coordinator"),
        mib_after.at("coordinator"), mib_before.at("standby"), mib_after.at("standby"));
    EXPECT_EQ(applied_in_time, asked);
    EXPECT_LT(slowest_answer, 2.0);
    EXPECT_LT(longest_frame_wait, 1.0);
    EXPECT_GE(limited, 1u);
    EXPECT_EQ(other_reason, 0u) << first_other_reason;
    EXPECT_LE(double(applied), rate + rate * elapsed + 1.0);  // until the last answer
#if defined(__SANITIZE_ADDRESS__)
    // AddressSanitizer holds freed memory back (its quarantine): resident memory says nothing here, and
    // LeakSanitizer checks what is kept at the end instead (measured: 137 MiB for 27,000 commands).
    std::printf("resident memory not checked under AddressSanitizer\n");
    std::printf("the flood's rate not checked under AddressSanitizer (it writes 5,600 a second there)\n");
#else
    // A flood, not a trickle: 15 times the rate limit at least. At the lowest priority the peer wrote
    // 37,000-57,000 a second on this machine and 23,000-25,000 under a quota of one CPU (a cgroup's
    // cpu.cfs_quota_us, as a CI runner may have); at equal priority 73,000-99,000; lpss::Client's synchronous
    // writes reach 10,000-19,000.
    EXPECT_GT(double(written) / flood_s, 15.0 * rate);
    // The standby holds each command it read until the coordinator's answer comes, which lags under a flood:
    // up to 22,000 of them at once in a 10 s flood (logged), none 2 s after it; what it grows by is that
    // high-water mark (3-15 MiB in nine runs). StandingCommands' own tests check that answers free them.
    EXPECT_LT(mib_after.at("coordinator") - mib_before.at("coordinator"), 16.0)
        << "a command must not be kept once it is read";
    EXPECT_LT(mib_after.at("standby") - mib_before.at("standby"), 32.0)
        << "a command must not be kept once it is answered";
#endif
    expect_stopped_cleanly(cluster);
}

TEST(Cluster, GarbageSectorSamplesFromAPeerAreRefusedAndChangeNothing) {
    // A peer on the domain (no DDS Security) writes sector samples to every worker while the world runs: a
    // frame far in the future (it would freeze its sector: every later real sample stale), NaN states, a
    // sector key beyond the grid, and well-formed samples of a real sector at the current frame with a body
    // no one has: under the epoch in force (but from a worker that does not own the sector), under an
    // older epoch (as a worker left behind by a newer assignment writes), and under an epoch no coordinator
    // announced (another term's). The world runs as lpss-sim runs it, no foreign body ever shows, and every
    // reader logs the refusals with their reason.
    const int domain = 143;
    const testing::DomainCleanup cleanup(domain);
    const Scene scene = crossing_scene();
    constexpr int kFrames = 240;
    const auto [path, sim] = simulate_scene(scene, "garbage", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1u);
    auto client = connect(domain, "garbage");
    auto peer = dds::Participant::create(domain, "", "a-peer-writing-garbage");
    ASSERT_TRUE(peer.ok());
    // In a partition of its own, as lpss's sector writers (own_partition.hpp): lpss's readers match it.
    dds::Writer<wire::SectorFrame> garbage((*peer)->sector_publisher(),
                                           (*peer)->topic<wire::SectorFramePubSubType>(dds::kSectorFrames),
                                           dds::writer_qos(dds::kSectorFrameDelivery));
    ASSERT_TRUE(garbage.ok());
    dds::Reader<wire::Assignment> assignments(**peer,
                                              (*peer)->topic<wire::AssignmentPubSubType>(dds::kSectorOwners),
                                              dds::reader_qos(dds::kAssignmentDelivery), nullptr);
    std::uint32_t epoch = 0;
    auto cluster = start_cluster(path, domain, 2, kFrames, {"--block-size", "1", "--await-clients", "1"});
    ASSERT_TRUE(cluster.process);
    auto sample = [](const SectorKey& key, std::uint64_t frame, BodyId id, float x) {
        wire::SectorFrame f;
        f.sector(dds::to_wire(key));
        f.recipients({1, 2});
        f.frame(frame);
        f.base(frame);
        f.worker(7);  // no such worker (one claiming a worker's own id is dropped by it, taken as its own)
        f.complete(true);
        BodySnapshot b;
        b.id = id;
        b.position = SectorPosition{key, Eigen::Vector3d(x, 0, 0)};
        f.bodies().push_back(dds::to_wire(b));
        f.kinds().emplace_back();
        f.kinds().back().id(id);
        return f;
    };
    std::map<std::uint64_t, WorldFrame> frames;
    std::uint64_t written = 0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < end && (frames.empty() || frames.rbegin()->first < kFrames)) {
        std::vector<WorldFrame> got = client->poll(std::chrono::milliseconds(10));
        for (WorldFrame& f : got)
            frames[f.frame] = std::move(f);
        if (got.empty() && written > 0) continue;  // a batch a frame
        const std::uint64_t now = frames.empty() ? 1 : frames.rbegin()->first + 1;
        garbage.write(sample({0, 0, 0}, std::uint64_t{1} << 62, 9999, 1.0f));
        wire::SectorFrame nan = sample({1, 0, 0}, now, 9998, 1.0f);
        nan.bodies()[0].position().x(std::nanf(""));
        garbage.write(nan);
        garbage.write(sample({INT64_MAX, 0, 0}, now, 9997, 1.0f));
        written += 3;
        assignments.take_all([&](const wire::Assignment& a, const dds::fdds::SampleInfo& info) {
            if (info.valid_data) epoch = std::max(epoch, a.epoch());
        });
        if (epoch == 0) continue;
        // Well-formed, in the sector the two spheres meet in: taken in, body 9996 would show in frames
        // and collide with them.
        for (std::uint32_t claimed : {epoch, epoch - 1, epoch + 1000}) {
            wire::SectorFrame forged = sample({0, 0, 0}, now, 9996, 2.0f);
            forged.epoch(claimed);
            garbage.write(forged);
            ++written;
        }
    }
    expect_stopped_cleanly(cluster);
    ASSERT_FALSE(frames.empty());
    EXPECT_EQ(frames.rbegin()->first, static_cast<std::uint64_t>(kFrames));
    EXPECT_GE(frames.size(), kFrames * 9u / 10u);
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "");
    std::printf("%llu garbage samples written over %zu frames; largest difference from lpss-sim %.3g\n",
                static_cast<unsigned long long>(written), frames.size(), worst);
    EXPECT_LE(worst, 1e-3);
    for (const char* log : {"worker-1.log", "worker-2.log", "coordinator.log"}) {
        const std::string text = read_file(cluster.log_dir + "/" + log);
        EXPECT_NE(text.find("frame is ahead of the newest started"), std::string::npos) << log << ":\n"
                                                                                        << text;
        EXPECT_NE(text.find("has a state that is not finite"), std::string::npos) << log;
        EXPECT_NE(text.find("sector index beyond 2^62"), std::string::npos) << log;
        EXPECT_NE(text.find("from worker 7: the sector is worker"), std::string::npos) << log;
        EXPECT_NE(text.find("is older than the one in force at its frame"), std::string::npos) << log;
        EXPECT_NE(text.find("never came"), std::string::npos) << log;
    }
}
TEST(Cluster, ASectorSampleWithoutItsBaseIsAskedForWholeByTheCoordinators) {
    // The coordinators' copy of the world is what a gone worker's sectors are restored from: a partial
    // sample whose base they lack (lost on a loaded machine) must be mended as workers and clients mend
    // it, by asking the owner for the sector whole, not dropped and the sector left stale. A peer stands
    // in for the loss: it writes, as the owner of the sector where the spheres meet, partial samples whose
    // base no reader can hold (their own frame). The coordinator and the standby refuse them and ask for
    // that sector whole. The real chain is not broken by them, so the world must run as lpss-sim runs it:
    // a refused sample changes nothing.
    const int domain = 193;
    const testing::DomainCleanup cleanup(domain);
    constexpr int kFrames = 150;
    const auto [path, sim] = simulate_scene(crossing_scene(), "without_base", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1u);
    auto client = connect(domain, "without-base");
    auto peer = dds::Participant::create(domain, "", "a-peer-losing-a-base");
    ASSERT_TRUE(peer.ok());
    dds::Writer<wire::SectorFrame> forged_out((*peer)->sector_publisher(),
                                              (*peer)->topic<wire::SectorFramePubSubType>(dds::kSectorFrames),
                                              dds::writer_qos(dds::kSectorFrameDelivery));
    dds::Reader<wire::Assignment> assignments(**peer,
                                              (*peer)->topic<wire::AssignmentPubSubType>(dds::kSectorOwners),
                                              dds::reader_qos(dds::kAssignmentDelivery), nullptr);
    dds::Reader<wire::SectorRequest> requests(
        **peer, (*peer)->topic<wire::SectorRequestPubSubType>(dds::kSectorRequests),
        dds::reader_qos(dds::kCommandDelivery), nullptr);
    // The frames started: a sample must be newer than what the coordinators hold of its sector, and no
    // further ahead than the frame after the one started, or it is stale or implausible to them.
    dds::Reader<wire::FrameGo> starts(**peer, (*peer)->topic<wire::FrameGoPubSubType>(dds::kFrameGo),
                                      dds::reader_qos(dds::kCoordinatorWords), nullptr);
    ASSERT_TRUE(forged_out.ok() && assignments.ok() && requests.ok() && starts.ok());
    auto cluster = start_cluster(path, domain, 2, kFrames, {"--block-size", "1", "--await-clients", "1"});
    ASSERT_TRUE(cluster.process);
    const SectorKey met{0, 0, 0};
    std::optional<SectorAssignment> in_force;
    std::map<std::uint64_t, WorldFrame> frames;
    std::set<std::string> askers;  ///< readers that asked for `met` whole
    std::uint64_t started = 0;
    std::uint64_t forged_at = 0;  ///< the frame started when the last was forged
    int forged = 0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(90);
    while (std::chrono::steady_clock::now() < end && (frames.empty() || frames.rbegin()->first < kFrames)) {
        std::vector<WorldFrame> got = client->poll(std::chrono::milliseconds(10));
        for (WorldFrame& f : got)
            frames[f.frame] = std::move(f);
        assignments.take_all([&](const wire::Assignment& a, const dds::fdds::SampleInfo& info) {
            if (info.valid_data) in_force = dds::from_wire(a);
        });
        starts.take_all([&](const wire::FrameGo& go, const dds::fdds::SampleInfo& info) {
            if (info.valid_data) started = std::max(started, go.frame());
        });
        requests.take_all([&](const wire::SectorRequest& r, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data) return;
            for (const wire::SectorKey& key : r.sectors())
                if (dds::from_wire(key) == met) askers.insert(r.reader());
        });
        // From a third of the way in, one for each frame started until both coordinators have asked: the
        // owner's own sample of the frame, taken in the same batch after it, mends the sector before the
        // batch's end, and a forged sample that comes after the frame's own is stale: both make no ask.
        if (!in_force || started < kFrames / 3 || started <= forged_at || forged >= 40 ||
            (askers.count("lpss-coordinator-1") && askers.count("lpss-coordinator-2")))
            continue;
        const std::uint64_t now = started + 1;
        forged_at = started;
        wire::SectorFrame f;
        f.sector(dds::to_wire(met));
        f.worker(in_force->owner_of(met));
        f.epoch(in_force->epoch);
        f.frame(now);
        f.base(now);  // a partial sample on a state of the same frame: no reader can hold it
        f.complete(false);
        f.recipients({1, 2});
        forged_out.write(f);
        ++forged;
    }
    expect_stopped_cleanly(cluster);
    ASSERT_GE(forged, 1);
    std::printf("%d sample(s) forged before both coordinators asked\n", forged);
    EXPECT_EQ(askers.count("lpss-coordinator-1"), 1u) << "the coordinator asked for the sector whole";
    EXPECT_EQ(askers.count("lpss-coordinator-2"), 1u) << "so did the standby";
    expect_logged(cluster, "coordinator.log", "sector(s) whole: their samples came without their base");
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "");
    EXPECT_LE(worst, 1e-3);
}
TEST(Cluster, TwoWorkersMatchLpssSim) { compare_with_sim(2, 121); }
TEST(Cluster, ThreeWorkersMatchLpssSim) { compare_with_sim(3, 122); }

/// Reads the wire directly, independently of lpss::Client: for every frame whose marks and samples are
/// all in, each body must sit in exactly one sector. It starts before the cluster, so that it sees every
/// frame from the first, in which every sector is written whole: after that, a sector that no mark lists
/// as written holds what it held. A writer that matched it late (discovery under load) leaves it without a
/// sector's base: it asks for that sector whole, as clients do, and checks the frames from the one it came.
class MembershipCheck {
public:
    explicit MembershipCheck(int domain) {
        auto p = dds::Participant::create(domain, "", "membership-check");
        EXPECT_TRUE(p.ok());
        participant_ = std::move(p).value();
        auto& part = *participant_;
        // Deep histories: this reader checks every frame, and must not lose one to the next while it
        // checks a large world's first state. Sector samples as any reader keeps them (a worker's are all
        // in one instance).
        const dds::Delivery every_frame{true, 256};
        frames_ = std::make_unique<dds::Reader<wire::SectorFrame>>(
            part, part.topic<wire::SectorFramePubSubType>(dds::kSectorFrames),
            dds::reader_qos(dds::kSectorFrameReading), &inbox_);
        marks_ = std::make_unique<dds::Reader<wire::WorkerFrame>>(
            part, part.topic<wire::WorkerFramePubSubType>(dds::kWorkerFrames), dds::reader_qos(every_frame),
            &inbox_);
        owners_ = std::make_unique<dds::Reader<wire::Assignment>>(
            part, part.topic<wire::AssignmentPubSubType>(dds::kSectorOwners),
            dds::reader_qos(dds::kAssignmentDelivery), &inbox_);
        requests_ = std::make_unique<dds::Writer<wire::SectorRequest>>(
            part, part.topic<wire::SectorRequestPubSubType>(dds::kSectorRequests),
            dds::writer_qos(dds::kCommandDelivery));
    }
    ~MembershipCheck() {
        requests_.reset();
        frames_.reset();
        marks_.reset();
        owners_.reset();
    }

    void poll() {
        inbox_.wait(std::chrono::milliseconds(20));
        frames_->take_all([&](const wire::SectorFrame& f, const dds::fdds::SampleInfo& info) {
            // The coordinator's samples (worker 0) hold the sectors not written since the first state.
            if (!info.valid_data) return;
            if (f.worker() != 0) worker_instances_[f.worker()].insert(info.instance_handle);
            if (chain_.stale(f)) return;
            if (!f.complete()) ++partial;
            const SectorKey key = dds::from_wire(f.sector());
            // A sector breaks at its first refused sample, and is mended by the whole sample after it; it may
            // break again before the frames checked reach that mend (a mend then a second break, kept
            // apart: the second one lost to the first, the frames after the mend were checked on an
            // unknown state).
            auto open_break = [&] {
                auto [first, last] = broken_.equal_range(key);
                for (; first != last; ++first)
                    if (first->second.mended == 0) return first;
                return broken_.end();
            };
            if (!chain_.accept(f)) {
                if (refusals.size() < 20)
                    refusals += " [sector " + std::to_string(key.i) + "," + std::to_string(key.j) + "," +
                                std::to_string(key.k) + " frame " + std::to_string(f.frame()) + " base " +
                                std::to_string(f.base()) + " from worker " + std::to_string(f.worker()) +
                                ", held as of " + std::to_string(chain_.newest(key)) + "]";
                wanted_.want(key);
                if (open_break() == broken_.end()) broken_.emplace(key, Broken{f.frame(), 0});
                return;
            }
            wanted_.got(key);
            if (auto b = open_break(); b != broken_.end() && f.complete()) b->second.mended = f.frame();
            pending_[f.frame()].push_back(f);
        });
        wire::SectorRequest whole;
        whole.sectors(wanted_.due(std::chrono::steady_clock::now()));
        if (!whole.sectors().empty()) {
            whole.reader("membership-check");
            whole.request(++requests_written_);
            requests_->write(whole);
        }
        owners_->take_all([&](const wire::Assignment& a, const dds::fdds::SampleInfo& info) {
            if (info.valid_data) assignment = dds::from_wire(a);
        });
        marks_->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
            if (info.valid_data && m.frame() == 0 && m.worker() == 0) {
                // The world's first state: the sectors the coordinator wrote at frame 0.
                first_state_.emplace();
                for (const auto& w : m.written())
                    first_state_->push_back(dds::from_wire(w.sector()));
            }
            if (!info.valid_data || m.frame() == 0 || m.worker() == 0) return;
            last_marks[m.worker()] = m;
            auto& written = marks_by_frame_[m.frame()][m.worker()];
            for (const auto& w : m.written())
                written.push_back(dds::from_wire(w.sector()));
        });
        // Frames in order, each once all workers marked it and every sample they list is here.
        for (;;) {
            if (next_ == 1) {
                // The first frame starts from the world's first state, which the coordinator's history holds
                // only until every worker has ended frame 2: a reader that matched its writer later
                // (discovery under load) lacks the sectors written then and never written since (walls), and
                // asks for them whole; until they come their state is unknown.
                // Its mark (durable: it comes, however late this reader matched the coordinator's marks
                // writer) says which sectors it holds; their samples are waited for until later frames show
                // they will not come (the marks of frame 10 are here).
                if (!first_state_) break;
                const bool late = !marks_by_frame_.empty() && marks_by_frame_.rbegin()->first >= 10;
                std::vector<SectorKey> lacking;
                for (const SectorKey& key : *first_state_) {
                    if (chain_.newest(key) == 0 && !chain_.holds(key, 0, ~std::uint64_t{0}))
                        lacking.push_back(key);
                }
                if (!lacking.empty() && !late) break;
                for (const SectorKey& key : lacking) {
                    wanted_.want(key);
                    broken_.emplace(key, Broken{1, 0});
                }
            }
            auto it = marks_by_frame_.find(next_);
            if (it == marks_by_frame_.end() || it->second.size() < workers) {
                // A mark more than eight frames older than a frame all workers marked will not come: the
                // writer matched this reader late (DDS discovery under load), and its history keeps eight.
                // That frame is skipped, its samples applied with the next one checked.
                auto later = marks_by_frame_.lower_bound(next_ + 9);
                bool lost = false;
                for (; later != marks_by_frame_.end() && !lost; ++later)
                    lost = later->second.size() >= workers;
                if (!lost) break;
                if (it != marks_by_frame_.end()) marks_by_frame_.erase(it);
                ++skipped;
                ++next_;
                continue;
            }
            bool held = true, mending = false;
            for (const auto& [worker, written] : it->second) {
                for (const SectorKey& key : written) {
                    const bool here = chain_.holds(key, next_, next_);
                    held = held && here;
                    // Refused and asked for, or mended by a later whole sample: this frame's state will not
                    // come.
                    mending = mending || (!here && (wanted_.wanted(key) || chain_.newest(key) > next_));
                }
            }
            if (!held && !mending) break;
            // A sector whose sample was refused holds an unknown state from that sample's frame until a
            // whole one mends it, in the frames that do not write it too.
            for (auto b = broken_.begin(); b != broken_.end();) {
                if (b->second.mended != 0 && b->second.mended <= next_) {
                    b = broken_.erase(b);
                    continue;
                }
                held = held && b->second.since > next_;
                ++b;
            }
            std::vector<const wire::SectorFrame*> batch;
            const auto end = pending_.upper_bound(next_);
            for (auto p = pending_.begin(); p != end; ++p) {
                for (const wire::SectorFrame& sample : p->second)
                    batch.push_back(&sample);
            }
            mirror_.apply(batch);
            pending_.erase(pending_.begin(), end);
            chain_.forget_applied(next_);
            if (!held) {
                // A sector of this frame waits for a whole sample: its state here is unknown.
                marks_by_frame_.erase(it);
                ++skipped;
                ++next_;
                continue;
            }
            // Counted by id in a flat table: a large world is checked every frame without falling behind
            // the cluster (a reader that does not take its samples in time loses them to newer ones).
            seen_.assign(seen_.size(), 0);
            std::size_t distinct = 0;
            bool twice = false;
            for (const auto& [key, bodies] : mirror_.sectors()) {
                for (const dds::SectorMirror::Body& body : bodies) {
                    const auto id = static_cast<std::size_t>(body.state.id);
                    if (id >= seen_.size()) seen_.resize(2 * id + 1, 0);
                    distinct += seen_[id] == 0;
                    twice = twice || seen_[id] == 1;
                    seen_[id] += 1;
                }
            }
            ++checked;
            doubled += twice;
            if (distinct != expected_bodies && incomplete++ == 0) {
                first_incomplete = "frame " + std::to_string(next_) + ": " + std::to_string(distinct) +
                                   " of " + std::to_string(expected_bodies) + " bodies; sectors:";
                for (const auto& [key, bodies] : mirror_.sectors()) {
                    first_incomplete += " (" + std::to_string(key.i) + "," + std::to_string(key.j) + "," +
                                        std::to_string(key.k) + "):";
                    for (const dds::SectorMirror::Body& body : bodies)
                        first_incomplete += " " + std::to_string(body.state.id);
                }
                first_incomplete += "; the first state's sectors:";
                for (const SectorKey& key : first_state_ ? *first_state_ : std::vector<SectorKey>{})
                    first_incomplete += " (" + std::to_string(key.i) + "," + std::to_string(key.j) + "," +
                                        std::to_string(key.k) + ") newest " +
                                        std::to_string(chain_.newest(key));
            }
            marks_by_frame_.erase(it);
            ++next_;
        }
    }

    std::size_t refused() const { return chain_.refused(); }

    std::size_t workers = 2;
    std::size_t expected_bodies = 0;
    std::size_t checked = 0, doubled = 0, incomplete = 0, partial = 0, skipped = 0;
    std::string first_incomplete;  ///< the first frame with a body missing, and what it held
    std::string refusals;          ///< the first samples refused for a missing base
    /// The most DDS instances one worker's sector samples came in: one, so that its writer's history has no
    /// holes (idl/lpss.idl, SectorFrame).
    std::size_t most_instances_of_a_worker() const {
        std::size_t most = 0;
        for (const auto& [worker, instances] : worker_instances_)
            most = std::max(most, instances.size());
        return most;
    }
    std::map<std::uint32_t, wire::WorkerFrame> last_marks;  ///< each worker's latest end of frame
    SectorAssignment assignment;                            ///< the latest the coordinator announced
    /// The sectors and their bodies as of the last frame checked.
    const dds::SectorMirror::Sectors& sectors() const { return mirror_.sectors(); }

private:
    dds::Inbox inbox_;
    std::unique_ptr<dds::Participant> participant_;
    std::unique_ptr<dds::Reader<wire::SectorFrame>> frames_;
    std::unique_ptr<dds::Reader<wire::WorkerFrame>> marks_;
    std::unique_ptr<dds::Reader<wire::Assignment>> owners_;
    std::unique_ptr<dds::Writer<wire::SectorRequest>> requests_;
    std::uint64_t requests_written_ = 0;
    dds::WholeSectorAsks wanted_;
    dds::SectorChain chain_;
    dds::SectorMirror mirror_;
    std::uint64_t next_ = 1;
    std::vector<std::uint8_t> seen_;
    std::map<std::uint64_t, std::vector<wire::SectorFrame>> pending_;
    std::map<std::uint32_t, std::set<dds::fdds::InstanceHandle_t>> worker_instances_;
    std::map<std::uint64_t, std::map<std::uint32_t, std::vector<SectorKey>>> marks_by_frame_;
    std::optional<std::vector<SectorKey>> first_state_;  ///< the sectors of the world's first state
    struct Broken {
        std::uint64_t since = 0;   ///< the frame of its first refused sample
        std::uint64_t mended = 0;  ///< the frame of the whole sample after it (0: not yet)
    };
    std::multimap<SectorKey, Broken> broken_;
};

/// Checks every frame until lpss-cluster ends, and then those still on their way, and expects it to have
/// ended cleanly: a check that stopped with the cluster would miss its last frames.
void check_to_the_end(MembershipCheck& check, testing::ClusterRun& cluster) {
    while (cluster.process->running())
        check.poll();
    for (int n = 0; n < 20; ++n)
        check.poll();
    EXPECT_EQ(cluster.process->exit_code().value_or(-1), 0) << "logs: " << cluster.log_dir;
}

TEST(Cluster, BodiesCrossingWorkerBordersAreSeenExactlyOnceInEveryFrame) {
    // Balls bouncing between walls 2.5 sectors apart, through the borders of three sectors owned by two
    // workers, in both directions, for 2,000 frames.
    Scene scene;
    scene.settings.sector_size = 32;
    scene.settings.sleeping = false;
    for (int n = 0; n < 2; ++n) {
        BodyDesc wall =
            scenes::box_body(100 + n, Eigen::Vector3d(0.5, 10, 10), 0.0, Eigen::Vector3d(n ? 60 : -20, 0, 0));
        wall.material = Material{0, 1};
        scene.bodies.push_back(wall);
    }
    for (int n = 0; n < 8; ++n) {
        BodyDesc ball = scenes::sphere_body(1 + n, 0.5, 1.0, Eigen::Vector3d(-10 + 7 * n, -8 + 2 * n, 0));
        ball.linear_velocity = Eigen::Vector3d((n % 2 ? -1 : 1) * (25 + 4 * n), 0, 0);
        ball.material = Material{0, 1};
        scene.bodies.push_back(ball);
    }
    const int domain = 123;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(scene, "exactly_once");
    MembershipCheck check(domain);
    check.workers = 2;
    check.expected_bodies = scene.bodies.size();
    auto cluster = start_cluster(path, domain, 2, 2000, {"--block-size", "1"});
    ASSERT_TRUE(cluster.process);
    check_to_the_end(check, cluster);
    EXPECT_GE(check.checked, 1900u) << "frames checked";
    EXPECT_EQ(check.doubled, 0u);
    EXPECT_EQ(check.incomplete, 0u) << check.first_incomplete << "\nrefused:" << check.refusals;
    // The walls never move: after the first frames the sectors travel as partial samples.
    EXPECT_GT(check.partial, 1000u);
    EXPECT_EQ(check.most_instances_of_a_worker(), 1u);
    std::printf(
        "%zu frames checked: %zu with a body twice, %zu with a body missing; %zu partial samples, %zu "
        "refused for a missing base, %zu frames skipped\n",
        check.checked, check.doubled, check.incomplete, check.partial, check.refused(), check.skipped);
    // The handoffs really happened: the coordinator counts those it granted.
    const std::string text = read_file(cluster.log_dir + "/coordinator.log");
    const std::size_t stopping = text.find("stopping after frame ");
    ASSERT_NE(stopping, std::string::npos) << text;
    const std::size_t count = text.find('(', stopping);
    ASSERT_NE(count, std::string::npos) << text;
    EXPECT_GT(std::stoull(text.substr(count + 1)), 10u) << "handoffs granted: " << text.substr(stopping, 60);
}

TEST(Cluster, AWorldFarLargerThanAnyHaloRunsWithEachWorkerHoldingItsShare) {
    // 50,000 resting bodies over about 120 sectors and 300 balls thrown across the middle, on 3 workers:
    // each worker owns its share and holds as ghosts only bodies that come near its own sectors (never the
    // world, nor whole sectors next to its own); every body is seen exactly once in every frame.
    const Scene scene = scenes::resting_world(50000, 300);
    const int domain = 134;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(scene, "share");
    MembershipCheck check(domain);
    check.workers = 3;
    check.expected_bodies = scene.bodies.size() - 1;  // the ground plane is in no sector
    auto cluster = start_cluster(path, domain, 3, 150);
    ASSERT_TRUE(cluster.process);
    check_to_the_end(check, cluster);
    EXPECT_GE(check.checked, 140u);
    EXPECT_EQ(check.doubled, 0u);
    EXPECT_EQ(check.incomplete, 0u);
    ASSERT_EQ(check.last_marks.size(), 3u);
    ASSERT_EQ(check.assignment.workers.size(), 3u);
    // The most a worker may hold as ghosts: the bodies of the sectors next to a sector it owns that holds
    // bodies (a sector goes to a neighbour's owner only if its bodies come near that neighbour).
    std::map<std::uint32_t, std::set<SectorKey>> own;
    for (const auto& [key, bodies] : check.sectors())
        own[check.assignment.owner_of(key)].insert(key);
    const double world = static_cast<double>(check.expected_bodies);
    // A body comes near a neighbour within the hysteresis band, its radius, the largest radius and three
    // frames of its motion (common/border_reach.hpp): here under 0.94 + 0.94 + 0.22 + 0.1 past the band.
    const double near_reach = scene.settings.hysteresis * scene.settings.sector_size + 2.5;
    const std::size_t balls = 300;
    std::uint64_t owned = 0;
    // Named, not bound: the lambda below reads the worker and the key, and a C++17 lambda cannot capture a
    // structured binding (clang refuses it).
    for (const auto& worker_marks : check.last_marks) {
        const std::uint32_t worker = worker_marks.first;
        const auto& m = worker_marks.second;
        owned += m.bodies();
        std::size_t next_to_own = 0, near_own = 0;
        for (const auto& sector : check.sectors()) {
            const SectorKey& key = sector.first;
            const auto& bodies = sector.second;
            if (own[worker].count(key)) continue;
            bool adjacent = false;
            for (const SectorKey& mine : own[worker])
                adjacent = adjacent || sector_distance(mine, key) == 1;
            if (!adjacent) continue;
            next_to_own += bodies.size();
            for (const dds::SectorMirror::Body& b : bodies) {
                const Eigen::Vector3d local(b.state.position[0], b.state.position[1], b.state.position[2]);
                bool near = false;
                neighbours_within(local, scene.settings.sector_size, near_reach, [&](const SectorKey& d) {
                    near = near || own[worker].count(SectorKey{key.i + d.i, key.j + d.j, key.k + d.k}) != 0;
                });
                near_own += near ? 1 : 0;
            }
        }
        std::printf(
            "worker %u: %u bodies of its own, %u ghosts and %u kept out of its engine (bodies next to its "
            "sectors: %zu, near them: %zu), %.1f kB received in its last frame\n",
            worker, m.bodies(), m.ghosts(), m.dormant(), next_to_own, near_own, m.received_bytes() / 1e3);
        // A ball that came near once stays a ghost until its sector releases the worker.
        EXPECT_LE(m.ghosts(), near_own + balls) << "worker " << worker << " holds more than what comes near";
        // The rest of the sectors it holds it keeps as records, and nothing beyond the sectors next to its
        // own; a sector with a body near it has others that are not (64 units wide, bodies 3 apart).
        EXPECT_LE(m.ghosts() + m.dormant(), next_to_own + balls)
            << "worker " << worker << " holds far sectors";
        EXPECT_GT(m.dormant(), 0u) << "worker " << worker
                                   << ": every body of the sectors it holds is a ghost";
        EXPECT_LT(m.bodies() + m.ghosts(), 0.6 * world) << "worker " << worker << " holds most of the world";
        EXPECT_GT(m.bodies(), 0.15 * world) << "worker " << worker << " has no share of the world";
    }
    EXPECT_EQ(owned, check.expected_bodies) << "every body owned by exactly one worker";
}

TEST(Cluster, SectorsMoveBetweenWorkersWhenTheLoadShifts) {
    // Ten resting boxes far to the west, ten balls in each of two sectors far to the east: the first
    // assignment gives the west and the nearer east sector to worker 1, the farther one to worker 2. The
    // balls then fly west into worker 1's sectors, leaving worker 2 idle: the coordinator moves sectors.
    Scene scene;
    scene.settings.sector_size = 32;
    scene.settings.sleeping = false;
    BodyId id = 1;
    for (int n = 0; n < 10; ++n) {
        scene.bodies.push_back(scenes::box_body(id++, Eigen::Vector3d::Constant(0.4), 1.0,
                                                Eigen::Vector3d(-128 + 2.0 * n, 0, 0)));
    }
    for (int sector = 4; sector <= 5; ++sector) {
        for (int n = 0; n < 10; ++n) {
            BodyDesc ball =
                scenes::sphere_body(id++, 0.4, 1.0, Eigen::Vector3d(32.0 * sector - 8 + 1.6 * n, 0, 3));
            ball.linear_velocity = Eigen::Vector3d(-60, 0, 0);
            scene.bodies.push_back(ball);
        }
    }
    BodyDesc wall = scenes::box_body(500, Eigen::Vector3d(0.5, 10, 10), 0.0, Eigen::Vector3d(-40, 0, 0));
    wall.material = Material{0.5, 0.0};
    scene.bodies.push_back(wall);
    const int domain = 127;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(scene, "rebalance");
    MembershipCheck check(domain);
    check.workers = 2;
    check.expected_bodies = scene.bodies.size();
    auto cluster =
        // Paced: the check must see the first frame's marks, which an unpaced cluster under a parallel test
        // load had replaced (eight frames deep) before the check's reader matched.
        start_cluster(path, domain, 2, 600, {"--block-size", "1", "--rebalance-every", "60"});
    ASSERT_TRUE(cluster.process);
    check_to_the_end(check, cluster);
    const std::string text = read_file(cluster.log_dir + "/coordinator.log");
    // Rebalances follow the balls while they fly; once they rest against the wall (by frame 210) the
    // load stands still, and one more rebalance may catch up with it, but no more: a later one would move
    // sectors back and forth for nothing.
    std::size_t rebalances = 0, at_rest = 0;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        const std::size_t at = line.find(" from frame ");
        if (line.find("(load shifted)") == std::string::npos || at == std::string::npos) continue;
        ++rebalances;
        if (std::stoull(line.substr(at + 12)) > 240) ++at_rest;
    }
    EXPECT_GE(rebalances, 1u) << text;
    EXPECT_LE(at_rest, 1u) << text;
    EXPECT_GE(check.checked, 500u);
    EXPECT_EQ(check.doubled, 0u);
    EXPECT_EQ(check.incomplete, 0u) << check.first_incomplete << "\nrefused:" << check.refusals;
    std::printf(
        "%zu frames checked across %zu rebalance(s): %zu with a body twice, %zu with a body missing (%zu "
        "skipped: their marks came too late)\n",
        check.checked, rebalances, check.doubled, check.incomplete, check.skipped);
}

TEST(Cluster, ALoadNoCutCanSpreadMovesNoSectors) {
    // Twenty bodies in one sector and two far away: whatever the cut, one worker carries the crowded
    // sector, so the load stays uneven, and a new assignment would only churn epochs and handoffs.
    Scene scene;
    scene.settings.sector_size = 32;
    scene.settings.sleeping = false;
    BodyId id = 1;
    for (int n = 0; n < 20; ++n)
        scene.bodies.push_back(
            scenes::sphere_body(id++, 0.4, 1.0, Eigen::Vector3d(2.0 * (n % 5), 2.0 * (n / 5), 0)));
    for (int n = 0; n < 2; ++n)
        scene.bodies.push_back(scenes::sphere_body(id++, 0.4, 1.0, Eigen::Vector3d(320 + 2.0 * n, 0, 0)));
    const int domain = 131;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(scene, "crowded");
    auto cluster =
        start_cluster(path, domain, 2, 400, {"--block-size", "1", "--rebalance-every", "60"}, true);
    ASSERT_TRUE(cluster.process);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (cluster.process->running() && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    EXPECT_EQ(cluster.process->exit_code().value_or(-1), 0) << "logs: " << cluster.log_dir;
    const std::string text = read_file(cluster.log_dir + "/coordinator.log");
    EXPECT_NE(text.find("stopping after frame 400"), std::string::npos) << text;
    // The load checks ran (every 60 frames), found it uneven, and kept the assignment.
    EXPECT_NE(text.find("but a new assignment would carry"), std::string::npos) << text;
    EXPECT_EQ(text.find("(load shifted)"), std::string::npos) << text;
}

/// The crossing bodies and slow balls in sectors far apart: whichever of them a worker owns lie outside
/// the halos of the others. Every body moves (the slow ones by 0.5/60 units a frame), so a frame of motion
/// lost or stepped twice shows against lpss-sim.
Scene crossing_scene_with_far_balls() {
    Scene scene = crossing_scene();
    for (int n = 0; n < 6; ++n) {
        BodyDesc far = scenes::sphere_body(40 + n, 0.5, 1.0, Eigen::Vector3d((8 + 4 * n) * kL, 0, 0));
        far.linear_velocity = Eigen::Vector3d(0, 0.5, 0);
        scene.bodies.push_back(far);
    }
    return scene;
}

TEST(Cluster, AKilledWorkerIsFoundWithinItsLeaseAndItsLostFrameIsSteppedAgain) {
    // Besides the crossing bodies, slow balls in sectors far apart: whichever of them worker 2 owns lie
    // outside the halos of the others, who must rebuild them from what the coordinator sends. Every body
    // moves (the slow ones by 0.5/60 units a frame), so a frame of motion lost shows against lpss-sim.
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 128;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 600;
    const auto [path, sim] = simulate_scene(scene, "dies", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "survivor");
    ASSERT_TRUE(client);
    auto cluster = start_cluster(path, domain, 3, kFrames, {"--block-size", "1"});
    ASSERT_TRUE(cluster.process);
    FrameRecorder seen(*client);
    auto& frames = seen.frames;
    seen.gather(150, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    // Kill worker 2 outright, as a crash would.
    const auto killed = Clock::now();
    ASSERT_EQ(pkill("KILL", worker_process(domain, 2)), 0);
    const std::uint64_t killed_at = frames.rbegin()->first;
    seen.gather(kFrames, std::chrono::seconds(60));
    ASSERT_GT(frames.rbegin()->first, killed_at + 120) << "frames go on after the death";

    // The pause a client sees: the longest wait for a frame after the kill.
    const double pause = seen.longest_wait(killed_at, killed);
    // Every frame the client saw holds every body once, each within the cluster's bound of lpss-sim
    // (docs/protocol.md: 1e-3), the frames around the death included.
    const SectorGrid grid(kL);
    double worst = 0.0, worst_after = 0.0;
    std::uint64_t checked_after = 0;
    for (const auto& [f, frame] : frames) {
        const auto& expected = sim.at(f);
        ASSERT_EQ(frame.bodies.size(), expected.size()) << "frame " << f;
        for (const BodyView& b : frame.bodies) {
            ASSERT_TRUE(expected.count(b.id)) << "frame " << f << " body " << b.id;
            const double d = (grid.to_global(b.position) - grid.to_global(expected.at(b.id).position)).norm();
            if (d > 1e-3 && worst <= 1e-3)
                std::printf("first beyond the bound: frame %llu body %llu by %.3g\n",
                            static_cast<unsigned long long>(f), static_cast<unsigned long long>(b.id), d);
            worst = std::max(worst, d);
            if (f > killed_at) worst_after = std::max(worst_after, d);
        }
        if (f > killed_at) ++checked_after;
    }
    std::printf(
        "worker 2 killed after frame %llu: the longest wait for a frame %.3f s; %llu frames after it, "
        "largest difference from lpss-sim %.3g (before and after: %.3g)\n",
        static_cast<unsigned long long>(killed_at), pause, static_cast<unsigned long long>(checked_after),
        worst_after, worst);
    // Real time after the pause: the time lost is reported with the frames, and the frames after it come
    // at the scene's rate, not in a burst that catches up on the wall time lost.
    // The time lost to the kill: the largest step in the time lost from one frame seen to the next after it
    // (a loaded machine loses time elsewhere too, and the client sees the kill some frames after it came).
    double lost = 0.0;
    for (auto it = frames.upper_bound(killed_at); it != frames.end(); ++it)
        lost = std::max(lost, it->second.time_lost_s - std::prev(it)->second.time_lost_s);
    const auto first_after = frames.lower_bound(killed_at + 5);
    const auto last_after = std::prev(frames.upper_bound(killed_at + 125));
    ASSERT_TRUE(first_after != frames.end() && last_after->first > first_after->first + 60);
    const double spacing =
        std::chrono::duration<double>(last_after->second.started - first_after->second.started).count() /
        static_cast<double>(last_after->first - first_after->first);
    std::printf(
        "real time lost to the kill, as reported with the frames: %.3f s; frames after it %.2f ms apart\n",
        lost, 1e3 * spacing);
    EXPECT_GE(lost, 0.2) << "the pause is reported";
    EXPECT_LE(lost, pause + 0.1) << "no more than the pause a client saw";
    EXPECT_GE(spacing, 0.95 / 60.0) << "no burst to catch up";
    EXPECT_LE(spacing, 1.5 / 60.0);
    EXPECT_LE(worst, 1e-3);
    EXPECT_LT(pause, 1.0) << "the world goes on within a second of the kill";
    EXPECT_GE(checked_after, (kFrames - killed_at) * 9 / 10) << "the client saw most frames after the kill";
    expect_stopped_cleanly(cluster);
    const std::string text = read_file(cluster.log_dir + "/coordinator.log");
    // Found by its liveliness lease (0.4 s), not by a silence of seconds; the frame it did not finish
    // stepped again by the coordinator.
    const std::size_t found = text.find("worker 2 is gone during frame");
    ASSERT_NE(found, std::string::npos) << text;
    EXPECT_NE(text.find("its liveliness lease expired", found), std::string::npos) << text;
    const std::size_t into = text.find("s into the frame", found);
    ASSERT_NE(into, std::string::npos) << text;
    const double seconds = std::stod(text.substr(text.rfind(", ", into) + 2));
    EXPECT_LE(seconds, 0.6) << "found within the lease (and the frame it died in)";
    EXPECT_NE(text.find("of worker 2 stepped again here"), std::string::npos) << text;

    // lpss-cluster's last line sums the bodies of the workers that run: the killed one's last report is not
    // among them, and is named as silent (it was summed: 3,988 bodies in a world of 2,272 after a kill).
    const std::string summary = read_file(cluster.log_dir + ".out");
    const std::size_t done = summary.rfind("done:");
    ASSERT_NE(done, std::string::npos) << summary;
    const std::string last_line = summary.substr(done, summary.find('\n', done) - done);
    const std::size_t bodies_at = last_line.find("bodies ");
    ASSERT_NE(bodies_at, std::string::npos) << last_line;
    const auto in_sectors = static_cast<long>(std::count_if(
        scene.bodies.begin(), scene.bodies.end(), [](const BodyDesc& b) { return !is_plane(b.shape); }));
    // Exact when the workers' last reports are of one frame; a body handed over between two reports of
    // different frames counts once more or less.
    EXPECT_NEAR(std::stol(last_line.substr(bodies_at + 7)), in_sectors, 2) << last_line;
    EXPECT_NE(last_line.find("silent: worker 2 since frame"), std::string::npos) << last_line;
    const std::size_t sectors_at = last_line.find("sectors per worker");
    ASSERT_NE(sectors_at, std::string::npos) << last_line;
    EXPECT_EQ(last_line.substr(sectors_at, last_line.find("ghosts") - sectors_at).find(" 2:"),
              std::string::npos)
        << last_line;
}

TEST(Cluster, AWorkerKilledInAWorldMostlyAtRestHasOnlyWhatMayChangeSteppedAgain) {
    // 20,000 resting bodies over 49 sectors and 100 balls in the middle, on 3 workers; worker 2 is killed.
    // The coordinator steps the frame it did not finish again only in its sectors next to a body awake (a
    // world of every body it held took 3.6 s at a million bodies, the world stopped meanwhile); the rest,
    // asleep throughout the frame, go to their new owners as they were. In every 20th frame a client of
    // changes rebuilt: every body once; before the kill every body where lpss-sim has it, after it every
    // body of the sectors far from any motion (near the balls the cluster drifts, below).
    const Scene scene = scenes::resting_world(20000, 100);
    const int domain = 181;
    const testing::DomainCleanup cleanup(domain);
    // Frames enough after the kill for a client that fell behind: the kill follows the client's frame 100,
    // and a client building its first frame of 20,000 bodies under a sanitizer beside other tests was seen
    // to sync again at frame 198 with the cluster at 327 (of 360 then: 2 frames left to compare).
    constexpr std::uint64_t kFrames = 480;
    constexpr int kEvery = 20;
    // Not bound as [path, sim]: gather, below, reads sim, and a C++17 lambda cannot capture a binding.
    const SimulatedScene simulated = simulate_scene(scene, "killed_at_rest", kFrames, kEvery);
    const SimFrames& sim = simulated.sim;
    ASSERT_EQ(sim.size(), kFrames / kEvery + 1);
    auto client = connect(domain, "rebuilds", std::nullopt, FrameContent::changes);
    ASSERT_TRUE(client);
    auto cluster = start_cluster(simulated.path, domain, 3, kFrames, {"--block-size", "1"});
    ASSERT_TRUE(cluster.process);
    std::map<BodyId, BodyView> bodies;
    std::map<std::uint64_t, WorldFrame> compared;  // the rebuilt world at the frames lpss-sim wrote
    std::uint64_t last = 0;
    auto gather = [&](std::uint64_t until, std::chrono::seconds limit) {
        const auto end = std::chrono::steady_clock::now() + limit;
        while (last < until && std::chrono::steady_clock::now() < end) {
            for (WorldFrame& f : client->poll(std::chrono::milliseconds(5))) {
                if (f.every_body) bodies.clear();
                for (const BodyView& b : f.bodies)
                    bodies[b.id] = b;
                for (BodyId id : f.departed)
                    bodies.erase(id);
                last = f.frame;
                if (!sim.count(f.frame)) continue;
                WorldFrame& copy = compared[f.frame];
                copy.frame = f.frame;
                for (const auto& [id, b] : bodies)
                    copy.bodies.push_back(b);
            }
        }
    };
    gather(100, std::chrono::seconds(90));
    ASSERT_GE(last, 100u) << testing::log_tails(cluster.log_dir);
    const std::uint64_t killed_at = last;
    ASSERT_EQ(pkill("KILL", worker_process(domain, 2)), 0);
    gather(kFrames, std::chrono::seconds(90));
    EXPECT_EQ(last, kFrames) << testing::log_tails(cluster.log_dir);
    EXPECT_TRUE(cluster.process->wait(std::chrono::seconds(30)));
    // Every body once in every frame compared.
    const double sector_size = scene.settings.sector_size;
    double worst = 0.0;
    ASSERT_EQ(testing::against_sim(compared, sim, worst, sector_size), "") << "logs: " << cluster.log_dir;
    // Where lpss-sim moved a body, and the sectors next to those: there the cluster diverges after the kill
    // (a frame stepped again, and sectors taken over, start without Bullet's contact history: balls among
    // resting bodies end up to about a unit from lpss-sim, the same whether all of the gone worker's sectors
    // are stepped again or only these; docs/protocol.md). Everywhere else every body rests throughout and
    // must be exactly where it was: those are the sectors not stepped again.
    const SectorGrid grid(sector_size);
    const auto& at_start = sim.begin()->second;
    std::set<SectorKey> lively;
    for (const auto& [f, rows] : sim) {
        for (const auto& [id, row] : rows) {
            const SimRow& start = at_start.at(id);
            if ((grid.to_global(row.position) - grid.to_global(start.position)).norm() < 1e-6) continue;
            for (const SectorKey& moved : {start.position.sector, row.position.sector})
                for (std::int64_t i = -1; i <= 1; ++i)
                    for (std::int64_t j = -1; j <= 1; ++j)
                        for (std::int64_t k = -1; k <= 1; ++k)
                            lively.insert(moved + SectorKey{i, j, k});
        }
    }
    double worst_before = 0.0, worst_lively = 0.0, worst_resting = 0.0;
    std::size_t resting = 0, after = 0;
    for (const auto& [f, frame] : compared) {
        after += f > killed_at + kEvery ? 1 : 0;
        for (const BodyView& b : frame.bodies) {
            const SimRow& expected = sim.at(f).at(b.id);
            const double d = (grid.to_global(b.position) - grid.to_global(expected.position)).norm();
            if (f <= killed_at) {
                worst_before = std::max(worst_before, d);
            } else if (lively.count(at_start.at(b.id).position.sector)) {
                worst_lively = std::max(worst_lively, d);
            } else {
                worst_resting = std::max(worst_resting, d);
                ++resting;
            }
        }
    }
    std::printf(
        "worker 2 killed after frame %llu; %zu frames compared with lpss-sim, %zu after the kill; largest "
        "difference before it %.3g, after it %.3g in %zu states of bodies of sectors far from any motion, "
        "%.3g near "
        "the balls\n",
        static_cast<unsigned long long>(killed_at), compared.size(), after, worst_before, worst_resting,
        resting, worst_lively);
    EXPECT_LE(worst_before, 1e-3);
    EXPECT_LE(worst_resting, 1e-3) << "a sector not stepped again goes on as it was";
    EXPECT_GT(resting, 0u) << "bodies far from any motion compared after the kill";
    EXPECT_GE(after, 5u) << "frames after the kill compared";
    const std::string text = read_file(cluster.log_dir + "/coordinator.log");
    std::smatch stepped;
    ASSERT_TRUE(std::regex_search(
        text, stepped,
        std::regex(R"(of worker 2 stepped again here: ([0-9]+) of its ([0-9]+) sectors may change)")))
        << text;
    std::printf("%s\n", stepped[0].str().c_str());
    EXPECT_GT(std::stoul(stepped[1]), 0u) << "a sector next to the balls is stepped again";
    EXPECT_LT(std::stoul(stepped[1]), std::stoul(stepped[2])) << "sectors far from them are not";
}

TEST(Cluster, AWorkerKilledWhileCommandsComeHasAllItsSectorsSteppedAgainAndEachCommandAppliedOnce) {
    // A client lifts a resting box every 5 ms, a different box each time, far from the balls (an upward
    // impulse of 3 N s on 1 kg), while worker 2 is killed. The frame it did not finish carries commands,
    // which may touch any sector: the coordinator steps every one of its sectors again, not only those next
    // to motion (with those alone, a command on a body elsewhere would find no body), which its log says.
    // Every command is answered once, and each one applied lifts its box once: it rises 0.434 (v^2 / 2g =
    // 0.459, less what stepping at 60 Hz loses); a lost one leaves it at rest, one applied twice lifts it
    // 1.8. (The boxes lifted before the kill wake the sectors they are in: the lift in the lost frame is
    // mostly in a sector stepped again anyway, so it is the log's count that fails if a frame with commands
    // is stepped again only in part; seen, with the commands left out of that decision: "7 of its 9", the
    // killed worker's sectors at the edge away from the lifts and the balls left out.)
    const Scene scene = scenes::resting_world(8000, 20);
    const int domain = 182;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(scene, "killed_while_lifting");
    constexpr std::uint64_t kFrames = 420;
    constexpr double kLift = 3.0;  // m/s on 1 kg
    // Unit boxes resting at y = 0.5 in a band along one edge of the world (z < -96: sectors k <= -2), far
    // from the balls (which start within 8 of the origin), in an order that spreads them along it. The
    // sectors at the other edge (k = 2) stay at rest: of those, the killed worker's may change only if the
    // frame's commands make everything change, which the count in the log tells.
    std::vector<BodyId> boxes;
    for (const BodyDesc& b : scene.bodies) {
        const auto* box = std::get_if<Box>(&b.shape);
        const auto* at = std::get_if<Eigen::Vector3d>(&b.position);
        if (box && at && box->half_extents.isApprox(Eigen::Vector3d::Constant(0.5)) && b.mass == 1.0 &&
            at->z() < -96.0)
            boxes.push_back(b.id);
    }
    ASSERT_GE(boxes.size(), 200u);
    std::shuffle(boxes.begin(), boxes.end(), std::mt19937(1));
    const double resting_height = 0.5;
    // A client of changes: it is told only the bodies that moved (the balls, the boxes in the air), and so
    // keeps up under a sanitizer on a loaded machine, where one of every body fell two seconds behind and
    // had to sync again, which a world of 420 frames does not wait for (docs/operations.md).
    auto watcher = connect(domain, "watcher", std::nullopt, FrameContent::changes);
    // The lifter follows one empty sector far away: its polls stay short (a client of the whole world that
    // is polled only now and then has the world to take in each time).
    auto lifter = connect(domain, "lifter", Region{{100, 0, 100}, {100, 0, 100}});
    ASSERT_TRUE(watcher && lifter);
    auto cluster = start_cluster(path, domain, 3, kFrames, {"--block-size", "1"});
    ASSERT_TRUE(cluster.process);
    // The heights of the boxes that may be lifted, in every frame they were seen moving (filled in before
    // the lifts begin: the lifting thread does not touch it).
    std::map<BodyId, std::map<std::uint64_t, double>> height;
    for (BodyId id : boxes)
        height[id];
    std::uint64_t last = 0;
    auto watch = [&](std::chrono::milliseconds wait) {
        for (const WorldFrame& f : watcher->poll(wait)) {
            last = std::max(last, f.frame);
            for (const BodyView& b : f.bodies) {
                auto it = height.find(b.id);
                if (it != height.end()) it->second[f.frame] = b.global.y();
            }
        }
    };
    // Both clients polled until the watcher has seen `frame` (or `limit` passes).
    auto follow_until = [&](std::uint64_t frame, std::chrono::seconds limit) {
        for (auto end = std::chrono::steady_clock::now() + limit;
             last < frame && std::chrono::steady_clock::now() < end;) {
            watch(std::chrono::milliseconds(20));
            lifter->poll(std::chrono::milliseconds(0));
        }
    };
    follow_until(60, std::chrono::seconds(60));
    ASSERT_GE(last, 60u) << testing::log_tails(cluster.log_dir);
    ASSERT_LT(last, 120u) << "the lifts start early in the run";
    // The lifts go on from a thread of their own while the worker is killed, so that they keep coming in
    // the frame it does not finish (the kill itself takes milliseconds): one every 5 ms, the kill once the
    // first has been applied (a new client's first commands wait until the coordinator has matched it;
    // under AddressSanitizer that took longer than a fixed count of lifts) and 20 more have gone, the
    // lifts 40 more after it.
    std::vector<std::pair<BodyId, std::uint64_t>> lifts;  // body, request
    std::atomic<std::size_t> sent{0}, flowing_from{0};
    std::atomic<bool> worker_killed{false};
    std::thread lifting([&] {
        std::size_t after_kill = 0;
        for (std::size_t n = 0; n < boxes.size() && after_kill < 40; ++n) {
            const BodyId id = boxes[n];
            lifts.emplace_back(id, lifter->apply_impulse(id, Eigen::Vector3d(0, kLift, 0)));
            sent = n + 1;
            lifter->poll(std::chrono::milliseconds(5));
            if (flowing_from == 0 && lifter->outcome(lifts.front().second)) flowing_from = n + 1;
            if (worker_killed) ++after_kill;
        }
    });
    const auto lifts_end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while ((flowing_from == 0 || sent < flowing_from + 20) && sent < boxes.size() &&
           std::chrono::steady_clock::now() < lifts_end)
        watch(std::chrono::milliseconds(2));
    const std::uint64_t killed_at = last;
    const int killed = pkill("KILL", worker_process(domain, 2));
    worker_killed = true;
    lifting.join();
    ASSERT_EQ(killed, 0);
    ASSERT_GT(flowing_from.load(), 0u) << "lifts applied before the kill";
    follow_until(kFrames, std::chrono::seconds(90));
    EXPECT_EQ(last, kFrames) << testing::log_tails(cluster.log_dir);
    EXPECT_TRUE(cluster.process->wait(std::chrono::seconds(30)));

    // Each command answered once, and each one applied lifted its box once.
    std::size_t applied = 0, on_the_killed = 0;
    double lowest = 1e9, highest = 0.0;
    for (const auto& [id, request] : lifts) {
        const auto outcome = lifter->wait_outcome(request, std::chrono::seconds(5));
        ASSERT_TRUE(outcome) << "the lift of body " << id << " was never answered";
        if (!outcome->applied) {
            EXPECT_FALSE(outcome->reason.empty()) << "body " << id;
            continue;
        }
        ++applied;
        const std::map<std::uint64_t, double>& seen = height.at(id);
        // At rest until then (far from the balls, asleep): a client of changes is not told of it before.
        for (auto it = seen.begin(); it != seen.end() && it->first < outcome->frame; ++it)
            ASSERT_NEAR(it->second, resting_height, 1e-3) << "body " << id << " moved before its lift";
        double top = resting_height;
        std::size_t frames_after = 0;
        for (auto it = seen.lower_bound(outcome->frame); it != seen.end() && it->first <= outcome->frame + 40;
             ++it, ++frames_after)
            top = std::max(top, it->second);
        ASSERT_GE(frames_after, 20u) << "body " << id << " seen moving after its lift at frame "
                                     << outcome->frame;
        const double rise = top - resting_height;
        lowest = std::min(lowest, rise);
        highest = std::max(highest, rise);
        EXPECT_GE(rise, 0.3) << "body " << id << " lifted at frame " << outcome->frame << " (lost?)";
        EXPECT_LE(rise, 0.6) << "body " << id << " lifted at frame " << outcome->frame << " (twice?)";
        if (outcome->frame >= killed_at && outcome->frame <= killed_at + 60) ++on_the_killed;
    }
    const std::string text = read_file(cluster.log_dir + "/coordinator.log");
    std::smatch stepped;
    const bool found = std::regex_search(
        text, stepped,
        std::regex(R"(of worker 2 stepped again here: ([0-9]+) of its ([0-9]+) sectors may change([^,]*),)"));
    std::printf(
        "worker 2 killed after frame %llu; %zu of %zu lifts applied (%zu within a second of the kill), "
        "rising %.3f to %.3f; %s\n",
        static_cast<unsigned long long>(killed_at), applied, lifts.size(), on_the_killed, lowest, highest,
        found ? stepped[0].str().c_str() : "(no frame stepped again)");
    EXPECT_GE(applied, lifts.size() * 9 / 10) << "lifts are refused only for a reason";
    EXPECT_GT(on_the_killed, 0u);
    ASSERT_TRUE(found) << text;
    if (stepped[3].str().find("the frame carries") == std::string::npos) {
        // The lifts come every 5 ms from a thread of this test's; on a loaded machine it can miss a frame's
        // start (seen once in a fresh-machine run of the suite at -j2: the frame stepped again carried no
        // command, and rightly stepped only its sectors that may change, 7 of 9). What this test is for is
        // then not in the run: it says so rather than pass.
        GTEST_SKIP() << "the frame worker 2 did not finish carried no command (the lifts missed its start): "
                     << stepped[0];
    }
    EXPECT_GE(std::stoul(stepped[1]), std::stoul(stepped[2])) << "every sector of worker 2 stepped again";
}

/// Every worker of a cluster of `workers` killed at once after frame 150 (or, `stop_s` > 0, stopped for
/// that long), lpss-cluster starting killed ones again (--restart-workers): the coordinator holds the world
/// until one joins, and no body is lost or doubled. Returns the pause a client saw, in seconds.
double fault_every_worker(int workers, int domain, int stop_s = 0) {
    const Scene scene = crossing_scene_with_far_balls();
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 600;
    const auto [path, sim] = simulate_scene(scene, "every" + std::to_string(workers), kFrames);
    EXPECT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "every");
    EXPECT_TRUE(client);
    if (!client) return -1.0;
    auto cluster = start_cluster(path, domain, workers, kFrames, {"--block-size", "1", "--restart-workers"});
    EXPECT_TRUE(cluster.process);
    if (!cluster.process) return -1.0;
    FrameRecorder seen(*client);
    auto& frames = seen.frames;
    seen.gather(150, std::chrono::seconds(60));
    EXPECT_FALSE(frames.empty());
    if (frames.empty()) return -1.0;
    const auto killed = Clock::now();
    const std::string pattern = "'[l]pss-worker --domain " + std::to_string(domain) + " '";
    // Stopped and continued in the background: the client is read meanwhile (at least every 2 s).
    const std::string fault = stop_s > 0 ? "(pkill -STOP -f " + pattern + "; sleep " +
                                               std::to_string(stop_s) + "; pkill -CONT -f " + pattern + ") &"
                                         : "pkill -KILL -f " + pattern;
    EXPECT_EQ(std::system(fault.c_str()), 0);
    const std::uint64_t killed_at = frames.rbegin()->first;
    seen.gather(kFrames, std::chrono::seconds(90));
    EXPECT_EQ(frames.rbegin()->first, kFrames) << "the world goes on to its last frame";
    const double pause = seen.longest_wait(killed_at, killed);
    double worst = 0.0;
    EXPECT_EQ(against_sim(frames, sim, worst), "");
    std::uint64_t after = 0;
    for (const auto& [f, frame] : frames)
        after += f > killed_at ? 1 : 0;
    std::printf(
        "every worker of %d %s after frame %llu: the longest wait for a frame %.3f s; %llu frames seen "
        "after it, largest difference from lpss-sim %.3g\n",
        workers, stop_s > 0 ? "stopped" : "killed", static_cast<unsigned long long>(killed_at), pause,
        static_cast<unsigned long long>(after), worst);
    EXPECT_LE(worst, 1e-3);
    EXPECT_GE(after, (kFrames - killed_at) * 9 / 10) << "the client saw most frames after the kill";
    expect_stopped_cleanly(cluster);
    expect_logged(cluster, "coordinator.log", "every worker is gone during frame");
    expect_logged(cluster, "coordinator.log", "joined the world waiting at frame");
    return pause;
}

TEST(Cluster, AWorldWhoseOnlyWorkerIsKilledWaitsForItToStartAgainAndLosesNothing) {
    // The worker started again asks to join while the coordinator still counts its old self: that request
    // marks the old one dead at its lease, without the silence the last live worker is otherwise given.
    const double pause = fault_every_worker(1, 165);
    EXPECT_GE(pause, 0.0);
    // A new process, a new DDS participant, its discovery and its request: 0.46 s here alone; the bound
    // leaves room for a loaded machine (parallel suites), where discovery has taken seconds.
    EXPECT_LT(pause, 5.0) << "the world goes on once the worker started again has joined";
}

TEST(Cluster, AWorldWhoseEveryWorkerIsKilledAtOnceWaitsForThemAndLosesNothing) {
    // The last live worker is taken as gone on its lease alone only when a worker started again under its
    // id has been heard (a machine too busy to renew every lease is not taken for a dead cluster); the
    // restarted workers cannot ask to join while the assignment names the other dead one, but their hello
    // counts. Before it did, the pause was the last one's silence: 5.1-5.5 s (worker_timeout, 5 s).
    const double pause = fault_every_worker(2, 166);
    EXPECT_GE(pause, 0.0);
    EXPECT_LT(pause, 4.5) << "the world goes on once the workers started again are heard, not after 5 s";
}

TEST(Cluster, AWorldWhoseOnlyWorkerStopsPastItsSilenceWaitsForItToJoinAgain) {
    // SIGSTOP for 7 s: past the last worker's 5 s of silence, it is taken as gone and the world waits.
    // Continued, the worker reads the frame start written again without it, stops without publishing and
    // joins again as a fresh worker, and the world goes on from where it was.
    const double pause = fault_every_worker(1, 167, 7);
    EXPECT_GE(pause, 5.0);
    // 7.0 s here alone: the stop, then a fresh participant's discovery and request (seconds under load);
    // well within the 30 s the world waits.
    EXPECT_LT(pause, 20.0);
}

TEST(Cluster, AWorkerTakenAsGoneStopsAndRejoinsWhenItComesBack) {
    // Worker 2 of 3 is frozen (SIGSTOP) past its lease, as a worker cut off from the others would be: the
    // world goes on without it. Thawed, it finds frames started without it and stops (exit 5) without
    // publishing anything more: its sectors are simulated elsewhere. lpss-cluster starts it again, and it
    // joins the running world. Every frame the client sees holds every body once, within the cluster's
    // bound of lpss-sim.
    const int domain = 144;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 480;
    const auto [path, sim] = simulate_scene(crossing_scene(), "frozen", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "frozen");
    ASSERT_TRUE(client);
    auto cluster = start_cluster(path, domain, 3, kFrames, {"--block-size", "1"});
    ASSERT_TRUE(cluster.process);
    std::map<std::uint64_t, WorldFrame> frames;
    const std::chrono::milliseconds poll(5);
    collect_into(*client, frames, 150, std::chrono::seconds(60), {}, poll);
    ASSERT_FALSE(frames.empty());
    const std::string worker = worker_process(domain, 2);
    ASSERT_EQ(pkill("STOP", worker), 0);
    const std::uint64_t frozen_at = frames.rbegin()->first;
    // 1.5 s: the world went on without it.
    collect_into(*client, frames, frozen_at + 90, std::chrono::seconds(60), {}, poll);
    ASSERT_EQ(pkill("CONT", worker), 0);
    collect_into(*client, frames, kFrames, std::chrono::seconds(60), {}, poll);
    EXPECT_EQ(frames.rbegin()->first, kFrames);
    cluster.process->stop(std::chrono::seconds(20));
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "");
    std::printf(
        "worker 2 frozen after frame %llu for 1.5 s, then thawed: %zu frames seen, largest "
        "difference from lpss-sim %.3g\n",
        static_cast<unsigned long long>(frozen_at), frames.size(), worst);
    EXPECT_LE(worst, 1e-3);
    EXPECT_GE(frames.size(), kFrames * 9 / 10);
    // Thawed, it finds itself out of the cluster (frames started without it, or no coordinator heard for
    // the lease while it was frozen), publishes nothing more, and joins again as a fresh worker.
    const std::string text = read_file(cluster.log_dir + "/worker-2.log");
    const std::size_t out = text.find("stopping without publishing");
    ASSERT_NE(out, std::string::npos) << text;
    const std::size_t again = text.find("joins again as a fresh worker", out);
    ASSERT_NE(again, std::string::npos) << text;
    EXPECT_NE(text.find("joins the cluster with sectors", again), std::string::npos) << text;
    expect_logged(cluster, "coordinator.log", "worker 2 asks to join");
}

/// The largest body count each worker reported in a mark of a frame after `after`: which workers
/// simulate something, read from the wire.
class BodiesPerWorker {
public:
    explicit BodiesPerWorker(int domain) {
        auto p = dds::Participant::create(domain, "", "bodies-per-worker");
        EXPECT_TRUE(p.ok());
        participant_ = std::move(p).value();
        marks_ = std::make_unique<dds::Reader<wire::WorkerFrame>>(
            *participant_, participant_->topic<wire::WorkerFramePubSubType>(dds::kWorkerFrames),
            dds::reader_qos(dds::Delivery{true, 256}), &inbox_);
    }
    ~BodiesPerWorker() { marks_.reset(); }
    void poll(std::uint64_t after) {
        marks_->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data || m.worker() == 0) return;
            if (old_writers_.count(info.publication_handle)) return;
            writers_.emplace(info.publication_handle, m.worker());
            newest_ = std::max(newest_, m.frame());
            if (m.frame() <= after) return;
            std::uint32_t& most = most_[m.worker()];
            most = std::max(most, m.bodies());
        });
    }
    /// From now on counts only the marks of writers not yet seen under `worker`'s id: a worker started
    /// again under it. (Frame numbers alone do not tell them apart: the killed one may have marked frames
    /// well past the last that a lagging client had seen when it was killed.)
    /// The newest frame any worker has marked, as of the last poll.
    std::uint64_t newest_frame() const { return newest_; }
    void forget(std::uint32_t worker) {
        poll(~std::uint64_t{0});
        for (const auto& [writer, id] : writers_)
            if (id == worker) old_writers_.insert(writer);
        most_.erase(worker);
    }
    std::uint32_t most(std::uint32_t worker) const {
        auto it = most_.find(worker);
        return it == most_.end() ? 0 : it->second;
    }

private:
    dds::Inbox inbox_;
    std::unique_ptr<dds::Participant> participant_;
    std::unique_ptr<dds::Reader<wire::WorkerFrame>> marks_;
    std::map<std::uint32_t, std::uint32_t> most_;
    std::map<dds::fdds::InstanceHandle_t, std::uint32_t> writers_;
    std::set<dds::fdds::InstanceHandle_t> old_writers_;
    std::uint64_t newest_ = 0;
};

TEST(Cluster, AWorkerRestartedUnderItsIdAndANewOneJoinTheRunningWorld) {
    // Worker 2 of 3 is killed, then started again under its id; later a fourth worker comes. Each asks to
    // join, is given sectors from a later frame, and builds them from their owners' whole samples: every
    // body stays exactly once, within the cluster's bound of lpss-sim, in every frame a client sees, and
    // both newcomers end up simulating bodies.
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 142;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 900;
    const auto [path, sim] = simulate_scene(scene, "joins", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "joins");
    ASSERT_TRUE(client);
    BodiesPerWorker owners(domain);
    auto cluster = start_cluster(path, domain, 3, kFrames, {"--block-size", "1"});
    ASSERT_TRUE(cluster.process);
    std::uint64_t killed_at = kFrames;
    // Worker 2's marks after the kill: the restarted one's.
    FrameRecorder seen(*client, [&] { owners.poll(killed_at + 10); });
    auto& frames = seen.frames;
    seen.gather(150, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    ASSERT_EQ(pkill("KILL", worker_process(domain, 2)), 0);
    killed_at = frames.rbegin()->first;
    owners.forget(2);
    seen.gather(killed_at + 60, std::chrono::seconds(60));
    auto restarted = start_worker(domain, 2, cluster.log_dir + ".joined2");
    ASSERT_TRUE(restarted);
    seen.gather(killed_at + 250, std::chrono::seconds(60));
    auto newcomer = start_worker(domain, 4, cluster.log_dir + ".joined4");
    ASSERT_TRUE(newcomer);
    seen.gather(kFrames, std::chrono::seconds(90));
    ASSERT_EQ(frames.rbegin()->first, kFrames);

    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "");
    std::printf(
        "worker 2 killed after frame %llu, restarted, and worker 4 added: %zu frames seen, largest "
        "difference from lpss-sim %.3g; most bodies simulated after they joined: worker 2 %u, worker 4 %u\n",
        static_cast<unsigned long long>(killed_at), frames.size(), worst, owners.most(2), owners.most(4));
    EXPECT_LE(worst, 1e-3);
    std::string unseen;
    for (std::uint64_t f = frames.begin()->first; f <= kFrames; ++f) {
        if (frames.count(f)) continue;
        std::uint64_t to = f;
        while (to < kFrames && !frames.count(to + 1))
            ++to;
        unseen += " " + std::to_string(f) + "-" + std::to_string(to);
        f = to;
    }
    std::printf("frames the client did not see:%s\n", unseen.empty() ? " none" : unseen.c_str());
    EXPECT_GE(frames.size(), kFrames * 9 / 10) << "the client saw most frames";
    EXPECT_GT(owners.most(2), 0u) << "the restarted worker simulates bodies";
    EXPECT_GT(owners.most(4), 0u) << "the new worker simulates bodies";
    expect_stopped_cleanly(cluster);
    EXPECT_TRUE(restarted->wait(std::chrono::seconds(20)));
    EXPECT_TRUE(newcomer->wait(std::chrono::seconds(20)));
    EXPECT_EQ(restarted->exit_code().value_or(-1), 0);
    EXPECT_EQ(newcomer->exit_code().value_or(-1), 0);
    expect_logged(cluster, "coordinator.log", "worker 2 asks to join");
    expect_logged(cluster, "coordinator.log", "worker 4 asks to join");
    for (int id : {2, 4}) {
        const std::string log = read_file(cluster.log_dir + ".joined" + std::to_string(id));
        EXPECT_NE(log.find("joins the cluster with sectors"), std::string::npos) << log;
        // A joiner reads the frame starts it missed in a burst, after newer samples: none of those is
        // refused as too far ahead (seen in the soak, the sector it was given among them).
        EXPECT_EQ(log.find("ahead of the newest started"), std::string::npos) << log;
    }
}

TEST(Cluster, AWorkerCutOffByItsLinkStopsPublishingAndJoinsAgainWhenTheLinkReturns) {
    // Four hosts on a bridge (network namespaces, each with its own /dev/shm) and the opt-in LAN profile: the
    // coordinator and its standby on host 1, a worker on each of hosts 2-4, this test's client on the bridge.
    // Host 3's link goes down for 4 s, then comes back. Cut off, worker 2 hears no coordinator for the lease
    // nor, as a standby follows, a frame start of the standby's within its time to take over, and stops
    // publishing; the coordinator finds it gone by its lease and the others take its sectors; back,
    // it joins again as a fresh worker. Every frame the client sees holds every body once, within the
    // cluster's bound of lpss-sim, and the world goes on during the cut.
    testing::FakeHosts hosts(4);
    if (!hosts.ok()) GTEST_SKIP() << "fake hosts need root and iproute2 (ip netns, veth, bridge)";
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 153;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 900;
    const auto [path, sim] = simulate_scene(scene, "cut", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    const std::string profile = LPSS_SOURCE_DIR "/deploy/profiles/lpss-lan.xml";
    const std::string logs = path + ".cut";
    ClientOptions options;
    options.domain = domain;
    options.name = "across";
    options.profile = profile;
    auto connected = Client::connect(options);
    ASSERT_TRUE(connected) << connected.error().message;
    auto client = std::move(connected).value();
    const std::vector<std::string> world = {path,
                                            "--workers",
                                            "3",
                                            "--frames",
                                            std::to_string(kFrames),
                                            "--domain",
                                            std::to_string(domain),
                                            "--profile",
                                            profile,
                                            "--realtime",
                                            "--block-size",
                                            "1",
                                            "--await-clients",
                                            "1"};
    auto with = [](std::vector<std::string> args, std::initializer_list<std::string> more) {
        args.insert(args.end(), more);
        return args;
    };
    auto standby = hosts.run(1, LPSS_COORDINATOR, with(world, {"--standby"}), logs + ".standby");
    auto coordinator =
        hosts.run(1, LPSS_COORDINATOR, with(world, {"--await-standby"}), logs + ".coordinator");
    std::vector<runtime::ChildProcess> workers;
    for (int w = 1; w <= 3; ++w) {
        auto worker =
            hosts.run(w + 1, LPSS_WORKER,
                      {"--id", std::to_string(w), "--domain", std::to_string(domain), "--profile", profile},
                      logs + ".worker" + std::to_string(w));
        ASSERT_TRUE(worker);
        workers.push_back(std::move(*worker));
    }
    ASSERT_TRUE(standby && coordinator);
    const testing::LogsOnFailure printed(logs);  // (the logs are beside the scene: "<scene>.cut.*")
    FrameRecorder seen(*client);
    auto& frames = seen.frames;
    seen.gather(150, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty()) << "no frame across the fake hosts";
    // About twice what the worker takes to know it is cut off: the lease and its grace (0.45 s) and the
    // standby's time to take over (CoordinatorWatch::kTakeover, 1.5 s).
    constexpr auto kCut = std::chrono::seconds(4);
    ASSERT_TRUE(hosts.cut(3));
    const auto cut = Clock::now();
    const std::uint64_t cut_at = frames.rbegin()->first;
    // During the cut, the others go on without worker 2.
    while (Clock::now() - cut < kCut) {
        seen.poll(std::chrono::milliseconds(5));
    }
    const std::uint64_t during = frames.rbegin()->first;
    ASSERT_TRUE(hosts.restore(3));
    seen.gather(kFrames, std::chrono::seconds(90));
    ASSERT_EQ(frames.rbegin()->first, kFrames);
    const double pause = seen.longest_wait(cut_at, cut);
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "");
    std::printf(
        "host 3 (worker 2) cut off after frame %llu for 4 s: frames went on to %llu during the cut; the "
        "longest "
        "wait for a frame %.3f s; %zu frames seen, largest difference from lpss-sim %.3g\n",
        static_cast<unsigned long long>(cut_at), static_cast<unsigned long long>(during), pause,
        frames.size(), worst);
    EXPECT_GT(during, cut_at + 60) << "the world goes on while a worker is cut off";
    EXPECT_LE(worst, 1e-3);
    EXPECT_TRUE(coordinator->wait(std::chrono::seconds(30)));
    EXPECT_EQ(coordinator->exit_code().value_or(-1), 0);
    for (runtime::ChildProcess& w : workers) {
        EXPECT_TRUE(w.wait(std::chrono::seconds(30)));
        EXPECT_EQ(w.exit_code().value_or(-1), 0);
    }
    const std::string coordinator_log = read_file(logs + ".coordinator");
    EXPECT_NE(coordinator_log.find("worker 2 is taken as gone during frame"), std::string::npos)
        << coordinator_log;
    EXPECT_NE(coordinator_log.find("its liveliness lease expired"), std::string::npos) << coordinator_log;
    // Cut off, it knew: it stopped publishing, and joined again once the link was back.
    const std::string cut_log = read_file(logs + ".worker2");
    const std::size_t knew = cut_log.find("no coordinator heard for its lease");
    ASSERT_NE(knew, std::string::npos) << cut_log;
    const std::size_t back = cut_log.find("a coordinator is heard again", knew);
    ASSERT_NE(back, std::string::npos) << cut_log;
    const std::size_t again = cut_log.find("joins again as a fresh worker", back);
    ASSERT_NE(again, std::string::npos) << cut_log;
    EXPECT_NE(cut_log.find("joins the cluster with sectors", again), std::string::npos) << cut_log;
}

TEST(Cluster, AKilledCoordinatorIsReplacedByItsStandbyAndNoFrameOrCommandIsLostOrRepeated) {
    // lpss-cluster starts a standby coordinator beside the coordinator. The coordinator is killed outright
    // mid-run while a client spawns bodies, one a frame: the standby takes over within a second, every frame
    // the client sees afterwards holds every body once within the cluster's bound of lpss-sim (no frame of
    // motion lost or stepped twice), and every spawn is answered once, applied or refused, and each applied
    // one is in the world once from the frame it was applied at.
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 146;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 600;
    const auto [path, sim] = simulate_scene(scene, "coordinator_dies", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "watcher");
    auto spawner = connect(domain, "spawner");
    ASSERT_TRUE(client && spawner);
    auto cluster = start_cluster(path, domain, 3, kFrames, {"--block-size", "1"});
    ASSERT_TRUE(cluster.process);
    FrameRecorder seen(*client);
    auto& frames = seen.frames;
    seen.gather(150, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    // Static spheres far from everything, so that the rest of the world stays lpss-sim's: 30 spawns about
    // a frame apart, the coordinator killed after the tenth.
    std::vector<std::pair<BodyId, std::uint64_t>> spawns;  // id, request
    const std::string coordinator = testing::primary_coordinator_process(domain);
    std::uint64_t killed_at = 0;
    Clock::time_point killed;
    for (int n = 0; n < 30; ++n) {
        BodyDesc b = scenes::sphere_body(1000 + n, 0.25, 0.0, Eigen::Vector3d(50 * kL, 3.0 * n, 0));
        spawns.emplace_back(b.id, spawner->spawn(b));
        spawner->poll(std::chrono::milliseconds(16));
        if (n == 10) {
            killed = Clock::now();
            killed_at = frames.rbegin()->first;
            ASSERT_EQ(pkill("KILL", coordinator), 0);
        }
        seen.poll(std::chrono::milliseconds(0));
    }
    seen.gather(kFrames, std::chrono::seconds(60));
    ASSERT_GT(frames.rbegin()->first, killed_at + 200) << "frames go on after the coordinator's death";
    expect_ended_cleanly(cluster);

    const double pause = seen.longest_wait(killed_at, killed);
    // Each spawn answered once: applied at a frame, or refused with a reason.
    std::map<BodyId, std::uint64_t> applied_at;
    for (const auto& [id, request] : spawns) {
        const auto outcome = spawner->wait_outcome(request, std::chrono::seconds(5));
        ASSERT_TRUE(outcome) << "spawn of body " << id << " never answered";
        if (outcome->applied) {
            applied_at[id] = outcome->frame;
        } else {
            EXPECT_FALSE(outcome->reason.empty());
        }
    }
    EXPECT_GE(applied_at.size(), 25u) << "spawns are refused only for a reason";
    const SectorGrid grid(kL);
    double worst = 0.0;
    std::uint64_t checked_after = 0;
    for (const auto& [f, frame] : frames) {
        const auto& expected = sim.at(f);
        std::size_t spawned = 0;
        std::set<BodyId> seen;
        for (const BodyView& b : frame.bodies) {
            ASSERT_TRUE(seen.insert(b.id).second) << "frame " << f << ": body " << b.id << " twice";
            if (b.id >= 1000) {
                ++spawned;
                ASSERT_TRUE(applied_at.count(b.id)) << "frame " << f << ": body " << b.id << " not applied";
                EXPECT_GE(f, applied_at.at(b.id)) << "body " << b.id << " before it was spawned";
                continue;
            }
            ASSERT_TRUE(expected.count(b.id)) << "frame " << f << " body " << b.id;
            worst = std::max(
                worst, (grid.to_global(b.position) - grid.to_global(expected.at(b.id).position)).norm());
        }
        ASSERT_EQ(frame.bodies.size() - spawned, expected.size()) << "frame " << f;
        std::size_t due = 0;
        for (const auto& [id, at] : applied_at)
            due += at <= f ? 1 : 0;
        EXPECT_EQ(spawned, due) << "frame " << f << ": every body spawned by then, once";
        if (f > killed_at) ++checked_after;
    }
    std::printf(
        "the coordinator killed after frame %llu: the longest wait for a frame %.3f s; %llu frames after it "
        "seen, largest difference from lpss-sim %.3g; %zu of 30 spawns applied\n",
        static_cast<unsigned long long>(killed_at), pause, static_cast<unsigned long long>(checked_after),
        worst, applied_at.size());
    EXPECT_LE(worst, 1e-3);
    EXPECT_LT(pause, 1.0) << "the world goes on within a second of the kill";
    EXPECT_GE(checked_after, (kFrames - killed_at) * 9 / 10) << "the client saw most frames after the kill";
    expect_logged(cluster, "standby.log", "taking over under term 2");
}

TEST(Cluster, AStandbyPausedPastItsLeaseIsNamedAgainAndStillTakesOver) {
    // The standby coordinator is stopped (SIGSTOP) past its lease, as a loaded machine or a lost beat
    // can make it look: the coordinator goes on without it and, when it comes back, names it again in its
    // frame starts (it read every start meanwhile). Then the coordinator is killed: the standby takes over,
    // and every frame the client sees holds every body once, within the cluster's bound of lpss-sim.
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 149;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 900;
    const auto [path, sim] = simulate_scene(scene, "standby_paused", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "watcher");
    ASSERT_TRUE(client);
    auto cluster = start_cluster(path, domain, 2, kFrames, {"--realtime"});
    ASSERT_TRUE(cluster.process);
    std::map<std::uint64_t, WorldFrame> frames;
    collect_into(*client, frames, 60, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    const std::string standby = testing::standby_process(domain);
    const std::string coordinator = testing::primary_coordinator_process(domain);
    // Stopped until the coordinator drops it (its lease past and confirmed), and thawed at once: the
    // coordinator writes a frame start or two without it, fewer than its writer keeps (8), so the standby
    // can still read them all. (A fixed pause is either short of the lease on a slow machine or lets more
    // than 8 starts go by.)
    ASSERT_EQ(pkill("STOP", standby), 0);
    const std::string dropped = "standby coordinator 2 missed its liveliness lease";
    for (auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
         read_file(cluster.log_dir + "/coordinator.log").find(dropped) == std::string::npos &&
         std::chrono::steady_clock::now() < until;)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ASSERT_EQ(pkill("CONT", standby), 0);
    const std::uint64_t resumed_at = frames.rbegin()->first;
    collect_into(*client, frames, resumed_at + 120, std::chrono::seconds(20));
    const std::string primary_log = read_file(cluster.log_dir + "/coordinator.log");
    EXPECT_NE(primary_log.find("standby coordinator 2 missed its liveliness lease"), std::string::npos)
        << "the pause went past the standby's lease";
    EXPECT_NE(primary_log.find("standby coordinator 2 is back"), std::string::npos) << primary_log;
    const std::uint64_t killed_at = frames.rbegin()->first;
    ASSERT_EQ(pkill("KILL", coordinator), 0);
    collect_into(*client, frames, kFrames, std::chrono::seconds(60));
    expect_ended_cleanly(cluster);
    ASSERT_GT(frames.rbegin()->first, killed_at + 100) << "frames go on after the coordinator's death";
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "") << "logs: " << cluster.log_dir;
    const auto after = static_cast<std::size_t>(std::distance(frames.upper_bound(killed_at), frames.end()));
    std::printf(
        "standby paused after frame %llu, the coordinator killed after frame %llu; %zu frames seen "
        "after it, largest difference from lpss-sim %.3g\n",
        static_cast<unsigned long long>(resumed_at), static_cast<unsigned long long>(killed_at), after,
        worst);
    EXPECT_LE(worst, 1e-3);
    expect_logged(cluster, "standby.log", "taking over under term 2");
}

TEST(Cluster, AKilledStandbyCostsAPauseAndNoBody) {
    // The standby coordinator killed outright in a paced world: the coordinator finds it gone by its
    // acknowledgements' lease, writes its latest frame start again without naming it, and goes on without
    // a standby. The client sees a pause of about the lease, then every frame, every body once.
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 190;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 480;
    const auto [path, sim] = simulate_scene(scene, "standby_killed", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "watcher");
    ASSERT_TRUE(client);
    auto cluster = start_cluster(path, domain, 2, kFrames);
    ASSERT_TRUE(cluster.process);
    FrameRecorder seen(*client);
    auto& frames = seen.frames;
    seen.gather(120, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    const auto killed = Clock::now();
    ASSERT_EQ(pkill("KILL", testing::standby_process(domain)), 0);
    const std::uint64_t killed_at = frames.rbegin()->first;
    seen.gather(kFrames, std::chrono::seconds(60));
    expect_ended_cleanly(cluster);
    ASSERT_EQ(frames.rbegin()->first, kFrames) << "the world ran to its end";
    const double pause = seen.longest_wait(killed_at, killed);
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "") << "logs: " << cluster.log_dir;
    const auto after = static_cast<std::size_t>(std::distance(frames.upper_bound(killed_at), frames.end()));
    std::printf(
        "standby killed after frame %llu: the longest wait for a frame %.3f s; %zu frames seen after it, "
        "largest difference from lpss-sim %.3g\n",
        static_cast<unsigned long long>(killed_at), pause, after, worst);
    EXPECT_LE(worst, 1e-3);
    EXPECT_GE(after, kFrames - killed_at - 10) << "the client saw the frames after the kill";
    // The lease (0.3 s) confirmed (0.15 s more) and the start written again; 1.5 s leaves room for a
    // loaded machine, and is far from the 5 s a worker waits before it takes the coordinator as gone.
    EXPECT_LT(pause, 1.5);
    expect_logged(cluster, "coordinator.log", "standby coordinator 2 missed its liveliness lease");
    EXPECT_NE(read_file(cluster.log_dir + ".out").find("the standby coordinator ended"), std::string::npos);
}

TEST(Cluster, AStandbyKilledBeforeFrameOneIsStartedAgainAndCanTakeOver) {
    // lpss-cluster's standby killed as it starts, long before frame 1: the coordinator would hold frame 1
    // for a standby's hello (--standby-wait-s, 60 s here), so lpss-cluster starts the standby again. The
    // new one says hello, frame 1 comes at once, and it is a standby indeed: the coordinator killed later,
    // it takes over and the world runs to its end, every body once.
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 191;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 480;
    const auto [path, sim] = simulate_scene(scene, "standby_restarted", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "watcher");
    ASSERT_TRUE(client);
    const auto started = Clock::now();
    auto cluster = start_cluster(path, domain, 2, kFrames, {"--standby-wait-s", "60"});
    ASSERT_TRUE(cluster.process);
    // The standby is lpss-cluster's first child: killed as soon as it is seen (it says hello only once it
    // holds the world's first state, which the coordinator sends after reading the scene).
    bool killed = false;
    for (auto until = Clock::now() + std::chrono::seconds(10); !killed && Clock::now() < until;) {
        killed = pkill("KILL", testing::standby_process(domain) + " 2>/dev/null") == 0;
        if (!killed) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(killed) << "the standby was seen";
    std::map<std::uint64_t, WorldFrame> frames;
    collect_into(*client, frames, 60, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty()) << "logs: " << cluster.log_dir;
    const double first_frames = std::chrono::duration<double>(Clock::now() - started).count();
    EXPECT_LT(first_frames, 30.0) << "frame 1 did not wait out the standby wait (60 s)";
    const std::string out = read_file(cluster.log_dir + ".out");
    EXPECT_NE(out.find("the standby coordinator ended before frame 1 (exit 137: killed by SIGKILL"),
              std::string::npos)
        << out;
    const std::uint64_t killed_at = frames.rbegin()->first;
    ASSERT_EQ(pkill("KILL", testing::primary_coordinator_process(domain)), 0);
    collect_into(*client, frames, kFrames, std::chrono::seconds(60));
    expect_ended_cleanly(cluster);
    ASSERT_EQ(frames.rbegin()->first, kFrames) << "the world ran to its end after the coordinator's death";
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "") << "logs: " << cluster.log_dir;
    std::printf(
        "standby killed at its start and started again; frame 60 seen %.2f s after the start; the "
        "coordinator "
        "killed after frame %llu; largest difference from lpss-sim %.3g\n",
        first_frames, static_cast<unsigned long long>(killed_at), worst);
    EXPECT_LE(worst, 1e-3);
    expect_logged(cluster, "standby.1.log", "taking over under term 2");
}

TEST(Cluster, ACoordinatorAndAWorkerKilledTogetherLoseNoBody) {
    // A double fault: the coordinator and worker 2 killed within milliseconds, in a paced world. The standby
    // takes over and then finds worker 2 gone: its sectors go to the others, and every frame the client sees
    // holds every body once, within the cluster's bound of lpss-sim.
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 151;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 600;
    const auto [path, sim] = simulate_scene(scene, "double_fault", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "watcher");
    ASSERT_TRUE(client);
    auto cluster = start_cluster(path, domain, 3, kFrames, {"--block-size", "1", "--realtime"});
    ASSERT_TRUE(cluster.process);
    std::map<std::uint64_t, WorldFrame> frames;
    collect_into(*client, frames, 150, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    const std::string coordinator = testing::primary_coordinator_process(domain);
    const std::uint64_t killed_at = frames.rbegin()->first;
    // The coordinator first: no frame starts after it, so the worker, killed a moment later, has ended the
    // frame the standby takes over from (the path where its sectors are restored as it left them).
    ASSERT_EQ(pkill("KILL", coordinator), 0);
    ASSERT_EQ(pkill("KILL", worker_process(domain, 2)), 0);
    collect_into(*client, frames, kFrames, std::chrono::seconds(60));
    EXPECT_TRUE(cluster.process->wait(std::chrono::seconds(30)));
    ASSERT_GT(frames.rbegin()->first, killed_at + 100)
        << "frames go on after the double fault; logs: " << cluster.log_dir;
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "") << "logs: " << cluster.log_dir;
    const auto after = static_cast<std::size_t>(std::distance(frames.upper_bound(killed_at), frames.end()));
    std::printf(
        "the coordinator and worker 2 killed after frame %llu; %zu frames seen after it, largest "
        "difference from lpss-sim %.3g\n",
        static_cast<unsigned long long>(killed_at), after, worst);
    EXPECT_LE(worst, 1e-3);
    const std::string text = read_file(cluster.log_dir + "/standby.log");
    EXPECT_NE(text.find("taking over under term 2"), std::string::npos) << text;
    EXPECT_NE(text.find("worker 2 is gone"), std::string::npos) << text;
    // Only worker 2: a live worker's lease reported lapsed in the instant the dead one's ran out is not
    // taken for a death (seen before lapses were confirmed: worker 3 taken as gone too, 3.74 off lpss-sim).
    EXPECT_EQ(text.find("worker 1 is gone"), std::string::npos) << text;
    EXPECT_EQ(text.find("worker 3 is gone"), std::string::npos) << text;
}

/// The coordinator stopped while it reads the scene, before any worker has a word of the world, then
/// killed (`killed`) or let go on past its lease. Its standby reads the scene itself and starts the world
/// under term 2 (a million bodies take half a minute to read; a kill then ended the world); a coordinator let
/// go on stops once it reads that (exit 6, which lpss-cluster takes for a takeover). Every frame the client
/// sees holds every body once, within the cluster's bound of lpss-sim.
void coordinator_gone_while_it_reads_the_scene(bool killed, int domain) {
    Scene scene = crossing_scene_with_far_balls();
    // 20,000 static boxes far from the rest, so that reading the scene takes a while.
    for (int n = 0; n < 20000; ++n) {
        BodyDesc box = scenes::box_body(10000 + n, Eigen::Vector3d::Constant(0.5), 0.0,
                                        Eigen::Vector3d(200 * kL + 3.0 * (n % 200), 0, 3.0 * (n / 200)));
        scene.bodies.push_back(box);
    }
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 150;
    auto [path, sim] = simulate_scene(scene, "coordinator_gone_reading", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    // The client follows the region of the moving bodies, not the boxes (20,000 bodies a frame kept a client
    // under AddressSanitizer 28 frames behind for two minutes): lpss-sim's frames without them.
    for (auto& [f, bodies] : sim) {
        for (auto it = bodies.begin(); it != bodies.end();)
            it = it->first >= 10000 ? bodies.erase(it) : std::next(it);
    }
    auto client = connect(domain, "watcher", Region{{-8, -8, -8}, {100, 8, 8}});
    ASSERT_TRUE(client);
    auto cluster = start_cluster(path, domain, 2, kFrames, {"--block-size", "1"});
    ASSERT_TRUE(cluster.process);
    // Stopped once it reads the scene and the standby says it would notice its end (it has its first word
    // and has heard its writers alive): nothing of the world was sent.
    const std::string coordinator = testing::primary_coordinator_process(domain);
    const std::string log = cluster.log_dir + "/coordinator.log";
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (
        (read_file(log).find("coordinator: loading") == std::string::npos ||
         read_file(cluster.log_dir + "/standby.log").find("follows the coordinator") == std::string::npos) &&
        std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ASSERT_EQ(pkill("STOP", coordinator), 0);
    const std::string before = read_file(log);
    ASSERT_NE(before.find("coordinator: loading"), std::string::npos) << before;
    ASSERT_EQ(before.find("read and checked"), std::string::npos) << "stopped too late: " << before;
    if (killed) {
        ASSERT_EQ(pkill("KILL", coordinator), 0);
    } else {
        // Past its lease (0.3 s, confirmed 0.15 s later), then on again.
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        ASSERT_EQ(pkill("CONT", coordinator), 0);
    }
    std::map<std::uint64_t, WorldFrame> frames;
    collect_into(*client, frames, kFrames, std::chrono::seconds(120));
    expect_ended_cleanly(cluster);
    ASSERT_FALSE(frames.empty()) << "logs: " << cluster.log_dir;
    EXPECT_EQ(frames.rbegin()->first, kFrames) << "logs: " << cluster.log_dir;
    EXPECT_GE(frames.size(), kFrames * 9 / 10) << "the client saw most frames";
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "") << "logs: " << cluster.log_dir;
    EXPECT_LE(worst, 1e-3);
    expect_logged(cluster, "standby.log", "starts the world under term 2");
    if (!killed) {
        const std::string after = read_file(log);
        EXPECT_NE(after.find("started the world while this one read the scene"), std::string::npos) << after;
        EXPECT_EQ(after.find("sectors sent"), std::string::npos) << "it sent the world too: " << after;
    }
    std::printf(
        "the coordinator %s while reading the scene: %zu frames seen, largest difference from "
        "lpss-sim %.3g\n",
        killed ? "killed" : "paused past its lease", frames.size(), worst);
}

TEST(Cluster, ACoordinatorKilledWhileItReadsTheSceneIsReplacedByItsStandbyWhichStartsTheWorld) {
    coordinator_gone_while_it_reads_the_scene(true, 179);
}

TEST(Cluster, ACoordinatorPausedPastItsLeaseWhileItReadsTheSceneYieldsToItsStandby) {
    coordinator_gone_while_it_reads_the_scene(false, 180);
}

TEST(Cluster, ACoordinatorPausedPastItsLeaseAfterItSentTheFirstStateKeepsItsStandby) {
    // The coordinator has sent the world's first state and waits, before frame 1, for a client; it is paused
    // past its lease (as a loaded machine starves it: seen under AddressSanitizer). The standby waits for it
    // to come back instead of stopping (it could take over from nothing: no frame start came), and so still
    // takes over when the coordinator is killed later. Before, it stopped at the lapse and the world ran
    // without a standby: the kill ended it.
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 184;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 300;
    const auto [path, sim] = simulate_scene(scene, "coordinator_paused_after_first_state", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto cluster = start_cluster(path, domain, 2, kFrames, {"--block-size", "1", "--await-clients", "1"});
    ASSERT_TRUE(cluster.process);
    const std::string coordinator = testing::primary_coordinator_process(domain);
    const std::string coordinator_log = cluster.log_dir + "/coordinator.log";
    const std::string standby_log = cluster.log_dir + "/standby.log";
    // Its first state sent, it says every 5 s that frame 1 waits for the client.
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (read_file(coordinator_log).find("frame 1 waits for 1 client") == std::string::npos &&
           std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_NE(read_file(coordinator_log).find("frame 1 waits for 1 client"), std::string::npos)
        << "logs: " << cluster.log_dir;
    // Past its lease (0.3 s, confirmed 0.15 s later), then on again.
    ASSERT_EQ(pkill("STOP", coordinator), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    ASSERT_EQ(pkill("CONT", coordinator), 0);
    const auto back_by = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (read_file(standby_log).find("follows it again") == std::string::npos &&
           std::chrono::steady_clock::now() < back_by)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const std::string waited = read_file(standby_log);
    EXPECT_NE(waited.find("lease lapsed while it sent the world's first state"), std::string::npos)
        << "the pause was past the lease: " << waited;
    EXPECT_NE(waited.find("follows it again"), std::string::npos) << waited;
    // Frame 1 starts with the client; the coordinator is killed in the run.
    auto client = connect(domain, "watcher");
    ASSERT_TRUE(client);
    std::map<std::uint64_t, WorldFrame> frames;
    collect_into(*client, frames, 100, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty()) << "logs: " << cluster.log_dir;
    const std::uint64_t killed_at = frames.rbegin()->first;
    ASSERT_LT(killed_at + 100, kFrames) << "time left to run after the takeover";
    ASSERT_EQ(pkill("KILL", coordinator), 0);
    collect_into(*client, frames, kFrames, std::chrono::seconds(60));
    expect_ended_cleanly(cluster);
    ASSERT_EQ(frames.rbegin()->first, kFrames) << "logs: " << cluster.log_dir;
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "") << "logs: " << cluster.log_dir;
    EXPECT_LE(worst, 1e-3);
    expect_logged(cluster, "standby.log", "taking over under term 2");
    std::printf(
        "the coordinator paused 1.5 s after its first state, killed after frame %llu: %zu frames seen, "
        "largest difference from lpss-sim %.3g\n",
        static_cast<unsigned long long>(killed_at), frames.size(), worst);
}

TEST(Cluster, AStandbyTakingOverAfterAWorkerRestartedTakesNoLiveWorkerAsGone) {
    // Worker 2 is killed and started again under its id, and joins; then the coordinator is killed. The
    // standby had noted worker 2's death too, and the deaths it notes while standing by are the
    // coordinator's to handle: taking over, it must not take the worker running under that id now (nor
    // any other) as gone. Seen before: in every soak, the standby took every worker killed earlier in the
    // run as gone at its takeover, and each stopped and joined again.
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 163;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 900;
    const auto [path, sim] = simulate_scene(scene, "restart_then_takeover", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "watcher");
    ASSERT_TRUE(client);
    BodiesPerWorker owners(domain);
    auto cluster = start_cluster(path, domain, 3, kFrames, {"--block-size", "1", "--realtime"});
    ASSERT_TRUE(cluster.process);
    std::uint64_t killed_at = kFrames;
    FrameRecorder seen(*client, [&] { owners.poll(killed_at + 10); });
    auto& frames = seen.frames;
    seen.gather(120, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    ASSERT_EQ(pkill("KILL", worker_process(domain, 2)), 0);
    killed_at = frames.rbegin()->first;
    owners.forget(2);
    seen.gather(killed_at + 60, std::chrono::seconds(60));
    auto restarted = start_worker(domain, 2, cluster.log_dir + ".restarted2");
    ASSERT_TRUE(restarted);
    // Until the restarted worker has simulated bodies (the standby has read its marks of frames too).
    const auto joined_by = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (owners.most(2) == 0 && std::chrono::steady_clock::now() < joined_by)
        seen.gather(frames.rbegin()->first + 10, std::chrono::seconds(10));
    ASSERT_GT(owners.most(2), 0u) << "the restarted worker joined; logs: " << cluster.log_dir;
    seen.gather(frames.rbegin()->first + 30, std::chrono::seconds(10));
    const std::uint64_t coordinator_killed_at = frames.rbegin()->first;
    ASSERT_LT(coordinator_killed_at + 100, kFrames) << "time left to run after the takeover";
    const std::string coordinator = testing::primary_coordinator_process(domain);
    ASSERT_EQ(pkill("KILL", coordinator), 0);
    seen.gather(kFrames, std::chrono::seconds(60));
    EXPECT_TRUE(cluster.process->wait(std::chrono::seconds(30)));
    EXPECT_TRUE(restarted->wait(std::chrono::seconds(20)));
    ASSERT_EQ(frames.rbegin()->first, kFrames) << "logs: " << cluster.log_dir;
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "") << "logs: " << cluster.log_dir;
    std::printf(
        "worker 2 killed after frame %llu and started again, the coordinator killed after frame %llu; "
        "largest "
        "difference from lpss-sim %.3g\n",
        static_cast<unsigned long long>(killed_at), static_cast<unsigned long long>(coordinator_killed_at),
        worst);
    EXPECT_LE(worst, 1e-3);
    const std::string text = read_file(cluster.log_dir + "/standby.log");
    const auto took_over = text.find("taking over under term 2");
    ASSERT_NE(took_over, std::string::npos) << text;
    EXPECT_EQ(text.find("taken as gone", took_over), std::string::npos) << text;
    EXPECT_EQ(text.find("is gone", took_over), std::string::npos) << text;
}

TEST(Cluster, AWorkerRestartedJustBeforeTheCoordinatorDiesIsLetInByTheStandbyAndRuns) {
    // Worker 2 is killed, and the coordinator takes it as gone; worker 2 is started again and the
    // coordinator killed at once, before the new worker can ask to join. The standby, which had noted the
    // old worker 2's lapse too, takes over and lets the new one in: the old lapse is not the new one's.
    // Seen under AddressSanitizer: the standby took the new worker 2 as gone in the frame it let it in
    // ("its liveliness lease expired, 0.00 s into the frame").
    const Scene scene = crossing_scene_with_far_balls();
    const int domain = 177;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 900;
    const auto [path, sim] = simulate_scene(scene, "restart_at_takeover", kFrames);
    ASSERT_EQ(sim.size(), kFrames + 1);
    auto client = connect(domain, "watcher");
    ASSERT_TRUE(client);
    BodiesPerWorker owners(domain);
    auto cluster = start_cluster(path, domain, 3, kFrames, {"--block-size", "1", "--realtime"});
    ASSERT_TRUE(cluster.process);
    FrameRecorder seen(*client, [&] { owners.poll(0); });
    auto& frames = seen.frames;
    seen.gather(120, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    ASSERT_EQ(pkill("KILL", worker_process(domain, 2)), 0);
    owners.forget(2);
    // A second at 60 frames a second: the lease (0.4 s) has lapsed for both coordinators by then.
    seen.gather(frames.rbegin()->first + 60, std::chrono::seconds(60));
    auto restarted = start_worker(domain, 2, cluster.log_dir + ".restarted2");
    ASSERT_TRUE(restarted);
    ASSERT_EQ(pkill("KILL", testing::primary_coordinator_process(domain)), 0);
    seen.gather(kFrames, std::chrono::seconds(60));
    EXPECT_TRUE(cluster.process->wait(std::chrono::seconds(30)));
    EXPECT_TRUE(restarted->wait(std::chrono::seconds(20)));
    ASSERT_EQ(frames.rbegin()->first, kFrames) << "logs: " << cluster.log_dir;
    double worst = 0.0;
    ASSERT_EQ(against_sim(frames, sim, worst), "") << "logs: " << cluster.log_dir;
    EXPECT_LE(worst, 1e-3);
    const std::string primary = read_file(cluster.log_dir + "/coordinator.log");
    ASSERT_NE(primary.find("worker 2 is gone"), std::string::npos) << primary;
    EXPECT_EQ(primary.find("asks to join"), std::string::npos)
        << "the coordinator died before the ask" << primary;
    const std::string text = read_file(cluster.log_dir + "/standby.log");
    const auto took_over = text.find("taking over under term 2");
    ASSERT_NE(took_over, std::string::npos) << text;
    // What makes the case: the standby noted the old worker 2's lapse before it took over, and let the new
    // one in (its ask is read after the takeover, unless the new worker read a start of the coordinator's
    // before it died).
    EXPECT_LT(text.find("worker 2 missed its liveliness lease"), took_over) << text;
    EXPECT_NE(text.find("worker 2 asks to join"), std::string::npos) << text;
    EXPECT_EQ(text.find("is gone", took_over), std::string::npos) << text;
    const std::string worker_log = read_file(cluster.log_dir + ".restarted2");
    EXPECT_EQ(worker_log.find("joins again as a fresh worker"), std::string::npos) << worker_log;
    EXPECT_GT(owners.most(2), 0u) << "the restarted worker simulates bodies; logs: " << cluster.log_dir;
    std::printf(
        "worker 2 started again as the coordinator was killed: let in by the standby, %u bodies at most; "
        "largest difference from lpss-sim %.3g\n",
        owners.most(2), worst);
}

TEST(Cluster, AWorkerJoiningAfterAStandbyTookOverGetsThePlanesAndRuns) {
    // Durable samples live in their writer: the ground plane's description went with the killed
    // coordinator's, and a worker that joined after the standby took over waited for ever for the plane a
    // frame start counts (tests/tools/takeover_during_hold.sh found it: it never ran a frame). The standby
    // now writes the planes again when it takes over. The example scene has a ground plane.
    const int domain = 176;
    const testing::DomainCleanup cleanup(domain);
    constexpr std::uint64_t kFrames = 600;
    auto client = connect(domain, "after-takeover");
    ASSERT_TRUE(client);
    auto cluster = start_cluster(LPSS_SOURCE_DIR "/deploy/scenes/far_stacks.textproto", domain, 2, kFrames,
                                 {"--await-clients", "1"});
    ASSERT_TRUE(cluster.process);
    std::map<std::uint64_t, WorldFrame> frames;
    collect_into(*client, frames, 100, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    const std::string primary = testing::primary_coordinator_process(domain);
    ASSERT_EQ(pkill("KILL", primary), 0);
    const std::uint64_t killed_at = frames.rbegin()->first;
    collect_into(*client, frames, killed_at + 60, std::chrono::seconds(60));
    auto newcomer = start_worker(domain, 3, cluster.log_dir + ".joined3");
    ASSERT_TRUE(newcomer);
    collect_into(*client, frames, kFrames, std::chrono::seconds(90));
    EXPECT_EQ(frames.rbegin()->first, kFrames) << "the world goes on to its last frame";
    const std::size_t bodies = frames.begin()->second.bodies.size();
    for (const auto& [f, frame] : frames)
        ASSERT_EQ(frame.bodies.size(), bodies) << "frame " << f;
    expect_stopped_cleanly(cluster);
    EXPECT_TRUE(newcomer->wait(std::chrono::seconds(20)));
    const std::string log = read_file(cluster.log_dir + ".joined3");
    EXPECT_NE(log.find("joins the cluster with sectors"), std::string::npos) << log;
    expect_logged(cluster, "standby.log", "taking over");
}

TEST(Cluster, WorkersSayTheCoordinatorIsGoneAndStop) {
    // Without a standby coordinator (none is started here), when the coordinator is killed mid-run, the
    // workers must not wait in silence for ever. They hear no coordinator for its lease (0.3 s), say so,
    // stop publishing, wait for one to come back, and stop after their coordinator wait (1 s here) with
    // exit code 3.
    const int domain = 140;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(crossing_scene(), "orphans");
    const std::string logs = path + ".orphans";
    testing::remove_stale(logs);
    std::vector<runtime::ChildProcess> workers;
    for (int w = 1; w <= 2; ++w) {
        auto worker = runtime::ChildProcess::start(
            LPSS_WORKER,
            {"--id", std::to_string(w), "--domain", std::to_string(domain), "--coordinator-wait-s", "1"},
            logs + ".worker" + std::to_string(w));
        ASSERT_TRUE(worker);
        workers.push_back(std::move(*worker));
    }
    auto coordinator = runtime::ChildProcess::start(
        LPSS_COORDINATOR, {path, "--workers", "2", "--domain", std::to_string(domain), "--realtime"},
        logs + ".coordinator");
    ASSERT_TRUE(coordinator);
    auto client = connect(domain, "orphans");
    ASSERT_TRUE(client);
    const auto frames = collect(*client, 60, std::chrono::seconds(60));
    ASSERT_FALSE(frames.empty());
    ASSERT_GE(frames.rbegin()->first, 60u) << "the world ran";
    ::kill(coordinator->pid(), SIGKILL);
    const auto killed = std::chrono::steady_clock::now();
    for (runtime::ChildProcess& worker : workers) {
        EXPECT_TRUE(worker.wait(std::chrono::seconds(60))) << "a worker still waits a minute on";
        EXPECT_EQ(worker.exit_code().value_or(-1), 3);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
    for (int w = 1; w <= 2; ++w) {
        const std::string text = read_file(logs + ".worker" + std::to_string(w));
        EXPECT_NE(text.find("no coordinator heard for its lease"), std::string::npos) << text;
        EXPECT_NE(text.find("no coordinator came back"), std::string::npos) << text;
    }
    EXPECT_LT(seconds, 10.0) << "found gone by the lease, not by DDS dropping its participant (20 s)";
    std::printf("the coordinator killed after frame %llu: both workers stopped %.1f s later\n",
                static_cast<unsigned long long>(frames.rbegin()->first), seconds);
}

TEST(Cluster, AStandbyNeverHeardDoesNotHoldFrameOneBackForEver) {
    // A coordinator told to await a standby, whose standby is gone before its hello reached it (here: none
    // is started; seen with lpss-cluster's standby killed at once, and under load): frame 1 waits for the
    // standby wait (2 s here, 20 s by default), then the world starts without one, and says so. Before, it
    // waited for ever.
    const int domain = 183;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(crossing_scene(), "standby-never-heard");
    const std::string logs = path + ".standby-never-heard";
    testing::remove_stale(logs);
    auto worker = runtime::ChildProcess::start(LPSS_WORKER, {"--id", "1", "--domain", std::to_string(domain)},
                                               logs + ".worker1");
    ASSERT_TRUE(worker);
    const auto started = std::chrono::steady_clock::now();
    auto coordinator =
        runtime::ChildProcess::start(LPSS_COORDINATOR,
                                     {path, "--workers", "1", "--domain", std::to_string(domain),
                                      "--await-standby", "--standby-wait-s", "2"},
                                     logs + ".coordinator");
    ASSERT_TRUE(coordinator);
    auto client = connect(domain, "standby-never-heard");
    ASSERT_TRUE(client);
    const auto frames = collect(*client, 30, std::chrono::seconds(60));
    const std::string text = read_file(logs + ".coordinator");
    ASSERT_FALSE(frames.empty()) << text;
    EXPECT_GE(frames.rbegin()->first, 30u) << "the world ran";
    EXPECT_NE(text.find("no standby coordinator said it stands by within 2 s: the world starts without one"),
              std::string::npos)
        << text;
    EXPECT_GE(std::chrono::steady_clock::now() - started, std::chrono::seconds(2)) << "frame 1 waited";
}

TEST(Cluster, ARecorderAndAClientStartedBeforeTheClusterSeeFrameOne) {
    // Started before the cluster, both are there when the world's first state is written: they follow it
    // from frame 1 on, every frame. (Before, a reader asked the workers for an inventory and started from
    // the frame that carried the answer: frame 150 in one run.) The cluster awaits them: without
    // --await-clients a worker may write frame 1 before its writers have matched a reader that is there
    // (DDS discovery under load; seen in 2 of 20 runs beside a parallel suite). Real time: an unpaced
    // cluster can outrun a reader by more than the eight frames writers keep.
    const int domain = 137;
    const testing::DomainCleanup cleanup(domain);
    const Scene scene = crossing_scene();
    const std::string path = write_scene(scene, "early");
    constexpr std::uint64_t kFrames = 180;
    const std::string csv = path + ".watch.csv";
    std::filesystem::remove(csv);
    auto recorder = runtime::ChildProcess::start(LPSS_WATCH,
                                                 {"--domain", std::to_string(domain), "--csv", csv,
                                                  "--frames", std::to_string(kFrames), "--wait-s", "60"},
                                                 path + ".watch.out");
    ASSERT_TRUE(recorder);
    auto client = connect(domain, "early");
    ASSERT_TRUE(client);
    std::this_thread::sleep_for(std::chrono::seconds(2));
    auto cluster = start_cluster(path, domain, 3, kFrames, {"--block-size", "1", "--await-clients", "2"});
    ASSERT_TRUE(cluster.process);
    auto frames = collect(*client, kFrames, std::chrono::seconds(60));
    expect_stopped_cleanly(cluster);
    ASSERT_FALSE(frames.empty());
    EXPECT_EQ(frames.begin()->first, 1u) << "the client's first frame";
    EXPECT_EQ(frames.size(), kFrames) << "every frame, 1 to " << kFrames;
    for (const auto& [f, frame] : frames)
        ASSERT_EQ(frame.bodies.size(), scene.bodies.size()) << "frame " << f;
    ASSERT_TRUE(recorder->wait(std::chrono::seconds(30))) << read_file(path + ".watch.out");
    EXPECT_EQ(recorder->exit_code(), 0) << read_file(path + ".watch.out");
    // The recorder's CSV: a row per body per frame, from frame 1 on.
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);
    std::map<std::uint64_t, std::size_t> rows;
    while (std::getline(in, line))
        ++rows[std::stoull(line.substr(0, line.find(',')))];
    ASSERT_FALSE(rows.empty()) << read_file(path + ".watch.out");
    EXPECT_EQ(rows.begin()->first, 1u) << "the recorder's first frame";
    EXPECT_EQ(rows.size(), kFrames) << "every frame recorded";
    for (const auto& [f, count] : rows)
        ASSERT_EQ(count, scene.bodies.size()) << "frame " << f;
}

TEST(Cluster, FrameOneWaitsForTheClientsItWasToldToAwait) {
    // --await-clients 1: the cluster loads and sends its first state, then waits; a client that comes 3 s
    // later still sees frame 1, and every frame after it (in real time: see the test above).
    const int domain = 138;
    const testing::DomainCleanup cleanup(domain);
    const Scene scene = crossing_scene();
    const std::string path = write_scene(scene, "awaited");
    constexpr std::uint64_t kFrames = 120;
    auto cluster = start_cluster(path, domain, 2, kFrames, {"--block-size", "1", "--await-clients", "1"});
    ASSERT_TRUE(cluster.process);
    std::this_thread::sleep_for(std::chrono::seconds(3));
    ASSERT_TRUE(cluster.process->running()) << "a cluster of 120 frames at 60 Hz would be done by now";
    auto client = connect(domain, "awaited");
    ASSERT_TRUE(client);
    auto frames = collect(*client, kFrames, std::chrono::seconds(60));
    expect_stopped_cleanly(cluster);
    ASSERT_FALSE(frames.empty());
    EXPECT_EQ(frames.begin()->first, 1u) << "the client's first frame";
    EXPECT_EQ(frames.size(), kFrames) << "every frame, 1 to " << kFrames;
    expect_logged(cluster, "coordinator.log", "client awaited is ready");
}

TEST(Cluster, AReaderMissingASectorsBaseGetsItWholeOnRequest) {
    // One worker, bodies always moving: after the first frame a sector travels as partial samples only,
    // nothing is resent whole on a schedule (only once when this reader joins, if its last sample was
    // partial). A reader that asks for a sector whole (as lpss::Client does when it refused a partial
    // sample) gets it with one of the next frames.
    const int domain = 133;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(crossing_scene(), "request");
    auto p = dds::Participant::create(domain, "", "request-test");
    ASSERT_TRUE(p.ok()) << p.error().message;
    dds::Participant& part = **p;
    dds::Inbox inbox;
    auto frames = std::make_unique<dds::Reader<wire::SectorFrame>>(
        part, part.topic<wire::SectorFramePubSubType>(dds::kSectorFrames),
        dds::reader_qos(dds::kSectorFrameReading), &inbox);
    auto requests = std::make_unique<dds::Writer<wire::SectorRequest>>(
        part, part.topic<wire::SectorRequestPubSubType>(dds::kSectorRequests),
        dds::writer_qos(dds::kCommandDelivery));
    auto cluster = start_cluster(path, domain, 1, 900);
    ASSERT_TRUE(cluster.process);
    std::optional<SectorKey> sector;
    std::uint64_t asked_at = 0, whole_at = 0, partial_before = 0, complete_before = 0;
    std::map<SectorKey, int> unasked_complete;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (whole_at == 0 && std::chrono::steady_clock::now() < end) {
        inbox.wait(std::chrono::milliseconds(10));
        frames->take_all([&](const wire::SectorFrame& f, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data || f.worker() == 0 || f.frame() < 2) return;
            const SectorKey key = dds::from_wire(f.sector());
            if (asked_at == 0) {
                (f.complete() ? complete_before : partial_before) += 1;
                if (f.complete()) ++unasked_complete[key];
                if (f.frame() < 100 || f.complete()) return;  // past the start and this reader's match
                sector = key;
                asked_at = f.frame();
                wire::SectorRequest r;
                r.reader("request-test");
                r.request(1);
                r.sectors().push_back(dds::to_wire(key));
                requests->write(r);
            } else if (key == *sector && f.complete()) {
                whole_at = f.frame();
            }
        });
    }
    frames.reset();
    requests.reset();
    cluster.process->stop();
    ASSERT_TRUE(sector) << "no partial sample seen";
    ASSERT_NE(whole_at, 0u) << "the sector never came whole again";
    std::printf("frames 2-%llu: %llu partial and %llu complete samples; asked at %llu, whole at %llu\n",
                static_cast<unsigned long long>(asked_at), static_cast<unsigned long long>(partial_before),
                static_cast<unsigned long long>(complete_before), static_cast<unsigned long long>(asked_at),
                static_cast<unsigned long long>(whole_at));
    for (const auto& [key, count] : unasked_complete)
        EXPECT_LE(count, 1) << "a sector sent whole again and again, unasked";
    EXPECT_GT(partial_before, 90u);
    EXPECT_LE(whole_at, asked_at + 5) << "the request is served with one of the next frames";
}

/// Reads the workers' end-of-frame marks until a frame all `workers` marked reports nothing awake; returns
/// that frame (0 if none within `limit`).
std::uint64_t wait_until_asleep(int domain, std::uint32_t workers, std::chrono::seconds limit) {
    auto participant = dds::Participant::create(domain, "", "sleep-probe");
    if (!participant) return 0;
    dds::Participant& p = **participant;
    dds::Inbox inbox;
    dds::Reader<wire::WorkerFrame> marks(p, p.topic<wire::WorkerFramePubSubType>(dds::kWorkerFrames),
                                         dds::reader_qos(dds::kFrameDelivery), &inbox);
    std::map<std::uint64_t, std::map<std::uint32_t, std::uint32_t>>
        awake_by_frame;  // frame -> worker -> awake
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
        inbox.wait(std::chrono::milliseconds(20));
        std::uint64_t asleep = 0;
        marks.take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data || m.frame() == 0 || m.worker() == 0) return;
            auto& awake = awake_by_frame[m.frame()];
            awake[m.worker()] = m.awake();
            std::uint32_t total = 0;
            for (const auto& [worker, count] : awake)
                total += count;
            if (awake.size() == workers && total == 0) asleep = m.frame();
        });
        if (asleep != 0) return asleep;
    }
    return 0;
}

TEST(Cluster, LateJoinerGetsTheWholeWorldAndARegionExactlyItsRegion) {
    Scene scene = scenes::box_stack(Eigen::Vector3d(0, 0, 0), 4, kL);
    for (int n = 0; n < 6; ++n) {
        // Beside the stack's line, not in it (a ball inside the stack's boxes knocked them over and rolled
        // on for ever: the world never came to rest, which a fixed sleep never showed).
        BodyDesc b = scenes::sphere_body(50 + n, 0.5, 1.0, Eigen::Vector3d(n * 1.5 * kL, 2, 5));
        scene.bodies.push_back(b);
    }
    const int domain = 124;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(scene, "late");
    auto cluster = start_cluster(path, domain, 2, 900);
    ASSERT_TRUE(cluster.process);
    // Late: once the workers report the stack and the balls asleep (their marks count what is awake).
    const std::uint64_t asleep_at = wait_until_asleep(domain, 2, std::chrono::seconds(60));
    ASSERT_GT(asleep_at, 0u) << "the world never came to rest";
    auto whole = connect(domain, "late");
    const Region region{{2, -1, -1}, {5, 1, 1}};
    auto regional = connect(domain, "regional", region);
    // Both clients polled side by side until they hold a frame in common (a client not polled for long
    // loses the end-of-frame marks of the frames it did not read in time).
    std::map<std::uint64_t, WorldFrame> seen_whole, seen_region;
    std::optional<std::uint64_t> common;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!common && std::chrono::steady_clock::now() < end) {
        for (WorldFrame& f : whole->poll(std::chrono::milliseconds(10)))
            seen_whole[f.frame] = std::move(f);
        for (WorldFrame& f : regional->poll(std::chrono::milliseconds(10)))
            seen_region[f.frame] = std::move(f);
        for (const auto& [f, frame] : seen_region) {
            if (seen_whole.count(f)) common = f;
        }
    }
    ASSERT_FALSE(seen_whole.empty());
    ASSERT_TRUE(common) << "no frame seen by both clients";
    std::printf("late joiners: first whole-world frame %llu, first region frame %llu, in common %llu\n",
                static_cast<unsigned long long>(seen_whole.begin()->first),
                static_cast<unsigned long long>(seen_region.empty() ? 0 : seen_region.begin()->first),
                static_cast<unsigned long long>(*common));
    EXPECT_GT(seen_whole.begin()->first, asleep_at) << "the client joined a world already at rest";
    std::set<BodyId> first_ids, scene_ids;
    for (const BodyView& b : seen_whole.begin()->second.bodies) {
        first_ids.insert(b.id);
        EXPECT_FALSE(b.awake) << "body " << b.id << " in the late joiner's first frame";
    }
    for (const BodyDesc& b : scene.bodies)
        scene_ids.insert(b.id);
    EXPECT_EQ(first_ids, scene_ids) << "the first frame holds every body";
    // The same frame of the whole world, filtered by the region, must be exactly what the region client has.
    const WorldFrame& r = seen_region.at(*common);
    const WorldFrame& w = seen_whole.at(*common);
    std::set<BodyId> want, got;
    for (const BodyView& b : w.bodies) {
        if (region.contains(b.position.sector)) want.insert(b.id);
    }
    for (const BodyView& b : r.bodies)
        got.insert(b.id);
    EXPECT_EQ(got, want);
    EXPECT_EQ(want, (std::set<BodyId>{51, 52, 53}));  // balls at 1.5 L, 3 L and 4.5 L
    cluster.process->stop();
}

TEST(Cluster, AClientThatFellBehindSyncsAgainOnWhatChangedNotOnTheWholeWorld) {
    // A whole-world client of changes not polled for longer than the frame marks it keeps loses marks and
    // syncs again. It holds every sector as of the last frame it applied, so the workers send whole only
    // the sectors written since (those the balls crossed): before, every body came again (at a million
    // resting bodies a whole-world client falls behind while it builds its first frame, and was sent the
    // million again).
    const Scene scene = scenes::resting_world(20000, 100);
    const std::size_t world = scene.bodies.size();  // the ground plane too: frames show planes as bodies
    const int domain = 178;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(scene, "fell_behind");
    auto client = connect(domain, "fell-behind", std::nullopt, FrameContent::changes);
    // And one that never falls behind, to compare with: a digest of every body's id and position at each
    // frame each saw (the frames themselves, 20,000 bodies each, are too many to keep). Of changes too, so
    // that it keeps up under AddressSanitizer (a client of every body there fell behind and synced again,
    // and the bodies sent whole for it reached the paused client too).
    auto steady = connect(domain, "steady", std::nullopt, FrameContent::changes);
    ASSERT_TRUE(client && steady);
    auto digest = [](BodyId id, const Eigen::Vector3d& at) {
        std::uint64_t h = id * 0x9E3779B97F4A7C15ull;
        for (int a = 0; a < 3; ++a) {
            std::uint64_t bits = 0;
            const double v = at[a];
            std::memcpy(&bits, &v, sizeof bits);
            h ^= bits + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        }
        return h;
    };
    // A world rebuilt from frames of changes, with the sum of its bodies' digests kept up to date.
    struct Rebuilt {
        std::map<BodyId, Eigen::Vector3d> bodies;
        std::uint64_t sum = 0;
        std::map<std::uint64_t, std::uint64_t> sums;  // frame -> sum
        std::uint64_t last = 0;
    };
    auto take = [&](Rebuilt& r, const WorldFrame& f) {
        if (f.every_body) {
            r.bodies.clear();
            r.sum = 0;
        }
        for (const BodyView& b : f.bodies) {
            auto [it, added] = r.bodies.emplace(b.id, b.global);
            if (!added) {
                r.sum -= digest(b.id, it->second);
                it->second = b.global;
            }
            r.sum += digest(b.id, b.global);
        }
        for (BodyId id : f.departed) {
            auto it = r.bodies.find(id);
            if (it == r.bodies.end()) continue;
            r.sum -= digest(id, it->second);
            r.bodies.erase(it);
        }
        r.sums[f.frame] = r.sum;
        r.last = f.frame;
    };
    Rebuilt truth, seen;
    auto follow_steady = [&] {
        for (const WorldFrame& f : steady->poll())
            take(truth, f);
    };
    BodiesPerWorker marks(domain);
    auto cluster = start_cluster(path, domain, 2, 3000, {"--realtime"});
    ASSERT_TRUE(cluster.process);
    std::uint64_t& last = seen.last;
    auto follow = [&](std::chrono::seconds limit, const std::function<bool()>& done) {
        const auto until = std::chrono::steady_clock::now() + limit;
        while (!done() && std::chrono::steady_clock::now() < until) {
            follow_steady();
            for (const WorldFrame& f : client->poll(std::chrono::milliseconds(20)))
                take(seen, f);
        }
    };
    follow(std::chrono::seconds(120), [&] { return last >= 60; });
    ASSERT_GE(last, 60u) << "logs: " << cluster.log_dir;
    EXPECT_EQ(seen.bodies.size(), world);
    const ClientStats before = client->stats();
    EXPECT_GE(before.syncs, 1u);
    EXPECT_GE(before.bodies_in_complete_samples, world - 1) << "the first sync brought every body";
    // Not polled while the world runs on by twice the marks a client keeps (120 a worker).
    const std::uint64_t paused_at = last;
    const auto paused = std::chrono::steady_clock::now();
    while (marks.newest_frame() < paused_at + 240 &&
           std::chrono::steady_clock::now() - paused < std::chrono::seconds(60)) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        follow_steady();
        marks.poll(0);
    }
    ASSERT_GE(marks.newest_frame(), paused_at + 240) << "logs: " << cluster.log_dir;
    follow(std::chrono::seconds(60),
           [&] { return client->stats().syncs > before.syncs && last > paused_at + 240; });
    // The frames after the sync do not wait for sectors the client still holds as they are, but what the
    // workers send whole for it comes within a frame or two: counted a second later.
    const std::uint64_t synced_at = last;
    follow(std::chrono::seconds(30), [&] { return last >= synced_at + 60; });
    const ClientStats after = client->stats();
    ASSERT_GT(after.syncs, before.syncs) << "it fell behind and synced again; logs: " << cluster.log_dir;
    ASSERT_GT(last, paused_at + 240) << "frames after the sync; logs: " << cluster.log_dir;
    EXPECT_EQ(seen.bodies.size(), world) << "every body, once synced again";
    // As the client that never fell behind saw the same frames, before the pause and after the sync.
    follow_steady();
    std::size_t compared = 0, differ = 0, after_sync = 0;
    for (const auto& [f, sum] : seen.sums) {
        auto same = truth.sums.find(f);
        if (same == truth.sums.end()) continue;
        ++compared;
        after_sync += f > paused_at ? 1 : 0;
        differ += same->second != sum ? 1 : 0;
    }
    EXPECT_GE(after_sync, 30u) << "frames after the sync that both clients saw";
    EXPECT_EQ(differ, 0u) << "frames of " << compared
                          << " where a body was not where the steady client saw it";
    EXPECT_EQ(truth.bodies.size(), world);
    EXPECT_EQ(steady->stats().syncs, 1u) << "the steady client kept up (its syncs' samples reach the other)";
    const std::uint64_t resent = after.bodies_in_complete_samples - before.bodies_in_complete_samples;
    std::printf(
        "paused at frame %llu, frames again from %llu: %llu syncs, %llu bodies sent whole for the sync "
        "(of %zu); %zu frames compared with the steady client, %zu after the pause\n",
        static_cast<unsigned long long>(paused_at), static_cast<unsigned long long>(last),
        static_cast<unsigned long long>(after.syncs - before.syncs), static_cast<unsigned long long>(resent),
        world, compared, after_sync);
    EXPECT_LT(resent, world / 10) << "only what changed since the client fell behind comes whole";
}

TEST(Cluster, AClientOfChangesHoldsWhatAClientOfEveryBodyHolds) {
    // 3,000 resting bodies and 60 balls thrown among them, on 2 workers: a client of every body, and two
    // clients of changes (the whole world, and a region the balls cross). Rebuilt from the changes, the
    // world at each frame both saw is exactly the frame of every body (filtered by the region).
    Scene scene = scenes::resting_world(3000, 60);
    // And balls rolling along the region's edge across its border, out of it and into it, beside the
    // resting bodies (which end at |z| = 83).
    for (int n = 0; n < 6; ++n) {
        const bool out = n < 3;
        BodyDesc ball =
            scenes::sphere_body(10000 + n, 0.4, 1.0, Eigen::Vector3d(out ? -60 : 100, 0.4, -90 + 2 * n));
        ball.linear_velocity = Eigen::Vector3d(out ? 25 : -25, 0, 0);
        scene.bodies.push_back(ball);
    }
#if defined(__SANITIZE_ADDRESS__)
    // Under AddressSanitizer the world runs at 30 frames a second: beside another cluster test at 60 the
    // clients' thread fell more than 2 s behind (the client of changes had 108 of 300 frames, then asked
    // for inventories of a world that had ended; the region client saw no ball leave, as they leave from
    // frame 221 on at 60 Hz). The clients are compared with each other, frame by frame, at any dt.
    scene.settings.dt = 1.0 / 30.0;
#endif
    const int domain = 136;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(scene, "changes");
    auto every = connect(domain, "every-body");
    auto changes = connect(domain, "changes", std::nullopt, FrameContent::changes);
    const Region region{{-1, -1, -1}, {0, 1, 0}};
    auto regional = connect(domain, "regional-changes", region, FrameContent::changes);
    ASSERT_TRUE(every && changes && regional);
    constexpr std::uint64_t kFrames = 300;
#if defined(__SANITIZE_ADDRESS__)
    // Under AddressSanitizer the three clients (one thread) fall behind a real-time world, and a client that
    // falls behind skips to the newest frame it can show: fewer frames are seen by two clients (111 of 300
    // beside another cluster test). Each one compared is still checked body by body.
    // The copy of the rebuilt world kept for each frame costs 5-7 ms there: kept for every fifth frame only,
    // or this thread polls a client less often than every 2 s, and a client not polled for 2 s (120 marks
    // of a worker at 60 Hz, the client's marks reader) must ask for inventories again (seen: a client that
    // went on asking when the world ended, its 2.4 s without a poll spent copying 3,066 bodies a frame).
    constexpr std::uint64_t kCompareEvery = 5;
    constexpr std::size_t kFramesCompared = 25;
#else
    constexpr std::uint64_t kCompareEvery = 1;
    constexpr std::size_t kFramesCompared = 150;
#endif
    auto cluster = start_cluster(path, domain, 2, kFrames, {"--realtime"});
    ASSERT_TRUE(cluster.process);
    struct Rebuilt {
        std::map<BodyId, BodyView> bodies;
        std::map<std::uint64_t, std::map<BodyId, BodyView>> at;  // the world after each frame seen
        std::size_t frames = 0, changed = 0, whole = 0, departed = 0;
        std::uint64_t last = 0;  // the newest frame taken
        void take(WorldFrame& f) {
            if (f.every_body) {
                bodies.clear();
                ++whole;
            }
            for (const BodyView& b : f.bodies)
                bodies[b.id] = b;
            for (BodyId id : f.departed)
                bodies.erase(id);
            departed += f.departed.size();
            changed += f.every_body ? 0 : f.bodies.size();
            ++frames;
            if (f.frame % kCompareEvery == 0) at[f.frame] = bodies;
            last = f.frame;
        }
    } whole_world, in_region;
    std::map<std::uint64_t, WorldFrame> seen;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    // Until each client has read the last frame: a client of changes reads every frame and can fall behind
    // the client of every body, which skips to the newest (seen under AddressSanitizer: 74 frames read
    // when the other had read frame 300).
    auto behind = [&](std::uint64_t newest) { return newest < kFrames; };
    while ((behind(seen.empty() ? 0 : seen.rbegin()->first) || behind(whole_world.last) ||
            behind(in_region.last)) &&
           std::chrono::steady_clock::now() < end) {
        for (WorldFrame& f : every->poll(std::chrono::milliseconds(5)))
            seen[f.frame] = std::move(f);
        for (WorldFrame& f : changes->poll())
            whole_world.take(f);
        for (WorldFrame& f : regional->poll())
            in_region.take(f);
    }
    expect_stopped_cleanly(cluster);
    std::size_t compared = 0, compared_region = 0;
    auto same = [](const BodyView& a, const BodyView& b) {
        return a.id == b.id && a.position.sector == b.position.sector &&
               a.position.local == b.position.local && a.orientation.coeffs() == b.orientation.coeffs() &&
               a.linear_velocity == b.linear_velocity && a.awake == b.awake;
    };
    for (const auto& [f, frame] : seen) {
        ASSERT_TRUE(std::is_sorted(frame.bodies.begin(), frame.bodies.end(),
                                   [](const BodyView& a, const BodyView& b) { return a.id < b.id; }))
            << "a frame's bodies in id order, its planes among them: frame " << f;
        if (auto it = whole_world.at.find(f); it != whole_world.at.end()) {
            ++compared;
            ASSERT_EQ(it->second.size(), frame.bodies.size()) << "frame " << f;
            for (const BodyView& b : frame.bodies)
                ASSERT_TRUE(it->second.count(b.id) && same(it->second.at(b.id), b))
                    << "body " << b.id << " frame " << f;
        }
        if (auto it = in_region.at.find(f); it != in_region.at.end()) {
            ++compared_region;
            std::size_t inside = 0;
            for (const BodyView& b : frame.bodies) {
                if (!region.contains(b.position.sector)) continue;
                ++inside;
                ASSERT_TRUE(it->second.count(b.id) && same(it->second.at(b.id), b))
                    << "body " << b.id << " in the region, frame " << f;
            }
            ASSERT_EQ(it->second.size(), inside) << "frame " << f;
        }
    }
    std::printf(
        "%zu frames compared (whole world), %zu (region); the whole-world client of changes got %zu frames, "
        "%zu whole, %.1f bodies per frame after the first\n",
        compared, compared_region, whole_world.frames, whole_world.whole,
        whole_world.frames > 1 ? static_cast<double>(whole_world.changed) / (whole_world.frames - 1) : 0.0);
    EXPECT_GE(compared, kFramesCompared);
    EXPECT_GE(compared_region, kFramesCompared);
    EXPECT_EQ(whole_world.whole, 1u) << "one frame of every body, then changes";
    EXPECT_GT(in_region.departed, 0u) << "bodies left the region";
    // What moves is the balls and what they hit, not the 3,000 resting bodies.
    EXPECT_LT(whole_world.changed, whole_world.frames * 600) << "changes cost what moves";
}

TEST(Cluster, CommandsFromTwoClientsAreOrderedAndBadOnesRefused) {
    Scene scene;
    scene.settings.sector_size = kL;
    for (int n = 0; n < 3; ++n)
        scene.bodies.push_back(scenes::sphere_body(1 + n, 0.5, 1.0, Eigen::Vector3d(n * 150.0, 0, 0)));
    scene.bodies.push_back(
        scenes::box_body(10, Eigen::Vector3d::Constant(1.0), 0.0, Eigen::Vector3d(0, -10, 0)));
    // A plane far below, out of the bodies' reach in this test, to be removed by command.
    scene.bodies.push_back(scenes::ground_plane(1000, Eigen::Vector3d(0, -1e5, 0)));
    const int domain = 125;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(scene, "commands");
    // Every answer on the wire, to count them.
    auto wire_participant = dds::Participant::create(domain, "", "answers");
    ASSERT_TRUE(wire_participant.ok());
    dds::Participant& p = **wire_participant;
    dds::Inbox answered;
    dds::Reader<wire::CommandResult> answers(p, p.topic<wire::CommandResultPubSubType>(dds::kCommandResults),
                                             dds::reader_qos(dds::kCommandDelivery), &answered);
    auto a = connect(domain, "alice");
    auto b = connect(domain, "bob");
    auto cluster = start_cluster(path, domain, 2, 1200);
    ASSERT_TRUE(cluster.process);
    ASSERT_TRUE(a->wait_for_cluster(std::chrono::seconds(30)));
    ASSERT_TRUE(b->wait_for_cluster(std::chrono::seconds(30)));
    collect(*a, 0, std::chrono::seconds(5));

    // Both set body 2's velocity at once: both are applied, in a defined order, and the later one wins.
    const auto ra = a->set_velocity(2, {1, 0, 0}, {0, 0, 0});
    const auto rb = b->set_velocity(2, {-3, 0, 0}, {0, 0, 0});
    auto oa = a->wait_outcome(ra, std::chrono::seconds(10));
    auto ob = b->wait_outcome(rb, std::chrono::seconds(10));
    ASSERT_TRUE(oa && ob);
    EXPECT_TRUE(oa->applied && ob->applied) << oa->reason << " / " << ob->reason;
    EXPECT_NE(oa->order, ob->order);
    const double winner = oa->order > ob->order ? 1.0 : -3.0;
    const std::uint64_t after = std::max(oa->frame, ob->frame) + 5;
    auto frames = collect(*a, after, std::chrono::seconds(10));
    ASSERT_TRUE(frames.count(after));
    bool seen = false;
    for (const BodyView& v : frames.at(after).bodies) {
        if (v.id != 2) continue;
        seen = true;
        EXPECT_NEAR(v.linear_velocity.x(), winner, 1e-6);
    }
    EXPECT_TRUE(seen) << "body 2 is in frame " << after;

    // Refusals, each with its reason, and nothing else changes.
    const WorldFrame before = frames.rbegin()->second;
    auto refused = [&](Client& c, std::uint64_t request, const std::string& reason) {
        auto o = c.wait_outcome(request, std::chrono::seconds(10));
        ASSERT_TRUE(o);
        EXPECT_FALSE(o->applied);
        EXPECT_NE(o->reason.find(reason), std::string::npos) << o->reason;
    };
    refused(*a, a->apply_impulse(77, {1, 0, 0}), "unknown body id 77");
    refused(*b, b->apply_impulse(1, {std::nan(""), 0, 0}), "finite");
    refused(*a, a->set_velocity(10, {1, 0, 0}, {0, 0, 0}), "static");
    refused(*b, b->remove(999), "unknown body id 999");
    BodyDesc twin = scenes::sphere_body(3, 0.5, 1.0, Eigen::Vector3d(5, 5, 5));
    refused(*a, a->spawn(twin), "id is used by another body");
    BodyDesc huge = scenes::sphere_body(40, 100.0, 1.0, Eigen::Vector3d(5, 5, 5));
    refused(*b, b->spawn(huge), "larger than a sector");
    // Hostile numbers, as a buggy or malicious peer sends them: each refused with its reason.
    refused(*a, a->apply_impulse(1, {1e300, 0, 0}), "the impulse is too large");
    refused(*b, b->apply_impulse(1, {0, 1e3, 0}, {1e12, 0, 0}), "angular speed");
    refused(*a, a->set_velocity(1, {0, 0, 1e25}, {0, 0, 0}), "linear speed 1e+25");
    refused(*b, b->set_velocity(1, {0, 0, 0}, {0, -1e20, 0}), "angular speed 1e+20");
    refused(*a, a->set_velocity(1, {0, 0, 0}, {0, INFINITY, 0}), "finite");
    refused(*b, b->apply_impulse(~BodyId{0}, {1, 0, 0}), "unknown body id 18446744073709551615");
    refused(*a, a->remove(~BodyId{0}), "unknown body id 18446744073709551615");
    BodyDesc far = scenes::sphere_body(41, 0.5, 1.0, Eigen::Vector3d(5, 5, 5));
    far.position = SectorPosition{SectorKey{INT64_MAX, INT64_MIN, 0}, Eigen::Vector3d::Zero()};
    refused(*b, b->spawn(far), "beyond 2^62");
    BodyDesc beyond = scenes::sphere_body(41, 0.5, 1.0, Eigen::Vector3d(1e300, 0, 0));
    refused(*a, a->spawn(beyond), "beyond sector index 2^62");
    BodyDesc spinning = scenes::sphere_body(41, 0.5, 1.0, Eigen::Vector3d(5, 5, 5));
    spinning.angular_velocity = Eigen::Vector3d(1e300, 0, 0);
    refused(*b, b->spawn(spinning), "angular_velocity is too fast");
    auto later = collect(*a, before.frame + 10, std::chrono::seconds(10));
    const WorldFrame& now = later.rbegin()->second;
    ASSERT_EQ(now.bodies.size(), before.bodies.size());
    // No gravity, nothing touching: every body keeps its velocity and moves by it over the frames between.
    const double seconds = static_cast<double>(now.frame - before.frame) * scene.settings.dt;
    for (std::size_t n = 0; n < now.bodies.size(); ++n) {
        const BodyView& x = now.bodies[n];
        const BodyView& y = before.bodies[n];
        EXPECT_EQ(x.id, y.id);
        EXPECT_LE((x.linear_velocity - y.linear_velocity).norm(), 1e-6) << "body " << x.id;
        EXPECT_LE((x.angular_velocity - y.angular_velocity).norm(), 1e-6) << "body " << x.id;
        EXPECT_LE((x.global - (y.global + seconds * y.linear_velocity)).norm(), 1e-4) << "body " << x.id;
        EXPECT_LE(x.orientation.angularDistance(y.orientation), 1e-6) << "body " << x.id;
    }

    // A spawn and a removal do what they say.
    BodyDesc fresh = scenes::sphere_body(41, 0.5, 1.0, Eigen::Vector3d(300, 2, 0));
    auto spawned = a->wait_outcome(a->spawn(fresh), std::chrono::seconds(10));
    ASSERT_TRUE(spawned && spawned->applied) << (spawned ? spawned->reason : "no answer");
    auto removed = b->wait_outcome(b->remove(1), std::chrono::seconds(10));
    ASSERT_TRUE(removed && removed->applied) << (removed ? removed->reason : "no answer");
    auto last = collect(*a, std::max(spawned->frame, removed->frame) + 3, std::chrono::seconds(10));
    std::set<BodyId> ids;
    for (const BodyView& v : last.rbegin()->second.bodies)
        ids.insert(v.id);
    EXPECT_TRUE(ids.count(41));
    EXPECT_FALSE(ids.count(1));

    // Every worker holds the planes; one of them answers for a plane.
    const std::uint64_t plane_request = b->remove(1000);
    auto plane_removed = b->wait_outcome(plane_request, std::chrono::seconds(10));
    ASSERT_TRUE(plane_removed && plane_removed->applied)
        << (plane_removed ? plane_removed->reason : "no answer");
    // Every worker answers, if at all, in the frame the command was applied in; once a client has seen ten
    // frames after it, every worker has ended that frame, and a second answer would have been written.
    auto without_plane = collect(*a, plane_removed->frame + 10, std::chrono::seconds(10));
    ASSERT_FALSE(without_plane.empty());
    ASSERT_GE(without_plane.rbegin()->first, plane_removed->frame + 10);
    for (const BodyView& v : without_plane.rbegin()->second.bodies)
        EXPECT_NE(v.id, 1000u) << "the plane is still shown";
    int plane_answers = 0;
    answers.take_all([&](const wire::CommandResult& r, const dds::fdds::SampleInfo& info) {
        plane_answers += info.valid_data && r.client() == "bob" && r.request() == plane_request;
    });
    EXPECT_EQ(plane_answers, 1);
    cluster.process->stop();
}

/// The Fast DDS files in /dev/shm, by name.
std::set<std::string> shm_files() {
    std::set<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator("/dev/shm")) {
        const std::string name = entry.path().filename().string();
        if (name.find("fastrtps_") != std::string::npos) names.insert(name);
    }
    return names;
}

/// The participant segments (not ports) that process `pid` maps, with their lock files.
std::set<std::string> segments_of(const std::string& pid) {
    std::set<std::string> names;
    std::ifstream maps("/proc/" + pid + "/maps");
    std::string line;
    while (std::getline(maps, line)) {
        const auto at = line.find("/dev/shm/fastrtps_");
        if (at == std::string::npos || line.find("port", at) != std::string::npos) continue;
        const std::string name = std::filesystem::path(line.substr(at)).filename().string();
        names.insert(name);
        names.insert(name + "_el");
    }
    return names;
}

TEST(Cluster, TheExamplesRunAgainstTheExampleScene) {
    const int domain = 132;
    const testing::DomainCleanup cleanup(domain);
    auto cluster =
        start_cluster(std::string(LPSS_SOURCE_DIR) + "/deploy/scenes/far_stacks.textproto", domain, 2, 1800);
    ASSERT_TRUE(cluster.process);
    const std::string game_out = cluster.log_dir + "-game.out",
                      observer_out = cluster.log_dir + "-observer.out";
    auto game = runtime::ChildProcess::start(LPSS_EXAMPLE_GAME, {std::to_string(domain), "3"}, game_out);
    // The observer with a profile given (no identity): the built-in one, as a file.
    const std::string profile = std::string(LPSS_SOURCE_DIR) + "/deploy/profiles/lpss-local.xml";
    auto observer = runtime::ChildProcess::start(LPSS_EXAMPLE_OBSERVER,
                                                 {std::to_string(domain), "120", "", profile}, observer_out);
    ASSERT_TRUE(game && observer);
    EXPECT_TRUE(game->wait(std::chrono::seconds(60)));
    EXPECT_TRUE(observer->wait(std::chrono::seconds(60)));
    EXPECT_EQ(game->exit_code().value_or(-1), 0) << read_file(game_out);
    EXPECT_EQ(observer->exit_code().value_or(-1), 0) << read_file(observer_out);
    cluster.process->stop();
    // A profile it cannot read: refused at once, naming it (the argument is used, not ignored).
    const std::string refused_out = cluster.log_dir + "-refused.out";
    auto refused = runtime::ChildProcess::start(
        LPSS_EXAMPLE_GAME, {std::to_string(domain), "3", "", profile + ".missing"}, refused_out);
    ASSERT_TRUE(refused);
    EXPECT_TRUE(refused->wait(std::chrono::seconds(30)));
    EXPECT_EQ(refused->exit_code().value_or(-1), 2) << read_file(refused_out);
    EXPECT_NE(read_file(refused_out).find("lpss-local.xml.missing"), std::string::npos)
        << read_file(refused_out);

    // The game backend spawned its four players and saw them move.
    const std::string game_text = read_file(game_out);
    for (int n = 0; n < 4; ++n)
        EXPECT_NE(game_text.find("player " + std::to_string(9000 + n) + " spawned at frame"),
                  std::string::npos)
            << game_text;
    // Pushed every second with impulses of up to 300 (mass 80: up to 3.75 units/s), each player moves.
    std::map<BodyId, std::vector<Eigen::Vector3d>> tracks;
    std::istringstream game_lines(game_text);
    for (std::string line; std::getline(game_lines, line);) {
        unsigned long long frame = 0, player = 0;
        double x = 0, y = 0, z = 0;
        if (std::sscanf(line.c_str(), "frame %llu player %llu at (%lf, %lf, %lf)", &frame, &player, &x, &y,
                        &z) == 5)
            tracks[player].emplace_back(x, y, z);
    }
    for (BodyId player = 9000; player < 9004; ++player) {
        const auto& track = tracks[player];
        ASSERT_GE(track.size(), 2u) << "player " << player << " reported twice at least\n" << game_text;
        // Horizontally: the pushes are; a player dropped at y = 2 falls whether pushed or not.
        const Eigen::Vector3d moved = track.back() - track.front();
        EXPECT_GT(std::hypot(moved.x(), moved.z()), 0.5) << "player " << player << " was pushed\n"
                                                         << game_text;
    }
    // The observer saw the stack 1e9 units out, in double global coordinates, and nothing from elsewhere:
    // at every report (every 60th of its 120 frames) all six of its bodies, five boxes and the ball.
    std::istringstream lines(read_file(observer_out));
    std::size_t far = 0, near = 0, reports = 0;
    for (std::string line; std::getline(lines, line);) {
        reports += line.find("bodies in the region") != std::string::npos;
        const std::size_t open = line.find('(');
        if (line.rfind("  ", 0) != 0 || open == std::string::npos) continue;
        const double x = std::stod(line.substr(open + 1));
        (std::abs(x - 1e9) < 100.0 ? far : near) += 1;
    }
    EXPECT_EQ(reports, 2u) << read_file(observer_out);
    EXPECT_EQ(far, 6 * reports) << read_file(observer_out);
    EXPECT_EQ(near, 0u) << read_file(observer_out);

    // Each worker holds its own sectors and, as ghosts, the bodies of their neighbours: not the world.
    const std::string summary = read_file(cluster.log_dir + ".out");
    const std::size_t done = summary.rfind("done:");
    ASSERT_NE(done, std::string::npos) << summary;
    std::istringstream words(summary.substr(summary.find("ghosts per worker", done) + 17));
    std::size_t ghosts = 0;
    for (std::string word; words >> word && word.find(':') != std::string::npos;)
        ghosts += std::stoul(word.substr(word.find(':') + 1));
    // Only the group 1e9 out lies astride a sector border (x = 1e9 + 64): if its two sectors have two
    // owners, each of its six bodies may be a ghost in the other worker. Every body everywhere would be 18.
    EXPECT_LE(ghosts, 6u) << summary;
    // The last memory line names every process with what it held: a process read as it went had been
    // counted 0 MiB (seen: "standby 0" in the example's last line on a fresh machine).
    std::smatch memory;
    ASSERT_TRUE(std::regex_search(summary, memory,
                                  std::regex(R"(memory at frame [0-9]+: [0-9]+ MiB resident \(([^;]*);)")))
        << summary;
    const std::string listed = memory[1];
    for (const char* process : {"coordinator ", "standby ", "worker 1 ", "worker 2 "}) {
        const std::size_t at = listed.find(process);
        ASSERT_NE(at, std::string::npos) << process << "missing from: " << listed;
        EXPECT_GT(std::stod(listed.substr(at + std::strlen(process))), 0.0) << listed;
    }
}

TEST(Cluster, NothingLeavesThisMachineWithTheBuiltInProfile) {
    // A cluster and two clients (a program and this process) on the built-in profile, in a namespace with
    // one more interface than loopback: not a packet may leave through it. Then the opt-in LAN profile's
    // multicast discovery must be seen leaving, to show that the count would catch a leak.
    const int domain = 139;
    const testing::DomainCleanup cleanup(domain);
    LeakCounter leak;
    if (!leak.ok()) GTEST_SKIP() << "cannot add an interface to this network namespace (needs root)";
    const std::uint64_t before = leak.sent();
    EXPECT_EQ(before, 0u);
    auto cluster = start_cluster(LPSS_SOURCE_DIR "/deploy/scenes/far_stacks.textproto", domain, 2, 300);
    ASSERT_TRUE(cluster.process);
    auto watch = runtime::ChildProcess::start(
        LPSS_WATCH, {"--domain", std::to_string(domain), "--wait-s", "20", "--frames", "200"},
        cluster.log_dir + "-watch.out");
    ASSERT_TRUE(watch);
    auto client = connect(domain, "leak-check");
    ASSERT_TRUE(client);
    const auto frames = collect(*client, 300, std::chrono::seconds(60));
    ASSERT_TRUE(cluster.process->wait(std::chrono::seconds(30)));
    EXPECT_EQ(cluster.process->exit_code().value_or(-1), 0) << "logs: " << cluster.log_dir;
    ASSERT_TRUE(watch->wait(std::chrono::seconds(30)));
    EXPECT_EQ(watch->exit_code().value_or(-1), 0) << read_file(cluster.log_dir + "-watch.out");
    EXPECT_GE(frames.size(), 290u) << "frames this process saw";
    const std::uint64_t built_in = leak.sent() - before;
    EXPECT_EQ(built_in, 0u) << "packets out of a non-loopback interface with the built-in profile";

    auto lan = runtime::ChildProcess::start(LPSS_WATCH,
                                            {"--domain", std::to_string(domain), "--wait-s", "2", "--profile",
                                             LPSS_SOURCE_DIR "/deploy/profiles/lpss-lan.xml"},
                                            cluster.log_dir + "-lan.out");
    ASSERT_TRUE(lan);
    lan->wait(std::chrono::seconds(20));
    const std::uint64_t with_lan = leak.sent() - before - built_in;
    EXPECT_GT(with_lan, 0u) << "the LAN profile's discovery should have left through the interface";
    std::printf(
        "packets out of a non-loopback interface: %llu with the built-in profile (a cluster of 2 "
        "workers and 2 clients, %zu frames); %llu from one LAN-profile participant in 2 s\n",
        static_cast<unsigned long long>(built_in), frames.size(), static_cast<unsigned long long>(with_lan));
}

TEST(Cluster, ClientsJoiningOneAfterAnotherHearEveryPeerWithoutWaitingForItsNextAnnouncement) {
    // Fast DDS 2.9 sends a new participant's first announcement before it listens, and a peer answers a
    // newcomer once: a newcomer that missed an answer learned of that peer only from its next periodic
    // announcement. Here every participant announces itself every 60 s (the built-in profile, slowed), so a
    // client that relied on those would not match the cluster within the test. Each of twelve clients joining
    // one after another must match within 5 s. Without the discovery prompt (dds::Participant::create;
    // LPSS_DDS_DISCOVERY_PROMPT=0) most newcomers missed some peer's answer: 9 of 12 bare participants.
    const int domain = 174;
    const testing::DomainCleanup cleanup(domain);
    std::string profile = read_file(LPSS_SOURCE_DIR "/deploy/profiles/lpss-local.xml");
    const std::string announcement = "<leaseAnnouncement>\n              <sec>1</sec>";
    const auto at = profile.find(announcement);
    ASSERT_NE(at, std::string::npos) << "the built-in profile's announcement period, to slow it";
    profile.replace(at, announcement.size(),
                    "<leaseDuration><sec>120</sec></leaseDuration><leaseAnnouncement><sec>60</sec>");
    const std::string profile_path = testing::workspace_path("slow_announcements.xml");
    std::ofstream(profile_path) << profile;
    auto cluster = start_cluster(LPSS_SOURCE_DIR "/deploy/scenes/far_stacks.textproto", domain, 2, 100000,
                                 {"--profile", profile_path});
    ASSERT_TRUE(cluster.process);
    {
        ClientOptions o;
        o.domain = domain;
        o.name = "slow-announcements-first";
        o.profile = profile_path;
        auto first = Client::connect(o);
        ASSERT_TRUE(first) << first.error().message;
        ASSERT_TRUE((*first)->wait_for_cluster(std::chrono::seconds(60)))
            << "the cluster itself did not form; logs: " << cluster.log_dir;
    }
    std::string times;
    // Without the prompt, 1-2 of eight failed in each of four runs.
    for (int k = 1; k <= 12; ++k) {
        ClientOptions o;
        o.domain = domain;
        o.name = "slow-announcements-" + std::to_string(k);
        o.profile = profile_path;
        const auto start = std::chrono::steady_clock::now();
        auto client = Client::connect(o);
        ASSERT_TRUE(client) << client.error().message;
        const bool found = (*client)->wait_for_cluster(std::chrono::seconds(5));
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        char cell[32];
        std::snprintf(cell, sizeof cell, " %.3f", seconds);
        times += cell;
        EXPECT_TRUE(found) << "client " << k << " found no cluster";
        EXPECT_TRUE((*client)->reaches_cluster())
            << "client " << k << " did not reach the coordinator and every worker within 5 s";
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    std::printf("clients matched the cluster after (s):%s\n", times.c_str());
    EXPECT_TRUE(cluster.process->running()) << "logs: " << cluster.log_dir;
    expect_stopped_cleanly(cluster);
}

TEST(Cluster, AKilledProcessLeavesNoSharedMemoryBehind) {
    const int domain = 129;
    const testing::DomainCleanup cleanup(domain);
    const long first_port = 7400 + 250L * domain;
    // The built-in profile has no shared memory (deploy/profiles/lpss-local.xml says why); the opt-in
    // profile beside it does, and lpss-cluster cleans up after it.
    const std::string shm_profile = LPSS_SOURCE_DIR "/deploy/profiles/lpss-local-shm.xml";
    auto own = dds::Participant::create(domain, shm_profile, "shm-test");
    ASSERT_TRUE(own.ok()) << own.error().message;
    const std::set<std::string> own_segments = segments_of("self");
    ASSERT_FALSE(own_segments.empty());
    // A worker waiting for a coordinator that never comes has a participant, with a segment of its own.
    auto worker =
        runtime::ChildProcess::start(LPSS_WORKER, {"--id", "1", "--domain", std::to_string(domain),
                                                   "--coordinator-wait-s", "60", "--profile", shm_profile});
    ASSERT_TRUE(worker);
    std::set<std::string> its_segments;
    for (int n = 0; n < 200 && its_segments.empty(); ++n) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        // It maps ours too, to read what we write.
        for (const std::string& name : segments_of(std::to_string(worker->pid())))
            if (!own_segments.count(name)) its_segments.insert(name);
    }
    ASSERT_FALSE(its_segments.empty()) << "the worker mapped no shared-memory segment";
    ::kill(worker->pid(), SIGKILL);
    ASSERT_TRUE(worker->wait(std::chrono::seconds(5)));
    for (const std::string& name : its_segments)
        ASSERT_TRUE(shm_files().count(name)) << "Fast DDS left " << name;

    // Young segments are spared (a participant starting elsewhere may not hold its lock yet)...
    dds::remove_abandoned_shm(domain);
    for (const std::string& name : its_segments)
        EXPECT_TRUE(shm_files().count(name)) << name << " went though it is young";
    // ... and abandoned ones go once old enough; here, at once.
    EXPECT_GT(dds::remove_abandoned_shm(domain, std::chrono::seconds(0)), 0u);
    const std::set<std::string> after = shm_files();
    for (const std::string& name : its_segments)
        EXPECT_FALSE(after.count(name)) << name << " is still there";
    for (const std::string& name : own_segments)
        EXPECT_TRUE(after.count(name)) << name << " was in use, and went";

    // With no participant left on the domain, none of its port files stays.
    own->reset();
    dds::remove_abandoned_shm(domain);
    for (const std::string& name : shm_files()) {
        long port = 0;
        if (std::sscanf(name.c_str(), "fastrtps_port%ld", &port) == 1) {
            EXPECT_FALSE(port >= first_port && port < first_port + 250) << name << " is left";
        }
    }
}

TEST(Cluster, TheMultiHostProfileRunsACluster) {
    const testing::DomainCleanup cleanup(119);
    // That profile talks on every interface: run it only where loopback is the only one. (/proc/self/net
    // is this process's network namespace; /sys/class/net is the one sysfs was mounted in.)
    std::size_t interfaces = 0;
    std::ifstream devices("/proc/self/net/dev");
    std::string line;
    while (std::getline(devices, line)) {
        const auto colon = line.find(':');
        if (colon == std::string::npos) continue;  // the two header lines
        const auto name = line.find_first_not_of(' ');
        interfaces += line.substr(name, colon - name) != "lo";
    }
    if (interfaces > 0) GTEST_SKIP() << "not in a loopback-only network namespace (needs root)";
    const Scene scene = crossing_scene();
    const std::string path = write_scene(scene, "lan");
    const std::string command =
        std::string(LPSS_CLUSTER) + " " + path + " --workers 2 --frames 120 --domain 119 --quiet --log-dir " +
        path + ".logs --profile " LPSS_SOURCE_DIR "/deploy/profiles/lpss-lan.xml > " + path + ".out 2>&1";
    EXPECT_EQ(std::system(command.c_str()), 0) << "see " << path << ".out";
}

TEST(Cluster, AWatcherEndsWithTheWorldAndSaysSoWhenTheClusterVanishes) {
    // A world that ends (its frames ran out) says so (its coordinator's status, "stopped"), and lpss-watch
    // ends with its last frame (exit 0) rather than after --wait-s of silence; a cluster killed says
    // nothing, and lpss-watch takes its silence for a cluster gone (exit 3), as lpss-dis does.
    const int domain = 186;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(crossing_scene(), "watched_to_the_end");
    const std::string watch_out = path + ".watch.out";
    auto watch = runtime::ChildProcess::start(
        LPSS_WATCH, {"--domain", std::to_string(domain), "--wait-s", "30"}, watch_out);
    ASSERT_TRUE(watch);
    std::this_thread::sleep_for(std::chrono::seconds(2));
    auto cluster = start_cluster(path, domain, 2, 120, {"--await-clients", "1"});  // every frame for it
    ASSERT_TRUE(cluster.process);
    ASSERT_TRUE(cluster.process->wait(std::chrono::seconds(60))) << "logs: " << cluster.log_dir;
    EXPECT_EQ(cluster.process->exit_code().value_or(-1), 0) << "logs: " << cluster.log_dir;
    // Well within its wait of 30 s.
    ASSERT_TRUE(watch->wait(std::chrono::seconds(10))) << read_file(watch_out);
    EXPECT_EQ(watch->exit_code().value_or(-1), 0) << read_file(watch_out);
    EXPECT_NE(read_file(watch_out).find("the world stopped after frame 120"), std::string::npos)
        << read_file(watch_out);
    EXPECT_NE(read_file(watch_out).find("lpss-watch: 120 frames"), std::string::npos) << read_file(watch_out);

    // The same, the cluster killed whole in its run.
    const std::string gone_out = path + ".gone.out";
    auto gone = runtime::ChildProcess::start(LPSS_WATCH,
                                             {"--domain", std::to_string(domain), "--wait-s", "3"}, gone_out);
    ASSERT_TRUE(gone);
    auto killed = start_cluster(path, domain, 2, 100000);
    ASSERT_TRUE(killed.process);
    const auto running_by = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (read_file(gone_out).find("frame ") == std::string::npos &&
           std::chrono::steady_clock::now() < running_by)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_NE(read_file(gone_out).find("frame "), std::string::npos)
        << "frames were shown: " << read_file(gone_out);
    // The coordinators and workers first: lpss-cluster's children get SIGTERM when it dies (PDEATHSIG), and
    // a coordinator that had that time stopped cleanly and said so (seen under AddressSanitizer: the watcher
    // took the killed cluster's frame 3 for the world's end).
    for (const auto& [pid, name] : testing::processes_of(domain))
        ::kill(pid, SIGKILL);
    ::kill(killed.process->pid(), SIGKILL);
    EXPECT_TRUE(killed.process->wait(std::chrono::seconds(5)));
    ASSERT_TRUE(gone->wait(std::chrono::seconds(20))) << read_file(gone_out);
    EXPECT_EQ(gone->exit_code().value_or(-1), 3) << read_file(gone_out);
    EXPECT_NE(read_file(gone_out).find("no frame for 3 s: the cluster is gone"), std::string::npos)
        << read_file(gone_out);
}

TEST(Cluster, TheClusterPassesItsTimeoutsToItsCoordinatorsAndWorkers) {
    // lpss-cluster takes the coordinators' and the workers' waits and passes each to the processes it
    // concerns (the docs describe them beside lpss-cluster, which could not set them before).
    const int domain = 185;
    const testing::DomainCleanup cleanup(domain);
    const std::string path = write_scene(crossing_scene(), "timeouts");
    auto cluster = start_cluster(path, domain, 2, 100000,
                                 {"--worker-wait-s", "9", "--worker-timeout-ms", "1234", "--standby-wait-s",
                                  "3", "--border-wait-ms", "321", "--coordinator-wait-s", "7"});
    ASSERT_TRUE(cluster.process);
    std::map<int, std::string> processes;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while ((processes = testing::processes_of(domain)).size() < 4 && std::chrono::steady_clock::now() < until)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_EQ(processes.size(), 4u) << "a coordinator, its standby and 2 workers";
    for (const auto& [pid, name] : processes) {
        const std::string line = read_file("/proc/" + std::to_string(pid) + "/cmdline");
        auto has = [&](const std::string& flag, const std::string& value) {
            return line.find(flag + '\0' + value + '\0') != std::string::npos;
        };
        const bool coordinator = name == "coordinator" || name == "standby";
        EXPECT_EQ(has("--worker-wait-s", "9"), coordinator) << name;
        EXPECT_EQ(has("--worker-timeout-ms", "1234"), coordinator) << name;
        EXPECT_EQ(has("--standby-wait-s", "3"), coordinator) << name;
        EXPECT_EQ(has("--border-wait-ms", "321"), !coordinator) << name;
        EXPECT_EQ(has("--coordinator-wait-s", "7"), !coordinator) << name;
    }
    expect_stopped_cleanly(cluster);
}

TEST(Cluster, ProgramsExplainWhyTheyCannotStart) {
    const testing::DomainCleanup cleanup(126);
    auto run = [](const std::string& command) {
        std::array<char, 4096> buffer{};
        std::string out;
        std::FILE* pipe = popen((command + " 2>&1").c_str(), "r");
        while (std::fgets(buffer.data(), buffer.size(), pipe))
            out += buffer.data();
        const int status = pclose(pipe);
        return std::make_pair(WEXITSTATUS(status), out);
    };
    auto [code, out] = run(std::string(LPSS_WORKER) + " --id 1 --domain 126 --coordinator-wait-s 2");
    EXPECT_EQ(code, 3);
    EXPECT_NE(out.find("no coordinator found on domain 126"), std::string::npos) << out;
    std::tie(code, out) = run(std::string(LPSS_CLUSTER) + " /nonexistent.textproto --domain 126");
    EXPECT_EQ(code, 2);
    EXPECT_NE(out.find("cannot open scene file"), std::string::npos) << out;
    // A scene the coordinator refuses: the reason names the body and the field, and nothing keeps running.
    Scene bad = scenes::sphere_pair(Eigen::Vector3d::Zero().eval(), kL);
    bad.bodies[1].position = Eigen::Vector3d(std::nan(""), 0, 0);
    std::tie(code, out) = run(std::string(LPSS_CLUSTER) + " " + write_scene(bad, "refused") +
                              " --domain 126 --log-dir " + testing::workspace_path("refused.logs"));
    EXPECT_NE(code, 0);
    EXPECT_NE(out.find("body 'right' (id 2): position.global is not finite"), std::string::npos) << out;
    std::tie(code, out) = run(std::string(LPSS_WORKER) + " --id 1 --domain 126 --profile /nonexistent.xml");
    EXPECT_EQ(code, 2);
    EXPECT_NE(out.find("cannot read the DDS profile /nonexistent.xml"), std::string::npos) << out;
    std::tie(code, out) = run(std::string(LPSS_WATCH) + " --domain 126 --wait-s 2");
    EXPECT_EQ(code, 3);
    EXPECT_NE(out.find("no lpss cluster found on domain 126"), std::string::npos) << out;
}

}  // namespace
}  // namespace lpss
