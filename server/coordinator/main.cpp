// lpss-coordinator: owns sector assignment, frame starts, handoffs and command order. Usually started by
// lpss-cluster.
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "coordinator.hpp"
#include "crash_report.hpp"
#include "heap.hpp"
#include "lpss/common/logging.hpp"
#include "stop_signal.hpp"

int main(int argc, char** argv) {
    lpss::runtime::install_crash_report("lpss-coordinator");
    CLI::App app{"lpss-coordinator: assigns sectors, starts frames, arbitrates handoffs and commands"};
    lpss::coordinator::CoordinatorOptions o;
    std::string log_level = "info";
    int worker_wait_s = 30, worker_timeout_ms = 5000, standby_wait_s = 20;
    app.add_option("scene", o.scene_path, "scene file (Protobuf text format)")->required();
    app.add_option("--workers", o.workers, "number of workers (ids 1..N)")->check(CLI::Range(1u, 4096u));
    app.add_option("--frames", o.frames, "stop after this many frames (0: until stopped)");
    app.add_flag("--realtime", o.realtime, "pace frames at the scene's dt");
    app.add_option("--domain", o.domain, "DDS domain id")->check(CLI::Range(0, 232));
    app.add_option("--profile", o.profile, "Fast DDS XML profile (default: built-in, this machine only)");
    app.add_option("--security", o.security,
                   "DDS Security identity folder (deploy/security/identities.sh; default: none)");
    app.add_option("--block-size", o.block_size, "sectors per block edge in assignments")
        ->check(CLI::Range(1, 1 << 20));
    app.add_option("--rebalance-every", o.rebalance_every, "frames between load checks (0: never)");
    app.add_option("--await-clients", o.await_clients,
                   "frame 1 waits until this many clients have matched every topic they read");
    app.add_option("--command-rate", o.command_rate,
                   "commands a second one client may send, in bursts of as many (0: no limit)")
        ->check(CLI::Range(0.0, 1e9));
    app.add_option(
        "--worker-wait-s", worker_wait_s,
        "how long to wait for the workers to appear, and for one to join once every worker is gone");
    app.add_option("--worker-timeout-ms", worker_timeout_ms, "silence after which a worker is taken as gone");
    app.add_flag(
        "--standby", o.standby,
        "follow the coordinator that runs the world, and take over when it is gone (id 2 unless --id)");
    app.add_option("--id", o.id, "this coordinator's id (1: the one that starts the world)")
        ->check(CLI::Range(1u, 1000u));
    app.add_flag("--await-standby", o.await_standby,
                 "frame 1 waits for a standby coordinator, and every frame until it holds the frame's start");
    app.add_option(
           "--standby-wait-s", standby_wait_s,
           "with --await-standby: how long frame 1 waits for the standby to say it stands by before the "
           "world starts without one")
        ->check(CLI::Range(0, 3600));
    app.add_option("--log-level", log_level, "trace, debug, info, warn, error, off");
    CLI11_PARSE(app, argc, argv);
    if (o.standby && app.count("--id") == 0) o.id = 2;
    if (lpss::Status st = lpss::set_log_level(log_level); !st) {
        std::fprintf(stderr, "lpss-coordinator: %s\n", st.error().message.c_str());
        return 2;
    }
    o.worker_wait = std::chrono::seconds(worker_wait_s);
    o.worker_timeout = std::chrono::milliseconds(worker_timeout_ms);
    o.standby_wait = std::chrono::seconds(standby_wait_s);
    lpss::runtime::keep_large_buffers_apart();
    const auto& stop = lpss::runtime::install_stop_signal();
    auto coordinator = lpss::coordinator::Coordinator::create(o);
    if (!coordinator) {
        spdlog::error("lpss-coordinator: cannot start: {}", coordinator.error().message);
        return 2;
    }
    return (*coordinator)->run(stop);
}
