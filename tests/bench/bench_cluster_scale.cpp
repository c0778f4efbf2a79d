// cluster-scale: a large world mostly at rest (scenes::resting_world: N resting bodies of mixed shapes,
// starting asleep, and 1,000 balls thrown across its middle) in lpss-sim and on lpss-cluster with 1, 2
// and 4 workers on this machine, in one run: the time from start to the first frame, milliseconds per
// frame (mean and 99th percentile over the frames after the first), the memory of every process, the
// bytes each worker receives per frame and the share of the world each worker holds. The activity is the
// same at every N: what grows is the resting world, which should cost nothing per frame.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "scenes.hpp"
#include "subcommands.hpp"

#if LPSS_BENCH_DRIVER
#include <unistd.h>

#include <filesystem>
#include <map>

#include "child_process.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#include "lpss_dds/topics.hpp"
#endif

namespace lpss::bench {

#if LPSS_BENCH_DRIVER
namespace {

using Clock = std::chrono::steady_clock;

/// The median over runs of one of their figures.
template <class Run>
double median_of(const std::vector<Run>& runs, double Run::*figure) {
    std::vector<double> values;
    for (const Run& run : runs)
        values.push_back(run.*figure);
    return median(values);
}

std::string read_text(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

/// The first number the pattern's group 1 matches in `text`, or NaN.
double find_number(const std::string& text, const std::string& pattern) {
    std::smatch m;
    if (!std::regex_search(text, m, std::regex(pattern))) return std::nan("");
    return std::stod(m[1].str());
}

double mean(const std::vector<double>& v) {
    double sum = 0.0;
    for (double x : v)
        sum += x;
    return v.empty() ? std::nan("") : sum / static_cast<double>(v.size());
}

double p99(std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, v.size() * 99 / 100)];
}

struct SimRun {
    double load_s = 0, first_frame_ms = 0, mean_ms = 0, p99_ms = 0, rss_mib = 0, peak_mib = 0, pss_mib = 0;
};

SimRun run_sim(const std::filesystem::path& scene, std::uint64_t frames, const std::filesystem::path& logs) {
    const std::filesystem::path sim = std::filesystem::path(LPSS_CLUSTER_PROGRAM).parent_path() / "lpss-sim";
    const std::filesystem::path out = logs / "lpss-sim.out";
    auto child = runtime::ChildProcess::start(
        sim.string(), {scene.string(), "--frames", std::to_string(frames)}, out.string());
    if (!child || !child->wait(std::chrono::hours(1)) || child->exit_code().value_or(1) != 0)
        throw std::runtime_error("lpss-sim failed: see " + out.string());
    const std::string text = read_text(out);
    SimRun r;
    r.load_s = find_number(text, R"(load\s+([0-9.]+) s)");
    r.first_frame_ms = find_number(text, R"(first frame ([0-9.]+) ms)");
    r.mean_ms = find_number(text, R"(mean ([0-9.]+) ms)");
    r.p99_ms = find_number(text, R"(mean [0-9.]+ ms, p99 ([0-9.]+) ms)");
    r.rss_mib = find_number(text, R"(memory\s+([0-9.]+) MiB resident)");
    r.peak_mib = find_number(text, R"(resident at the end, ([0-9.]+) MiB at most)");
    r.pss_mib = find_number(text, R"(proportional set ([0-9.]+) MiB)");
    return r;
}

struct ClusterRun {
    double first_frame_s = 0, mean_ms = 0, p99_ms = 0, rss_mib = 0, peak_mib = 0;
    double pss_mib = 0;                    ///< the processes' proportional sets together, near the last frame
    double bytes_max = 0, bytes_mean = 0;  ///< per worker per frame (max over workers, mean over them)
    double held_share = 0;                 ///< bodies and ghosts of the busiest worker, over all bodies
    double step_max_ms = 0, publish_max_ms = 0;        ///< per frame, mean over frames, the busiest worker
    std::string memory;                                ///< lpss-cluster's memory line
    double coordinator_mib = 0, first_worker_mib = 0;  ///< resident at the last frame
    /// A whole-world client of changes (lpss-watch) beside the cluster, if asked for: its memory at the
    /// end, and the frames it returned.
    double client_mib = 0, client_peak_mib = 0, client_frames = 0;
};

ClusterRun run_cluster(const std::filesystem::path& scene, std::size_t bodies, int workers,
                       std::uint64_t frames, int domain, const std::filesystem::path& logs,
                       bool with_client) {
    auto participant = dds::Participant::create(domain, "", "lpss-bench");
    if (!participant) throw std::runtime_error(participant.error().message);
    dds::Participant& p = **participant;
    dds::Inbox inbox;
    auto marks_in = std::make_unique<dds::Reader<wire::WorkerFrame>>(
        p, p.topic<wire::WorkerFramePubSubType>(dds::kWorkerFrames), dds::reader_qos(dds::kFrameDelivery),
        &inbox);
    std::optional<runtime::ChildProcess> watch;
    if (with_client) {
        // There before the cluster, as a client waiting for the world; it counts frames to the last.
        watch = runtime::ChildProcess::start(
            LPSS_WATCH_PROGRAM,
            {"--domain", std::to_string(domain), "--frames", std::to_string(frames), "--wait-s", "600"},
            (logs / "lpss-watch.out").string());
        if (!watch) throw std::runtime_error("cannot start lpss-watch");
    }
    const auto launched = Clock::now();
    auto cluster = runtime::ChildProcess::start(
        LPSS_CLUSTER_PROGRAM,
        {scene.string(), "--workers", std::to_string(workers), "--frames", std::to_string(frames), "--domain",
         std::to_string(domain), "--quiet", "--log-dir", (logs / "cluster-logs").string()},
        (logs / "cluster.out").string());
    if (!cluster) throw std::runtime_error("cannot start lpss-cluster");

    // Per frame: the marks of the workers that ended it, and when the last of them arrived here.
    std::map<std::uint64_t, std::map<std::uint32_t, wire::WorkerFrame>> marks;
    std::map<std::uint64_t, double> ended;  // seconds since launch
    while (cluster->running()) {
        inbox.wait(std::chrono::milliseconds(5));
        marks_in->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data || m.frame() == 0 || m.worker() == 0) return;
            auto& frame = marks[m.frame()];
            frame[m.worker()] = m;
            if (frame.size() == static_cast<std::size_t>(workers))
                ended[m.frame()] = std::chrono::duration<double>(Clock::now() - launched).count();
        });
    }
    marks_in.reset();
    participant->reset();
    dds::remove_abandoned_shm(domain);  // the port files our participant leaves
    if (cluster->exit_code().value_or(1) != 0)
        throw std::runtime_error("lpss-cluster failed: see " + logs.string());
    if (!ended.count(1) || ended.size() < frames / 2)
        throw std::runtime_error(
            fmt::format("lpss-cluster: only {} frames seen whole: see {}", ended.size(), logs.string()));
    ClusterRun r;
    r.first_frame_s = ended.at(1);
    std::vector<double> intervals;
    for (auto it = std::next(ended.begin()); it != ended.end(); ++it) {
        auto before = ended.find(it->first - 1);
        if (before != ended.end()) intervals.push_back(1e3 * (it->second - before->second));
    }
    r.mean_ms = mean(intervals);
    r.p99_ms = p99(intervals);
    // Frame by frame, for whoever looks into a slow frame: when it ended here, and each worker's times.
    {
        std::ofstream csv(logs / "frames.csv");
        csv << "frame,ended_s,interval_ms,worker,step_ms,wait_ms,publish_ms,received_bytes\n";
        for (const auto& [f, frame] : marks) {
            auto end = ended.find(f);
            auto before = ended.find(f - 1);
            const double interval = end != ended.end() && before != ended.end()
                                        ? 1e3 * (end->second - before->second)
                                        : std::nan("");
            for (const auto& [w, m] : frame)
                csv << f << ',' << (end != ended.end() ? end->second : std::nan("")) << ',' << interval << ','
                    << w << ',' << m.step_ms() << ',' << m.wait_ms() << ',' << m.publish_ms() << ','
                    << m.received_bytes() << '\n';
        }
    }
    std::map<std::uint32_t, std::vector<double>> bytes, steps, publishes;
    for (const auto& [f, frame] : marks) {
        if (f < 2) continue;
        for (const auto& [w, m] : frame) {
            bytes[w].push_back(static_cast<double>(m.received_bytes()));
            steps[w].push_back(m.step_ms());
            publishes[w].push_back(m.publish_ms());
        }
    }
    double sum = 0;
    for (const auto& [w, b] : bytes) {
        r.bytes_max = std::max(r.bytes_max, mean(b));
        sum += mean(b);
        r.step_max_ms = std::max(r.step_max_ms, mean(steps[w]));
        r.publish_max_ms = std::max(r.publish_max_ms, mean(publishes[w]));
    }
    r.bytes_mean = bytes.empty() ? 0 : sum / static_cast<double>(bytes.size());
    for (const auto& [w, m] : marks.rbegin()->second)
        r.held_share = std::max(r.held_share,
                                static_cast<double>(m.bodies() + m.ghosts()) / static_cast<double>(bodies));
    if (watch) {
        // It ends after the last frame, or gives up once frames stop coming (those it missed never come).
        watch->wait(std::chrono::seconds(20));
        watch->stop();
        const std::string watched = read_text(logs / "lpss-watch.out");
        r.client_frames = find_number(watched, R"(lpss-watch: ([0-9]+) frames;)");
        r.client_mib = find_number(watched, R"(memory ([0-9.]+) MiB resident)");
        r.client_peak_mib = find_number(watched, R"(([0-9.]+) MiB at most)");
    }
    const std::string text = read_text(logs / "cluster.out");
    r.coordinator_mib =
        find_number(text, R"(memory at frame [0-9]+: [0-9.]+ MiB resident \(coordinator ([0-9.]+))");
    r.first_worker_mib = find_number(text, R"(memory at frame [0-9]+: [^\n]*worker 1 ([0-9.]+))");
    r.rss_mib = find_number(text, R"(memory at frame [0-9]+: ([0-9.]+) MiB resident)");
    r.peak_mib = find_number(text, R"(\), ([0-9.]+) MiB at most)");
    r.pss_mib = find_number(text, R"(memory at frame [^\n]*counted once\) ([0-9.]+) MiB at frame)");
    std::smatch line;
    if (std::regex_search(text, line, std::regex(R"(memory at frame [^\n]*)"))) r.memory = line.str();
    return r;
}

}  // namespace
#endif

void run_cluster_scale(const Context& context) {
#if LPSS_BENCH_DRIVER
    Table table({"bodies",
                 "workers",
                 "first_frame_s",
                 "sim_load_s",
                 "start_ratio",
                 "ms_per_frame",
                 "p99_ms",
                 "sim_ms_per_frame",
                 "sim_p99_ms",
                 "frame_budget_ms",
                 "rss_mib",
                 "sim_rss_mib",
                 "rss_ratio",
                 "pss_mib",
                 "sim_pss_mib",
                 "pss_ratio",
                 "peak_mib",
                 "sim_peak_mib",
                 "bytes_per_worker_frame_max",
                 "bytes_per_worker_frame_mean",
                 "held_share_max",
                 "step_ms_max",
                 "publish_ms_max",
                 "rounds",
                 "budget_ratio",
                 "budget_ratio_low",
                 "budget_ratio_high"});
    std::filesystem::create_directories(context.out);
    const std::vector<std::size_t> sizes = !context.sizes.empty() ? context.sizes
                                           : context.quick        ? std::vector<std::size_t>{10000, 30000}
                                                           : std::vector<std::size_t>{10000, 100000, 1000000};
    const std::vector<int> worker_counts = context.quick ? std::vector<int>{1, 2} : std::vector<int>{1, 2, 4};
    const std::size_t moving = 1000;
    const std::uint64_t frames = context.quick ? 120 : 300;
    const unsigned rounds = context.rounds ? context.rounds : (context.quick ? 1u : 3u);
    int domain = 170;
    std::string memory_lines;
    struct Held {  // resident MiB at each size
        std::vector<double> sizes, sim, worker, coordinator, client;
    } held;
    Table clients({"bodies", "frames_seen", "frames", "client_rss_mib", "client_peak_mib", "ms_per_frame"});
    for (std::size_t n : sizes) {
        // Scenes and logs go to a folder of this run's own (a million bodies is 150 MB of text).
        const std::filesystem::path logs =
            std::filesystem::temp_directory_path() / fmt::format("lpss-bench-scale-{}-{}", ::getpid(), n);
        std::filesystem::create_directories(logs);
        progress(fmt::format("cluster-scale: writing a world of {} resting bodies and {} balls ({})", n,
                             moving, logs.string()));
        const std::filesystem::path scene = logs / "world.textproto";
        std::ofstream(scene) << format_scene(scenes::resting_world(n, moving));
        // Round after round, lpss-sim and then every cluster, each cluster's frame compared with the lpss-sim
        // frame of its own round: this shared machine's slow spells last minutes, and the ratio of a single
        // run moved by 10-15% from run to run. Each figure below is the median over the rounds.
        std::vector<SimRun> sims;
        std::map<int, std::vector<ClusterRun>> runs;
        for (unsigned round = 1; round <= rounds; ++round) {
            const std::filesystem::path round_logs = logs / fmt::format("round-{}", round);
            std::filesystem::create_directories(round_logs);
            progress(fmt::format("cluster-scale: {} bodies in lpss-sim (round {} of {})", n, round, rounds));
            sims.push_back(run_sim(scene, frames, round_logs));
            for (int workers : worker_counts) {
                progress(fmt::format("cluster-scale: {} bodies on {} worker(s) (round {} of {})", n, workers,
                                     round, rounds));
                const std::filesystem::path run_logs = round_logs / fmt::format("workers-{}", workers);
                std::filesystem::create_directories(run_logs);
                runs[workers].push_back(
                    run_cluster(scene, n + moving + 1, workers, frames, domain++, run_logs, false));
            }
        }
        const double sim_ms = median_of(sims, &SimRun::mean_ms);
        const double sim_load_s = median_of(sims, &SimRun::load_s);
        const double sim_rss = median_of(sims, &SimRun::rss_mib);
        const double sim_pss = median_of(sims, &SimRun::pss_mib);
        for (int workers : worker_counts) {
            const std::vector<ClusterRun>& c = runs.at(workers);
            // Ratios round by round, each against its own round's lpss-sim.
            std::vector<double> budget, start, rss, pss;
            for (std::size_t r = 0; r < c.size(); ++r) {
                budget.push_back(c[r].mean_ms / (1.5 * sims[r].mean_ms + 1.0));
                start.push_back(c[r].first_frame_s / sims[r].load_s);
                rss.push_back(c[r].rss_mib / sims[r].rss_mib);
                pss.push_back(c[r].pss_mib / sims[r].pss_mib);
            }
            if (workers == 1) {
                held.coordinator.push_back(median_of(c, &ClusterRun::coordinator_mib));
                held.worker.push_back(median_of(c, &ClusterRun::first_worker_mib));
            }
            memory_lines += fmt::format("- {} bodies, {} worker(s), round {}: {}\n", n, workers, c.size(),
                                        c.back().memory);
            table.add({std::to_string(n),
                       std::to_string(workers),
                       num(median_of(c, &ClusterRun::first_frame_s), 4),
                       num(sim_load_s, 4),
                       num(median(start), 3),
                       num(median_of(c, &ClusterRun::mean_ms), 4),
                       num(median_of(c, &ClusterRun::p99_ms), 4),
                       num(sim_ms, 4),
                       num(median_of(sims, &SimRun::p99_ms), 4),
                       num(1.5 * sim_ms + 1.0, 4),
                       num(median_of(c, &ClusterRun::rss_mib), 5),
                       num(sim_rss, 5),
                       num(median(rss), 3),
                       num(median_of(c, &ClusterRun::pss_mib), 5),
                       num(sim_pss, 5),
                       num(median(pss), 3),
                       num(median_of(c, &ClusterRun::peak_mib), 5),
                       num(median_of(sims, &SimRun::peak_mib), 5),
                       num(median_of(c, &ClusterRun::bytes_max), 5),
                       num(median_of(c, &ClusterRun::bytes_mean), 5),
                       num(median_of(c, &ClusterRun::held_share), 3),
                       num(median_of(c, &ClusterRun::step_max_ms), 4),
                       num(median_of(c, &ClusterRun::publish_max_ms), 4),
                       std::to_string(c.size()),
                       num(median(budget), 3),
                       num(*std::min_element(budget.begin(), budget.end()), 3),
                       num(*std::max_element(budget.begin(), budget.end()), 3)});
        }
        // A whole-world client of changes beside 2 workers: what a client holds, and whether it keeps up.
        progress(fmt::format("cluster-scale: {} bodies on 2 workers, with a whole-world client", n));
        const std::filesystem::path client_logs = logs / "client";
        std::filesystem::create_directories(client_logs);
        const ClusterRun c = run_cluster(scene, n + moving + 1, 2, frames, domain++, client_logs, true);
        held.sizes.push_back(static_cast<double>(n + moving + 1));
        held.sim.push_back(sim_rss);
        held.client.push_back(c.client_mib);
        clients.add({std::to_string(n), num(c.client_frames, 4), std::to_string(frames), num(c.client_mib, 5),
                     num(c.client_peak_mib, 5), num(c.mean_ms, 4)});
        if (!context.keep) std::filesystem::remove_all(logs);
    }
    // Per body: the slope of resident memory from the smallest world to the largest (what a body adds),
    // and what the process holds with no body (the intercept).
    Table per_body({"process", "bytes_per_body", "fixed_mib", "resident_mib_at_largest"});
    auto slope = [&](const std::string& name, const std::vector<double>& mib) {
        if (mib.size() < 2) return;
        const double dn = held.sizes.back() - held.sizes.front();
        const double per = (mib.back() - mib.front()) * 1048576.0 / dn;
        per_body.add({name, num(per, 4), num(mib.front() - per * held.sizes.front() / 1048576.0, 3),
                      num(mib.back(), 5)});
    };
    slope("lpss-sim (the whole world)", held.sim);
    slope("worker holding the whole world (1 worker)", held.worker);
    slope("coordinator", held.coordinator);
    slope("whole-world client of changes (lpss-watch)", held.client);
    const std::string md =
        fmt::format(
            "scenes::resting_world: N resting bodies of five shapes, 3 units apart on a ground plane, "
            "starting asleep, in sectors of 64; {} balls thrown across the middle (the same at every N). "
            "{} frames, unpaced. Each size is run {} time(s) over, lpss-sim and then each cluster in "
            "turn; every figure is the median over those rounds, and every ratio is taken within its round "
            "(start_ratio, rss_ratio, pss_ratio; budget_ratio: the cluster's mean frame over 1.5 x its "
            "round's lpss-sim mean + 1 ms, the target being 1 or less, with budget_ratio_low and "
            "budget_ratio_high its extremes over the rounds, the bars in the plot). first_frame_s: from "
            "starting lpss-cluster to the first frame ended by "
            "every worker (as a DDS reader beside the cluster sees it); sim_load_s: lpss-sim reading the "
            "scene and building its world. ms_per_frame, p99_ms: time between frames ended by every "
            "worker, frames 2 on; sim_: lpss-sim's frames 2 on; frame_budget_ms: 1.5 x lpss-sim's mean "
            "+ 1 ms, the target. rss_mib: the resident memory of every process together, taken at the "
            "last frame (lpss-cluster's report); pss_mib: the processes' proportional sets together (Pss: a "
            "page n processes share counted 1/n, so each library's code once), near the last frame; "
            "peak_mib: the sum of each process's most. "
            "bytes_per_worker_frame: serialized sector samples a worker received per frame (mean over "
            "frames; the busiest worker, and the mean over workers). held_share_max: bodies and ghosts "
            "of the worker holding most, over the world's bodies. step_ms_max, publish_ms_max: the "
            "busiest worker's engine step and sample writing per frame.\n\n",
            moving, frames, rounds) +
        table.markdown() + "\nMemory of each process (resident, and at most):\n\n" + memory_lines +
        "\nA whole-world client beside 2 workers (lpss-watch: lpss::Client with FrameContent::changes, "
        "started before the cluster): the frames it returned of those the cluster ran, its memory at the "
        "end, and the cluster's ms per frame with it there.\n\n" +
        clients.markdown() +
        "\nMemory per body: the slope of each process's resident memory from the smallest world to the "
        "largest, and the intercept (what it holds with no body: DDS, code, pools).\n\n" +
        per_body.markdown();
    const std::string plot =
        R"(set multiplot layout 2,2 title 'A world at rest: lpss-cluster against lpss-sim on the same scene (targets dotted)'
set datafile missing NaN
set logscale x
set xrange [7000:1.5e6]
set yrange [0:*]
set xlabel 'bodies at rest'
set key top right font ',8'
set grid
set ylabel 'first frame / lpss-sim load'
set title 'Start: time to the first frame, over lpss-sim loading the scene (worker counts offset)'
plot '$CSV' using ($1*0.94):($2==1?$5:NaN) with linespoints pt 7 lc 1 title '1 worker', \
     '$CSV' using 1:($2==2?$5:NaN) with linespoints pt 5 lc 2 title '2 workers', \
     '$CSV' using ($1*1.06):($2==4?$5:NaN) with linespoints pt 9 lc 3 title '4 workers', \
     1.5 with lines dt 3 lc rgb 'black' title 'target 1.5'
set ylabel 'ms per frame / (1.5 x lpss-sim + 1 ms)'
set title "Running: frame over its budget, rounds' median and range; p99 open"
set key top left maxrows 4 width 1 samplen 2
set logscale y
set yrange [0.5:12]
set ytics (0.5, 0.75, 1, 1.5, 2, 3, 5, 8, 12)
plot '$CSV' using ($1*0.94):($2==1?$25:NaN):26:27 with yerrorlines pt 7 lc 1 title '1 worker', \
     '$CSV' using 1:($2==2?$25:NaN):26:27 with yerrorlines pt 5 lc 2 title '2 workers', \
     '$CSV' using ($1*1.06):($2==4?$25:NaN):26:27 with yerrorlines pt 9 lc 3 title '4 workers', \
     '$CSV' using ($1*0.94):($2==1?$7/$10:NaN) with points pt 6 lc 1 title '1 worker p99', \
     '$CSV' using 1:($2==2?$7/$10:NaN) with points pt 4 lc 2 title '2 workers p99', \
     '$CSV' using ($1*1.06):($2==4?$7/$10:NaN) with points pt 8 lc 3 title '4 workers p99', \
     '$CSV' using 1:($2==1?$9/$10:NaN) with points pt 12 lc 4 title 'lpss-sim p99', \
     1 with lines dt 3 lc rgb 'black' title 'target'
unset logscale y
set yrange [0:*]
set ytics autofreq
set key default
set key top right font ',8'
set ylabel 'all processes / lpss-sim'
set title 'Memory, all processes over lpss-sim: resident (solid), shared pages once (dashed)'
set key top right font ',8' maxrows 3
plot '$CSV' using ($1*0.94):($2==1?$13:NaN) with linespoints pt 7 lc 1 title '1 worker', \
     '$CSV' using 1:($2==2?$13:NaN) with linespoints pt 5 lc 2 title '2 workers', \
     '$CSV' using ($1*1.06):($2==4?$13:NaN) with linespoints pt 9 lc 3 title '4 workers', \
     '$CSV' using ($1*0.94):($2==1?$16:NaN) with linespoints dt 2 pt 6 lc 1 title '1, Pss', \
     '$CSV' using 1:($2==2?$16:NaN) with linespoints dt 2 pt 4 lc 2 title '2, Pss', \
     '$CSV' using ($1*1.06):($2==4?$16:NaN) with linespoints dt 2 pt 8 lc 3 title '4, Pss', \
     1.5 with lines dt 3 lc rgb 'black' title 'target 1.5'
set ylabel 'kB per frame'
set title 'Bytes the busiest worker receives per frame'
set key default
set key bottom right font ',8'
plot '$CSV' using 1:($2==2?$19/1000:NaN) with linespoints pt 5 lc 2 title '2 workers', \
     '$CSV' using 1:($2==4?$19/1000:NaN) with linespoints pt 9 lc 3 title '4 workers'
unset multiplot
)";
    publish(context, "cluster-scale", table, "cluster-scale: a world at rest, from 10^4 to 10^6 bodies", md,
            plot);
#else
    (void)context;
    throw std::runtime_error("cluster-scale runs in the float build only");
#endif
}

}  // namespace lpss::bench
