// lpss-cluster: the main job. Starts a coordinator and N workers on this machine as child processes,
// runs a scene, shows the coordinator's progress while a large world loads, prints a live summary (frame
// rate, bodies, sectors, frame time and bytes received per worker, handoffs, memory), and on Ctrl-C or at
// the end stops every child cleanly. A standby coordinator runs beside the coordinator unless told not to,
// and takes over if the coordinator dies.
#include <fmt/format.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <thread>

#include "child_process.hpp"
#include "crash_report.hpp"
#include "lpss/common/process_memory.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#include "lpss_dds/topics.hpp"
#include "stop_signal.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using lpss::runtime::ChildProcess;

/// The id lpss-coordinator takes with --standby unless told another (lpss-cluster tells none).
constexpr std::uint32_t kStandbyId = 2;
/// A worker whose last end of a frame is this many frames behind the newest is left out of the live line's
/// sums (it is gone, or cut off); marks of one frame reach this reader a few milliseconds apart.
constexpr std::uint64_t kSilentAfterFrames = 30;

std::filesystem::path own_directory() {
    std::error_code error;
    std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    return error ? std::filesystem::current_path() : self.parent_path();
}

/// What the workers said about their latest frame.
struct WorkerSeen {
    std::uint64_t frame = 0;
    std::uint32_t bodies = 0, awake = 0, sectors = 0, ghosts = 0, dormant = 0, clones = 0, degraded = 0;
    float step_ms = 0, wait_ms = 0, publish_ms = 0;
    std::uint64_t received_bytes = 0;
};

double mib(std::uint64_t bytes) { return static_cast<double>(bytes) / 1048576.0; }

}  // namespace

int main(int argc, char** argv) {
    lpss::runtime::install_crash_report("lpss-cluster");
    CLI::App app{"lpss-cluster: runs a scene on a coordinator and N workers on this machine"};
    std::string scene_path, profile, log_dir, security;
    std::uint32_t workers = 2;
    std::uint64_t frames = 0;
    bool realtime = false, quiet = false;
    std::int64_t block_size = 4;
    std::uint64_t rebalance_every = 300;
    int domain = 0, threads = 1;
    app.add_option("scene", scene_path, "scene file (Protobuf text format)")->required();
    app.add_option("--workers", workers, "worker processes")->check(CLI::Range(1u, 256u));
    app.add_option("--frames", frames, "frames to run (0: until Ctrl-C)");
    app.add_flag("--realtime", realtime, "pace frames at the scene's dt");
    app.add_option("--domain", domain, "DDS domain id")->check(CLI::Range(0, 232));
    app.add_option("--profile", profile,
                   "Fast DDS XML profile for every process (default: built-in, this machine only)");
    app.add_option("--security", security,
                   "DDS Security: the folder deploy/security/identities.sh made; the coordinators take its "
                   "coordinator identity, the workers its worker identity, this program its observer's");
    app.add_option("--threads", threads, "threads per worker")->check(CLI::Range(1, 256));
    app.add_option("--log-dir", log_dir, "where the children's logs go (default: a new folder under /tmp)");
    app.add_flag("--quiet", quiet, "no live summary, only the final one");
    app.add_option("--block-size", block_size, "sectors per block edge in assignments")
        ->check(CLI::Range(1, 1 << 20));
    app.add_option("--rebalance-every", rebalance_every,
                   "frames between load checks (0: never move sectors)");
    std::uint32_t await_clients = 0;
    double command_rate = 1000.0;
    app.add_option("--command-rate", command_rate,
                   "commands a second one client may send, in bursts of as many (0: no limit)")
        ->check(CLI::Range(0.0, 1e9));
    app.add_option("--await-clients", await_clients,
                   "frame 1 waits until this many clients have matched every topic they read");
    bool restart_workers = false;
    app.add_flag("--restart-workers", restart_workers,
                 "start a worker that dies again under its id, once the world runs (at most once every 10 s "
                 "per worker); it joins the running world");
    bool no_standby = false;
    app.add_flag("--no-standby", no_standby,
                 "no standby coordinator (by default one follows the world and takes over if the coordinator "
                 "dies)");
    // Passed to the coordinators or the workers as given (their own defaults otherwise).
    int worker_wait_s = 0, standby_wait_s = 0, coordinator_wait_s = 0, worker_timeout_ms = 0,
        border_wait_ms = 0;
    CLI::Option* worker_wait = app.add_option(
        "--worker-wait-s", worker_wait_s,
        "coordinator: how long to wait for the workers to appear, and for one to join once every worker is "
        "gone (default 30)");
    CLI::Option* worker_timeout =
        app.add_option("--worker-timeout-ms", worker_timeout_ms,
                       "coordinator: silence after which a worker is taken as gone (default 5000)");
    CLI::Option* standby_wait =
        app.add_option("--standby-wait-s", standby_wait_s,
                       "coordinator: how long frame 1 waits for the standby to say it stands by (default 20)")
            ->check(CLI::Range(0, 3600));
    CLI::Option* border_wait =
        app.add_option("--border-wait-ms", border_wait_ms,
                       "workers: longest wait for other workers' data before a frame (default 2000)");
    CLI::Option* coordinator_wait =
        app.add_option("--coordinator-wait-s", coordinator_wait_s,
                       "workers: how long to wait for a coordinator (default 30)");
    CLI11_PARSE(app, argc, argv);

    // The coordinator reads and checks the scene (reading it here too would double the start of a large
    // world): a refusal comes from it, and is shown below.
    if (access(scene_path.c_str(), R_OK) != 0) {
        std::fprintf(stderr, "lpss-cluster: %s: cannot open scene file\n", scene_path.c_str());
        return 2;
    }
    if (!profile.empty() && access(profile.c_str(), R_OK) != 0) {
        std::fprintf(stderr, "lpss-cluster: cannot read the DDS profile %s\n", profile.c_str());
        return 2;
    }
    const auto& stop = lpss::runtime::install_stop_signal();
    if (log_dir.empty())
        log_dir =
            (std::filesystem::temp_directory_path() / fmt::format("lpss-cluster-{}", getpid())).string();
    std::filesystem::create_directories(log_dir);
    const std::filesystem::path bin = own_directory();
    const std::filesystem::path worker_program = bin / "lpss-worker";
    const std::filesystem::path coordinator_program = bin / "lpss-coordinator";
    for (const auto& p : {worker_program, coordinator_program}) {
        if (access(p.c_str(), X_OK) != 0) {
            std::fprintf(stderr, "lpss-cluster: %s is missing (build it beside lpss-cluster)\n", p.c_str());
            return 2;
        }
    }
    std::vector<std::string> common = {"--domain", std::to_string(domain)};
    if (!profile.empty()) common.insert(common.end(), {"--profile", profile});
    // Each process its role's identity (a folder of its own, as on separate hosts).
    auto identity = [&](const char* role) {
        return security.empty() ? std::string() : (std::filesystem::path(security) / role).string();
    };
    for (const char* role : {"coordinator", "worker", "observer"}) {
        if (!security.empty() && !std::filesystem::is_directory(identity(role))) {
            std::fprintf(stderr,
                         "lpss-cluster: --security %s holds no %s identity (make them with "
                         "deploy/security/identities.sh init %s)\n",
                         security.c_str(), role, security.c_str());
            return 2;
        }
    }

    // The monitor joins first, so that it sees everything from the first frame.
    auto participant =
        lpss::dds::Participant::create(domain, profile, "lpss-cluster", {}, identity("observer"));
    if (!participant) {
        std::fprintf(stderr, "lpss-cluster: cannot start DDS: %s\n", participant.error().message.c_str());
        return 2;
    }
    lpss::dds::Inbox inbox;
    auto marks = std::make_unique<lpss::dds::Reader<lpss::wire::WorkerFrame>>(
        **participant, (*participant)->topic<lpss::wire::WorkerFramePubSubType>(lpss::dds::kWorkerFrames),
        lpss::dds::reader_qos(lpss::dds::kFrameDelivery), &inbox);
    auto status = std::make_unique<lpss::dds::Reader<lpss::wire::ClusterStatus>>(
        **participant, (*participant)->topic<lpss::wire::ClusterStatusPubSubType>(lpss::dds::kStatus),
        lpss::dds::reader_qos(lpss::dds::kStateDelivery), &inbox);

    std::vector<ChildProcess> children;
    auto worker_args = [&](std::uint32_t w) {
        std::vector<std::string> args = common;
        args.insert(args.end(), {"--id", std::to_string(w), "--threads", std::to_string(threads)});
        if (border_wait->count())
            args.insert(args.end(), {"--border-wait-ms", std::to_string(border_wait_ms)});
        if (coordinator_wait->count())
            args.insert(args.end(), {"--coordinator-wait-s", std::to_string(coordinator_wait_s)});
        if (!security.empty()) args.insert(args.end(), {"--security", identity("worker")});
        return args;
    };
    for (std::uint32_t w = 1; w <= workers; ++w) {
        auto child =
            ChildProcess::start(worker_program, worker_args(w), log_dir + fmt::format("/worker-{}.log", w));
        if (!child) {
            std::fprintf(stderr, "lpss-cluster: cannot start worker %u\n", w);
            return 2;
        }
        children.push_back(std::move(*child));
    }
    std::vector<std::string> args = common;
    args.insert(
        args.end(),
        {scene_path, "--workers", std::to_string(workers), "--frames", std::to_string(frames), "--block-size",
         std::to_string(block_size), "--rebalance-every", std::to_string(rebalance_every), "--await-clients",
         std::to_string(await_clients), "--command-rate", fmt::format("{}", command_rate)});
    if (realtime) args.push_back("--realtime");
    if (worker_wait->count()) args.insert(args.end(), {"--worker-wait-s", std::to_string(worker_wait_s)});
    if (worker_timeout->count())
        args.insert(args.end(), {"--worker-timeout-ms", std::to_string(worker_timeout_ms)});
    if (standby_wait->count()) args.insert(args.end(), {"--standby-wait-s", std::to_string(standby_wait_s)});
    if (!security.empty()) args.insert(args.end(), {"--security", identity("coordinator")});
    // The standby first, so that it follows the world from its first state; the coordinator waits for it.
    std::optional<ChildProcess> standby;
    bool standby_gone = false;  ///< ended before the coordinator (said once)
    std::vector<std::string> standby_args = args;
    standby_args.push_back("--standby");
    // The standby's log now: one started again has its own.
    std::string standby_log = log_dir + "/standby.log";
    if (!no_standby) {
        standby = ChildProcess::start(coordinator_program, standby_args, standby_log);
        if (!standby) {
            std::fprintf(stderr, "lpss-cluster: cannot start the standby coordinator\n");
            return 2;
        }
        args.push_back("--await-standby");
    }
    auto coordinator = ChildProcess::start(coordinator_program, args, log_dir + "/coordinator.log");
    if (!coordinator) {
        std::fprintf(stderr, "lpss-cluster: cannot start the coordinator\n");
        return 2;
    }
    ChildProcess* active = &*coordinator;  ///< the coordinator that runs the world
    bool taken_over = false;
    // The standby has said it leads (its status: it writes none while it stands by).
    bool standby_leads = false;
    Clock::time_point taken_over_at;
    fmt::print("lpss-cluster: {} on {} worker(s), domain {}; logs in {}\n", scene_path, workers, domain,
               log_dir);
    std::fflush(stdout);

    std::map<std::uint32_t, WorkerSeen> seen;
    double first_frame_seconds = 0.0;
    bool memory_seen = false;
    std::string memory_at_frame;  ///< the latest memory line taken while frames ran
    std::uint64_t memory_frame = 0;
    auto memory_taken = Clock::now();
    std::uint64_t handoffs = 0, first_frame = 0, last_frame = 0;
    const auto start = Clock::now();
    auto last_print = start;
    auto first_time = start;
    std::uint64_t printed_frame = 0;
    // Memory of every process, as the kernel counts it: resident now, and the most each has held. None if
    // one of them could not be read: at the end they go one by one, and one read as it went counted 0 MiB
    // (seen: "standby 0" in the example's last line, the standby gone between a check that it was there and
    // the reading). The proportional set (each shared page counted once) costs the kernel a walk of every
    // page (17 ms for a process of 1.2 GB here): taken every 10 s, and once past 80% of a run of --frames.
    std::string proportional_said = "not yet taken";
    auto proportional_taken = Clock::now() - std::chrono::seconds(10);
    bool proportional_near_end = false;
    auto memory = [&]() -> std::optional<std::string> {
        const bool near_end = frames > 0 && !proportional_near_end && last_frame * 5 >= frames * 4;
        const bool with_proportional =
            near_end || Clock::now() - proportional_taken >= std::chrono::seconds(10);
        std::vector<std::pair<std::string, lpss::MemoryUse>> all;
        std::uint64_t proportional = 0;
        // A kernel or /proc that does not give the proportional set loses that part of the line only.
        bool proportional_read = true;
        auto add = [&](std::string name, const ChildProcess& process) {
            const std::optional<lpss::MemoryUse> use = lpss::memory_use(process.pid());
            if (!use) return false;
            all.emplace_back(std::move(name), *use);
            if (with_proportional) {
                const std::optional<std::uint64_t> pss = lpss::proportional_resident_bytes(process.pid());
                proportional += pss.value_or(0);
                proportional_read = proportional_read && pss.has_value();
            }
            return true;
        };
        if (coordinator->running() && !add("coordinator", *coordinator)) return std::nullopt;
        if (standby && standby->running() &&
            !add(taken_over ? "coordinator (was standby)" : "standby", *standby))
            return std::nullopt;
        for (std::size_t n = 0; n < children.size(); ++n) {
            if (!add(fmt::format("worker {}", n + 1), children[n])) return std::nullopt;
        }
        std::uint64_t total = 0, peak = 0, shared = 0;
        std::string now, most;
        for (const auto& [name, use] : all) {
            total += use.resident_bytes;
            peak += use.peak_bytes;
            shared += use.shared_bytes;
            now += fmt::format("{}{} {:.0f}", now.empty() ? "" : ", ", name, mib(use.resident_bytes));
            most += fmt::format("{}{:.0f}", most.empty() ? "" : ", ", mib(use.peak_bytes));
        }
        if (with_proportional) {
            proportional_said = proportional_read
                                    ? fmt::format("{:.0f} MiB at frame {}", mib(proportional), last_frame)
                                    : std::string("not readable");
            proportional_taken = Clock::now();
            proportional_near_end = proportional_near_end || near_end;
        }
        return fmt::format(
            "{:.0f} MiB resident ({} MiB; {:.0f} MiB of it shared memory, counted by each process "
            "mapping it), {:.0f} MiB at most ({} MiB); proportional set (a page processes share counted "
            "once) {}",
            mib(total), now, mib(shared), mib(peak), most, proportional_said);
    };
    auto print = [&](bool final) {
        std::uint32_t bodies = 0, degraded = 0;
        std::string per_worker, ghosts, dormant, work, silent;
        for (const auto& [w, s] : seen) {
            degraded += s.degraded;
            // A worker gone (killed, taken as gone) keeps its last report here: its bodies are its
            // successors' now (seen: "bodies 149657" in a world of 101,000 after a worker was killed).
            if (s.frame + kSilentAfterFrames < last_frame) {
                silent += fmt::format("{}worker {} since frame {}", silent.empty() ? "" : ", ", w, s.frame);
                continue;
            }
            bodies += s.bodies;
            per_worker += fmt::format(" {}:{}", w, s.sectors);
            ghosts += fmt::format(" {}:{}", w, s.ghosts);
            dormant += fmt::format(" {}:{}", w, s.dormant);
            work += fmt::format(" {}:{:.2f}ms/{:.1f}kB", w, s.step_ms + s.publish_ms,
                                static_cast<double>(s.received_bytes) / 1e3);
        }
        const double elapsed = std::chrono::duration<double>(Clock::now() - last_print).count();
        const double rate =
            final ? (last_frame - first_frame) /
                        std::max(1e-9, std::chrono::duration<double>(Clock::now() - first_time).count())
                  : (last_frame - printed_frame) / std::max(1e-9, elapsed);
        fmt::print(
            "{}frame {:>7}  {:7.1f} frames/s  bodies {:>6}  sectors per worker{}  ghosts per worker{} (and "
            "kept out of the engine{})  handoffs {}  degraded {}{}\n",
            final ? "done: " : "", last_frame, rate, bodies, per_worker, ghosts, dormant, handoffs, degraded,
            silent.empty() ? "" : "  silent: " + silent);
        if (!final && !work.empty()) fmt::print("      step+publish and bytes received per worker{}\n", work);
        std::fflush(stdout);
        printed_frame = last_frame;
        last_print = Clock::now();
    };
    int exit_code = 0;
    std::optional<std::size_t> failed_worker;  // whose exit code `exit_code` is, if not a coordinator's
    bool stopping = false;
    // A worker that dies again at once (a scene that crashes it, say) is not started in a loop.
    constexpr auto kRestartInterval = std::chrono::seconds(10);
    std::vector<Clock::time_point> restarted_at(children.size(), Clock::time_point{});
    std::vector<bool> said_ended(children.size(), false);
    int restarts = 0;
    constexpr int kStandbyRestarts = 3;
    int standby_restarts = 0;
    while (true) {
        inbox.wait(std::chrono::milliseconds(100));
        marks->take_all([&](const lpss::wire::WorkerFrame& m, const lpss::dds::fdds::SampleInfo& info) {
            if (!info.valid_data || m.frame() == 0 || m.worker() == 0) return;  // 0: the coordinator
            WorkerSeen& s = seen[m.worker()];
            if (m.frame() <= s.frame) return;
            s = WorkerSeen{m.frame(),   m.bodies(),  m.awake(),      m.sector_count(),
                           m.ghosts(),  m.dormant(), m.clones(),     m.degraded(),
                           m.step_ms(), m.wait_ms(), m.publish_ms(), m.received_bytes()};
            handoffs += m.leaving().size();
            if (first_frame == 0) {
                first_frame = m.frame();
                first_time = Clock::now();
            }
            last_frame = std::max(last_frame, m.frame());
        });
        status->take_all([&](const lpss::wire::ClusterStatus& st, const lpss::dds::fdds::SampleInfo& info) {
            if (info.valid_data && st.coordinator() == kStandbyId) standby_leads = true;
            if (!info.valid_data || quiet || last_frame > 0) return;
            // Loading a large world takes a while: say what the coordinator is at.
            if (st.phase() == "loading" && st.bodies() == 0) {
                fmt::print("lpss-cluster: the coordinator is reading the scene\n");
            } else if (st.phase() == "loading") {
                fmt::print("lpss-cluster: {} bodies read\n", st.bodies());
            } else if (st.phase() == "sending") {
                fmt::print("lpss-cluster: sending the world to the workers: {:.0f}%\n",
                           100.0 * st.progress());
            }
            std::fflush(stdout);
        });
        if (last_frame > memory_frame && Clock::now() - memory_taken > std::chrono::milliseconds(200)) {
            // Only while every process is there (the standby too: it ends first when the world does).
            const bool standby_went = standby && !taken_over && !standby_gone && !standby->running();
            if (std::optional<std::string> line = standby_went ? std::nullopt : memory()) {
                memory_at_frame = std::move(*line);
                memory_frame = last_frame;
                memory_taken = Clock::now();
            }
        }
        if (!quiet && Clock::now() - last_print > std::chrono::seconds(1) && last_frame > 0) {
            print(false);
            fmt::print("      memory {}\n", memory_at_frame);
        }
        if (last_frame > 0 && !memory_seen) {
            first_frame_seconds = std::chrono::duration<double>(Clock::now() - start).count();
            memory_seen = true;
        }
        if (last_frame > 0 && !stop.load()) {
            for (std::size_t n = 0; n < children.size(); ++n) {
                ChildProcess& c = children[n];
                const auto w = static_cast<std::uint32_t>(n + 1);
                // (One that ends with 0 read the coordinator's stop: the run is ending.)
                if (c.running() || c.exit_code().value_or(0) == 0) continue;
                if (!restart_workers) {
                    if (!said_ended[n]) {
                        said_ended[n] = true;
                        fmt::print(
                            "lpss-cluster: worker {} ended ({}); the others take its sectors, or "
                            "with none left the world waits for a worker to join (--restart-workers "
                            "starts it again)\n",
                            w, lpss::runtime::describe_exit_code(c.exit_code().value_or(1)));
                        std::fflush(stdout);
                    }
                    continue;
                }
                if (Clock::now() - restarted_at[n] < kRestartInterval) continue;
                const int code = c.exit_code().value_or(1);
                restarted_at[n] = Clock::now();
                auto again = ChildProcess::start(worker_program, worker_args(w),
                                                 log_dir + fmt::format("/worker-{}.{}.log", w, ++restarts));
                if (!again) {
                    fmt::print(stderr, "lpss-cluster: cannot start worker {} again\n", w);
                    continue;
                }
                c = std::move(*again);
                fmt::print("lpss-cluster: worker {} ended ({}); started again under its id\n", w,
                           lpss::runtime::describe_exit_code(code));
                std::fflush(stdout);
            }
        }
        // (One that ends with 0 read the coordinator's stop, as the workers do: the run is ending.)
        if (standby && !taken_over && !standby_gone && !standby->running() &&
            standby->exit_code().value_or(1) != 0) {
            // One killed before frame 1 is started again: the coordinator holds frame 1 for a standby's
            // hello (for --standby-wait-s, 20 s), and a new one can still follow the world from its first
            // state. Not one that ended by itself (it said why in its log), and not in a loop. After frame 1
            // a new standby could not take over (it would lack the frames before), so none is started then.
            const int code = standby->exit_code().value_or(1);
            if (last_frame == 0 && code > 128 && standby_restarts < kStandbyRestarts &&
                coordinator->running()) {
                standby_log = log_dir + fmt::format("/standby.{}.log", ++standby_restarts);
                auto again = ChildProcess::start(coordinator_program, standby_args, standby_log);
                if (again) {
                    standby = std::move(*again);
                    fmt::print(
                        "lpss-cluster: the standby coordinator ended before frame 1 ({}); started again, "
                        "its log in {}\n",
                        lpss::runtime::describe_exit_code(code), standby_log);
                    std::fflush(stdout);
                    continue;
                }
            }
            standby_gone = true;
            fmt::print(
                "lpss-cluster: the standby coordinator ended ({}): no takeover if the coordinator "
                "ends; see {}\n",
                lpss::runtime::describe_exit_code(standby->exit_code().value_or(1)), standby_log);
            std::fflush(stdout);
        }
        // Before frame 1 the standby knows the coordinator by its first word: one that died before that
        // reached it is never found gone. A standby that has not said it leads within the coordinator's
        // participant lease (Fast DDS's 20 s) and a little more is not going to: the world ends, as without
        // one.
        if (taken_over && last_frame == 0 && !standby_leads &&
            Clock::now() - taken_over_at > std::chrono::seconds(25)) {
            fmt::print(stderr, "lpss-cluster: the standby did not start the world within 25 s; see {}\n",
                       standby_log);
            active->stop(std::chrono::seconds(2));
            exit_code = 3;
            break;
        }
        if (!active->running()) {
            exit_code = active->exit_code().value_or(1);
            // A coordinator killed (a signal, not an exit that says why), or one that found its standby had
            // taken over (exit 6: it was stopped or cut off past its lease), while its standby runs: the
            // standby goes on with the world (before frame 1, it starts the world from the scene if the
            // coordinator had sent none of it, or says why it cannot).
            // (A coordinator that yields, exit 6, may end after its standby ran the world to its end.)
            if (exit_code == 6 && !taken_over && standby && !standby->running() &&
                standby->exit_code().value_or(1) == 0) {
                taken_over = true;
                active = &*standby;
                exit_code = 0;
                break;
            }
            if ((exit_code >= 128 || exit_code == 6) && !taken_over && standby && standby->running()) {
                taken_over = true;
                taken_over_at = Clock::now();
                active = &*standby;
                fmt::print("lpss-cluster: the coordinator ended ({}); the standby takes over\n",
                           lpss::runtime::describe_exit_code(exit_code));
                std::fflush(stdout);
                exit_code = 0;
                continue;
            }
            break;
        }
        if (stop.load() && !stopping) {
            // Ctrl-C: the coordinator tells the workers to stop after the current frame.
            stopping = true;
            fmt::print("lpss-cluster: stopping\n");
            exit_code = active->stop(std::chrono::seconds(10));
            if (exit_code == 128 + 15) exit_code = 0;
            break;
        }
    }
    // A standby ends on the coordinator's stop too; stopped if not.
    if (standby && !taken_over &&
        !standby->wait(exit_code == 0 ? std::chrono::seconds(5) : std::chrono::seconds(0)))
        standby->stop();
    // Workers end on the coordinator's stop; those that do not are stopped (at once if the coordinator
    // failed: no stop will come).
    for (ChildProcess& c : children) {
        if (!c.wait(exit_code == 0 ? std::chrono::seconds(5) : std::chrono::seconds(0))) c.stop();
        const int code = c.exit_code().value_or(0);
        if (code != 0 && exit_code == 0 && !stopping) {
            exit_code = code;
            failed_worker = static_cast<std::size_t>(&c - children.data()) + 1;
        }
    }
    marks.reset();
    status.reset();
    participant->reset();
    // A worker that was killed leaves its shared memory behind; so does every participant's port files.
    const std::size_t cleaned = lpss::dds::remove_abandoned_shm(domain);
    if (cleaned > 0 && !quiet)
        fmt::print("lpss-cluster: removed {} abandoned file(s) from /dev/shm\n", cleaned);
    print(true);
    if (memory_seen) {
        fmt::print("first frame {:.3f} s after start\n", first_frame_seconds);
        fmt::print("memory at frame {}: {}\n", memory_frame, memory_at_frame);
    } else {
        fmt::print("no frame ran\n");  // (not "first frame 0.000 s", nor an empty memory line)
    }
    if (exit_code != 0) {
        // The coordinator's last words say why (a refused scene, say).
        std::ifstream log(taken_over ? standby_log : log_dir + "/coordinator.log");
        std::string line, last_error;
        while (std::getline(log, line)) {
            if (!last_error.empty() || line.find("[error]") != std::string::npos) last_error += line + "\n";
        }
        if (!last_error.empty()) fmt::print(stderr, "{}", last_error);
        fmt::print(stderr, "lpss-cluster: {} failed ({}); see the logs in {}\n",
                   failed_worker ? fmt::format("worker {}", *failed_worker)
                   : taken_over  ? std::string("the standby coordinator")
                                 : std::string("the coordinator"),
                   lpss::runtime::describe_exit_code(exit_code), log_dir);
    }
    return exit_code;
}
