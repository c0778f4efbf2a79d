// late-join: clients joining a running cluster (lpss-cluster, 2 workers, --realtime, 2,000 bodies, one
// in ten drifting), one after another: how long each takes to match the cluster (lpss::Client::
// wait_for_cluster) and to show its first frame (whole: an inventory from every worker and every sector it
// lists). Issue 10 asks for a late joiner matched within 0.5 s on this machine. Joins alternate between
// lpss's default and LPSS_DDS_DISCOVERY_PROMPT=0 (participant.cpp), so that what the prompt buys is measured
// side by side in one run.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "subcommands.hpp"

#if LPSS_BENCH_DRIVER
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

#include "child_process.hpp"
#include "lpss/client/client.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#include "lpss_dds/topics.hpp"
#endif

namespace lpss::bench {

void run_late_join(const Context& context) {
#if LPSS_BENCH_DRIVER
    using Clock = std::chrono::steady_clock;
    Table table({"join", "discovery_prompt", "seconds_to_matched", "seconds_to_first_frame", "first_frame",
                 "world_frames_per_s"});
    std::filesystem::create_directories(context.out);
    const int domain = 170;
    const std::filesystem::path file = context.out / "late_join.textproto";
    std::ofstream(file) << format_scene(drifting(2000, 10));
    const std::filesystem::path logs =
        std::filesystem::temp_directory_path() / fmt::format("lpss-bench-late-join-{}", ::getpid());
    std::filesystem::create_directories(logs);
    progress("late-join: logs in " + logs.string());
    auto cluster = runtime::ChildProcess::start(
        LPSS_CLUSTER_PROGRAM,
        {file.string(), "--workers", "2", "--realtime", "--frames", "36000", "--domain",
         std::to_string(domain), "--quiet", "--log-dir", (logs / "cluster-logs").string()},
        (logs / "cluster.out").string());
    if (!cluster) throw std::runtime_error("cannot start lpss-cluster");
    auto connect = [&](const std::string& name) {
        ClientOptions o;
        o.domain = domain;
        o.name = name;
        Expected<std::unique_ptr<Client>> c = Client::connect(o);
        if (!c) throw std::runtime_error(c.error().message);
        return std::move(c).value();
    };
    // How fast the world runs while each client joins (the scene's bodies spread over ever more sectors,
    // and the machine's two cores fill up): from the workers' marks, read apart from the clients.
    auto watcher = dds::Participant::create(domain, "", "lpss-bench-late-join");
    if (!watcher) throw std::runtime_error(watcher.error().message);
    dds::Reader<wire::WorkerFrame> marks(**watcher,
                                         (*watcher)->topic<wire::WorkerFramePubSubType>(dds::kWorkerFrames),
                                         dds::reader_qos(dds::kMarksReading), nullptr);
    std::uint64_t newest = 0;
    auto newest_frame = [&] {
        marks.take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
            if (info.valid_data) newest = std::max<std::uint64_t>(newest, m.frame());
        });
        return newest;
    };
    // Joins start once the world runs.
    {
        auto probe = connect("late-join-probe");
        const auto end = Clock::now() + std::chrono::seconds(120);
        while (probe->poll(std::chrono::milliseconds(20)).empty()) {
            if (Clock::now() > end || !cluster->running())
                throw std::runtime_error("the cluster did not run: see " + logs.string());
        }
    }
    const int joins = context.quick ? 4 : 30;
    // [0]: without the discovery prompt, [1]: with it (lpss's default).
    std::vector<double> matched[2], first[2];
    int never[2] = {0, 0};
    for (int k = 1; k <= joins; ++k) {
        const int prompt = k % 2 == 0 ? 1 : 0;
        const std::string prompt_cell = prompt ? "yes" : "no";
        const auto start = Clock::now();
        const std::uint64_t frame_at_start = newest_frame();
        // Read by Participant::create, in this thread, while no other participant is being created.
        if (prompt)
            ::unsetenv("LPSS_DDS_DISCOVERY_PROMPT");
        else
            ::setenv("LPSS_DDS_DISCOVERY_PROMPT", "0", 1);
        auto client = connect(fmt::format("late-join-{}", k));
        ::unsetenv("LPSS_DDS_DISCOVERY_PROMPT");
        // Matched: it reaches the coordinator and every worker (wait_for_cluster also returns at its limit).
        const bool found = client->wait_for_cluster(std::chrono::seconds(30)) && client->reaches_cluster();
        const double to_match = std::chrono::duration<double>(Clock::now() - start).count();
        std::uint64_t frame = 0;
        while (frame == 0 && Clock::now() - start < std::chrono::seconds(30)) {
            for (const WorldFrame& f : client->poll(std::chrono::milliseconds(5)))
                frame = frame == 0 ? f.frame : frame;
            newest_frame();
        }
        const double to_frame = std::chrono::duration<double>(Clock::now() - start).count();
        const std::string rate = num(static_cast<double>(newest_frame() - frame_at_start) / to_frame, 3);
        if (!found || frame == 0) {
            // Recorded, not thrown: a joiner that never shows a frame is the finding this run exists for.
            ++never[prompt];
            table.add(
                {std::to_string(k), prompt_cell, found ? num(to_match, 3) : "never", "never", "-", rate});
            progress(fmt::format("late-join: {} {} and showed no frame in 30 s; logs in {}", k,
                                 found ? "matched" : "never matched", logs.string()));
            client.reset();
            continue;
        }
        matched[prompt].push_back(to_match);
        first[prompt].push_back(to_frame);
        table.add({std::to_string(k), prompt_cell, num(to_match, 3), num(to_frame, 3), std::to_string(frame),
                   rate});
        progress(
            fmt::format("late-join: {} ({} prompt) matched after {:.3f} s, first frame {} after {:.3f} s", k,
                        prompt ? "with" : "without", to_match, frame, to_frame));
        client.reset();
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
    cluster->stop(std::chrono::seconds(10));
    dds::remove_abandoned_shm(domain);
    auto quantile = [](std::vector<double> v, double q) {
        if (v.empty()) return std::nan("");
        std::sort(v.begin(), v.end());
        return v[static_cast<std::size_t>(std::floor(q * static_cast<double>(v.size() - 1) + 0.5))];
    };
    auto summary = [&](int prompt) {
        const std::vector<double>& m = matched[prompt];
        const std::vector<double>& f = first[prompt];
        const int n = static_cast<int>(m.size()) + never[prompt];
        const auto within = std::count_if(m.begin(), m.end(), [](double s) { return s <= 0.5; });
        return fmt::format(
            "{} ({} joins). Matched: median {:.3f} s, 90th percentile {:.3f} s, at most {:.3f} s; {} of {} "
            "within 0.5 s. First frame: median {:.3f} s, 90th percentile {:.3f} s, at most {:.3f} s, of "
            "those "
            "that showed one; {} of {} showed no frame within 30 s.\n\n",
            prompt ? "**With the discovery prompt** (lpss's default)"
                   : "**Without it** (LPSS_DDS_DISCOVERY_PROMPT=0, as before 2026-12-03)",
            n, quantile(m, 0.5), quantile(m, 0.9),
            m.empty() ? std::nan("") : *std::max_element(m.begin(), m.end()), within, n, quantile(f, 0.5),
            quantile(f, 0.9), f.empty() ? std::nan("") : *std::max_element(f.begin(), f.end()), never[prompt],
            n);
    };
    std::string md = fmt::format(
        "{} clients joined a running lpss-cluster (2 workers, --realtime, 2,000 bodies in sectors of 8, one "
        "in ten drifting), one after another, 0.3 s apart, each a new DDS participant in this process; "
        "every other one without the discovery prompt (docs/operations.md, \"Late joiners\"). "
        "seconds_to_matched: from creating the client to `wait_for_cluster` returning (its command writer "
        "and result reader matched the coordinator and every worker). seconds_to_first_frame: to its first "
        "frame, whole (an inventory from every worker, with every sector it lists). world_frames_per_s: how "
        "fast the world ran meanwhile (60 is real time), from the workers' marks.\n\n",
        joins);
    md += summary(1) + summary(0);
    md += table.markdown();
    // Every join is drawn: one that showed no frame at the 30 s it waited, with its own mark; seconds on a
    // log axis (matching takes 0.02-1 s, a first frame up to tens).
    const std::string plot = fmt::format(
        R"(set title 'Clients joining a running cluster, one after another (2 workers, 2,000 bodies drifting apart)'
set xlabel 'join, in order (the world runs on between joins; odd joins without the discovery prompt)'
set ylabel 'seconds (log)'
set y2label 'world frames per second while it joined'
set logscale y
set yrange [0.005:100]
set y2range [0:80]
set y2tics
set ytics nomirror
set xrange [0.5:{}.5]
set key top left
plot '$CSV' using 1:(strcol(4) eq 'never' || strcol(2) eq 'no' ? NaN : $4) with points pt 7 ps 1.5 lc rgb 'dark-green' title 'first frame, with the discovery prompt', \
     '$CSV' using 1:(strcol(4) eq 'never' || strcol(2) eq 'yes' ? NaN : $4) with points pt 6 ps 1.5 lc rgb 'dark-orange' title 'first frame, without', \
     '$CSV' using 1:(strcol(3) eq 'never' || strcol(2) eq 'no' ? NaN : $3) with points pt 5 lc rgb 'dark-green' title 'matched, with the discovery prompt', \
     '$CSV' using 1:(strcol(3) eq 'never' || strcol(2) eq 'yes' ? NaN : $3) with points pt 4 lc rgb 'dark-orange' title 'matched, without', \
     '$CSV' using 1:(strcol(4) eq 'never' ? 30 : NaN) with points pt 2 ps 2.5 lw 2 lc rgb 'red' title 'no first frame within 30 s (drawn at 30)', \
     '$CSV' using 1:(strcol(3) eq 'never' ? 60 : NaN) with points pt 3 ps 2.5 lw 2 lc rgb 'red' title 'never matched (drawn at 60)', \
     '$CSV' using 1:6 axes x1y2 with linespoints dt 3 lc rgb 'gray40' title 'world frames/s (right axis)', \
     0.5 with lines dt 2 lc rgb 'blue' title 'target: matched within 0.5 s'
)",
        joins);
    publish(context, "late-join", table, "late-join: clients joining a running cluster", md, plot);
#else
    (void)context;
    throw std::runtime_error("late-join runs in the float build only");
#endif
}

}  // namespace lpss::bench
