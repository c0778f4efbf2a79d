// lpss-worker: a sector worker process. Usually started by lpss-cluster.
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "crash_report.hpp"
#include "heap.hpp"
#include "lpss/common/logging.hpp"
#include "stop_signal.hpp"
#include "worker.hpp"

int main(int argc, char** argv) {
    lpss::runtime::install_crash_report("lpss-worker");
    CLI::App app{"lpss-worker: simulates the sectors the coordinator assigns it"};
    lpss::worker::WorkerOptions options;
    std::string log_level = "info";
    int border_wait_ms = 2000;
    int coordinator_wait_s = 30;
    app.add_option("--id", options.id, "worker id, 1..N")->required()->check(CLI::Range(1u, 1000000u));
    app.add_option("--domain", options.domain, "DDS domain id")->check(CLI::Range(0, 232));
    app.add_option("--profile", options.profile,
                   "Fast DDS XML profile (default: built-in, this machine only)");
    app.add_option("--security", options.security,
                   "DDS Security identity folder (deploy/security/identities.sh; default: none)");
    app.add_option("--threads", options.threads, "threads stepping sectors")->check(CLI::Range(1, 256));
    app.add_option("--border-wait-ms", border_wait_ms, "longest wait for other workers' data before a frame");
    app.add_option("--coordinator-wait-s", coordinator_wait_s, "how long to wait for a coordinator");
    app.add_option("--log-level", log_level, "trace, debug, info, warn, error, off");
    bool rejoin = true;
    app.add_flag("--rejoin,!--no-rejoin", rejoin,
                 "taken as gone or cut off, join the cluster again as a fresh worker (default), or exit 5");
    CLI11_PARSE(app, argc, argv);
    if (lpss::Status st = lpss::set_log_level(log_level); !st) {
        std::fprintf(stderr, "lpss-worker: %s\n", st.error().message.c_str());
        return 2;
    }
    options.border_wait = std::chrono::milliseconds(border_wait_ms);
    options.coordinator_wait = std::chrono::seconds(coordinator_wait_s);
    lpss::runtime::keep_large_buffers_apart();
    const auto& stop = lpss::runtime::install_stop_signal();
    for (;;) {
        auto worker = lpss::worker::Worker::create(options);
        if (!worker) {
            spdlog::error("lpss-worker {}: cannot start: {}", options.id, worker.error().message);
            return 2;
        }
        const int code = (*worker)->run(stop);
        if (code != lpss::worker::kTakenAsGone || !rejoin || stop.load()) return code;
        // Out of the cluster: a fresh participant (new writers, whose histories hold nothing this one wrote)
        // joins it again, as a worker restarted under this id would; under another participant id, so that
        // peers do not take it for the one they knew.
        options.avoid_participant_ids.insert((*worker)->participant_id());
        (*worker).reset();
        spdlog::info("worker {}: joins again as a fresh worker", options.id);
    }
}
