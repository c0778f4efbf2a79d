// cluster: lpss-cluster with 2 workers on this machine, for 1k, 10k and 50k drifting bodies: frames per
// second reached, the time from a worker finishing a frame to a client holding it (median, 99th
// percentile), bytes of sector frames per body per frame, handoffs per second; and the same scene in one
// process (the engine lpss-sim runs, timed by Google Benchmark), so that the cost of distribution reads
// as a ratio.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "scenes.hpp"
#include "subcommands.hpp"

#if LPSS_BENCH_DRIVER
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "child_process.hpp"
#include "lpssPubSubTypes.h"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/participant.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#include "lpss_dds/topics.hpp"
#endif

namespace lpss::bench {

#if LPSS_BENCH_DRIVER
namespace {

using Clock = std::chrono::system_clock;

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(std::min<double>(v.size() - 1, std::floor(p * (v.size() - 1) + 0.5)))];
}

double seconds_of(const eprosima::fastrtps::rtps::Time_t& t) { return t.seconds() + t.nanosec() * 1e-9; }

struct ClusterRun {
    double frames_per_second = 0, latency_p50_ms = 0, latency_p99_ms = 0, bytes_per_body_frame = 0;
    double handoffs_per_second = 0;
    std::uint64_t frames = 0;
};

/// `identities`: the folder deploy/security/identities.sh made, for a secured run (this reader then takes
/// its observer identity); empty for a plain one.
ClusterRun run_cluster(const std::string& scene_file, std::size_t bodies, std::uint64_t frames, int domain,
                       const std::filesystem::path& logs, const std::string& identities = "") {
    ClusterRun out;
    auto participant = dds::Participant::create(domain, "", "lpss-bench", {},
                                                identities.empty() ? "" : identities + "/observer");
    if (!participant) throw std::runtime_error(participant.error().message);
    dds::Participant& p = **participant;
    dds::Inbox inbox;
    auto frames_in = std::make_unique<dds::Reader<wire::SectorFrame>>(
        p, p.topic<wire::SectorFramePubSubType>(dds::kSectorFrames),
        dds::reader_qos(dds::kSectorFrameReading), &inbox);
    auto marks_in = std::make_unique<dds::Reader<wire::WorkerFrame>>(
        p, p.topic<wire::WorkerFramePubSubType>(dds::kWorkerFrames), dds::reader_qos(dds::kFrameDelivery),
        &inbox);
    std::vector<std::string> args = {scene_file,
                                     "--workers",
                                     "2",
                                     "--frames",
                                     std::to_string(frames),
                                     "--domain",
                                     std::to_string(domain),
                                     "--quiet",
                                     "--log-dir",
                                     (logs / "cluster-logs").string()};
    if (!identities.empty()) args.insert(args.end(), {"--security", identities});
    auto cluster = runtime::ChildProcess::start(LPSS_CLUSTER_PROGRAM, args, (logs / "cluster.out").string());
    if (!cluster) throw std::runtime_error("cannot start lpss-cluster");

    // Per (worker, frame): when its marker was written, and the sectors (with stamps) it covers.
    struct Pending {
        double written = 0;
        std::vector<std::pair<SectorKey, std::uint64_t>> stamps;
    };
    std::map<std::pair<std::uint32_t, std::uint64_t>, Pending> pending;
    std::map<SectorKey, std::uint64_t> latest;
    std::vector<double> latencies;
    double payload = 0, first = 0, last = 0;
    std::uint64_t handoffs = 0, first_frame = 0, last_frame = 0;
    auto settle = [&](double now) {
        for (auto it = pending.begin(); it != pending.end();) {
            bool held = true;
            for (const auto& [key, stamp] : it->second.stamps) {
                auto seen = latest.find(key);
                held = held && seen != latest.end() && seen->second >= stamp;
            }
            if (!held) {
                ++it;
                continue;
            }
            latencies.push_back(1e3 * (now - it->second.written));
            it = pending.erase(it);
        }
    };
    while (cluster->running()) {
        inbox.wait(std::chrono::milliseconds(5));
        frames_in->take_all([&](const wire::SectorFrame& f, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data) return;
            payload += static_cast<double>(wire::SectorFrame::getCdrSerializedSize(f));
            std::uint64_t& l = latest[dds::from_wire(f.sector())];
            l = std::max(l, f.frame());
        });
        marks_in->take_all([&](const wire::WorkerFrame& m, const dds::fdds::SampleInfo& info) {
            if (!info.valid_data || m.frame() == 0) return;
            Pending entry;
            entry.written = seconds_of(info.source_timestamp);
            for (const auto& w : m.written())
                entry.stamps.emplace_back(dds::from_wire(w.sector()), m.frame());
            pending[{m.worker(), m.frame()}] = std::move(entry);
            handoffs += m.leaving().size();
            const double now = std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
            if (first_frame == 0) {
                first_frame = m.frame();
                first = now;
            }
            last_frame = std::max(last_frame, m.frame());
            last = now;
        });
        settle(std::chrono::duration<double>(Clock::now().time_since_epoch()).count());
    }
    frames_in.reset();
    marks_in.reset();
    participant->reset();
    dds::remove_abandoned_shm(domain);  // the port files our participant leaves
    if (cluster->exit_code().value_or(1) != 0)
        throw std::runtime_error("lpss-cluster failed: see " + logs.string());
    out.frames = last_frame;
    const double span = std::max(1e-9, last - first);
    out.frames_per_second = static_cast<double>(last_frame - first_frame) / span;
    out.latency_p50_ms = percentile(latencies, 0.5);
    out.latency_p99_ms = percentile(latencies, 0.99);
    out.bytes_per_body_frame =
        payload / (static_cast<double>(bodies) * static_cast<double>(std::max<std::uint64_t>(1, last_frame)));
    out.handoffs_per_second = static_cast<double>(handoffs) / span;
    return out;
}

}  // namespace
#endif

#if LPSS_BENCH_DRIVER
namespace {

/// The same runs with and without DDS Security, one after the other, so that their ratio comes from one
/// sitting of the machine.
void run_cluster_security(const Context& context) {
    Table table({"bodies", "moving", "security", "frames", "frames_per_second", "ms_per_frame",
                 "latency_p50_ms", "latency_p99_ms", "bytes_per_body_frame", "ratio_to_plain"});
    std::filesystem::create_directories(context.out);
    const std::filesystem::path work =
        std::filesystem::temp_directory_path() / fmt::format("lpss-bench-cluster-security-{}", ::getpid());
    std::filesystem::create_directories(work);
    const std::string identities = (work / "identities").string();
    const std::string make = std::string(LPSS_SOURCE_DIR) + "/deploy/security/identities.sh init " +
                             identities + " > " + (work / "identities.log").string() + " 2>&1";
    if (std::system(make.c_str()) != 0)
        throw std::runtime_error("identities.sh failed: see " + work.string());
    progress("cluster --security: identities and logs in " + work.string());
    const std::vector<int> counts = context.quick ? std::vector<int>{1000} : std::vector<int>{1000, 10000};
    int domain = 156;
    for (int n : counts) {
        for (int every : {1, 10}) {
            const Scene scene = drifting(n, every);
            const std::filesystem::path file = work / fmt::format("drifting_{}_{}.textproto", n, every);
            std::ofstream(file) << format_scene(scene);
            const std::uint64_t frames = n <= 1000 ? 600 : 200;
            double plain_ms = 0.0;
            for (bool secured : {false, true}) {
                progress(fmt::format("cluster --security: {} bodies, 1 in {} moving, {}", n, every,
                                     secured ? "secured" : "plain"));
                const std::filesystem::path logs =
                    work / fmt::format("{}-{}-{}", n, every, secured ? "secured" : "plain");
                std::filesystem::create_directories(logs);
                const ClusterRun run = run_cluster(file.string(), scene.bodies.size(), frames, domain, logs,
                                                   secured ? identities : "");
                const double ms = 1e3 / run.frames_per_second;
                if (!secured) plain_ms = ms;
                table.add({std::to_string(n), every == 1 ? "all" : "1/" + std::to_string(every),
                           secured ? "secured" : "plain", std::to_string(run.frames),
                           num(run.frames_per_second, 4), num(ms, 4), num(run.latency_p50_ms, 3),
                           num(run.latency_p99_ms, 3), num(run.bytes_per_body_frame, 4),
                           num(ms / plain_ms, 3)});
            }
            ++domain;
        }
    }
    if (!context.keep) std::filesystem::remove_all(work);
    std::string md =
        "The cluster benchmark's scenes (2 workers, unpaced, drifting bodies in sectors of 8; 1,000 and "
        "10,000 bodies), each run plain and then with DDS Security: identities from "
        "deploy/security/identities.sh, the governance it signs (discovery and liveliness protected, every "
        "lpss topic's data and metadata encrypted with AES-GCM), lpss-cluster --security, and this benchmark "
        "reading as an observer. Columns as in the cluster section; ratio_to_plain: ms_per_frame over the "
        "plain run's just before it. bytes_per_body_frame counts the serialized samples before "
        "encryption.\n\n" +
        table.markdown();
    std::string plot = R"(set multiplot layout 1,2
set logscale xy
set xrange [700:14000]
set xlabel 'bodies'
set key top left
set title 'Frame time with and without DDS Security (2 workers)'
set ylabel 'milliseconds per frame'
plot '$CSV' every 4::1 using 1:6 with linespoints pt 7 title 'plain, all moving', \
     '$CSV' every 4::2 using 1:6 with linespoints pt 5 title 'secured, all moving', \
     '$CSV' every 4::3 using 1:6 with linespoints pt 6 title 'plain, 1 in 10 moving', \
     '$CSV' every 4::4 using 1:6 with linespoints pt 4 title 'secured, 1 in 10 moving'
set title 'Worker to reader latency, 99th percentile'
set ylabel 'milliseconds'
plot '$CSV' every 4::1 using 1:8 with linespoints pt 7 title 'plain, all moving', \
     '$CSV' every 4::2 using 1:8 with linespoints pt 5 title 'secured, all moving', \
     '$CSV' every 4::3 using 1:8 with linespoints pt 6 title 'plain, 1 in 10 moving', \
     '$CSV' every 4::4 using 1:8 with linespoints pt 4 title 'secured, 1 in 10 moving'
unset multiplot
)";
    publish(context, "cluster-security", table, "cluster --security: the cost of DDS Security", md, plot);
}

}  // namespace
#endif

void run_cluster(const Context& context) {
#if LPSS_BENCH_DRIVER
    if (context.security) return run_cluster_security(context);
    Table table({"bodies", "moving", "workers", "frames", "frames_per_second", "ms_per_frame",
                 "latency_p50_ms", "latency_p99_ms", "bytes_per_body_frame", "handoffs_per_second",
                 "in_process_ms_per_frame", "ratio_to_in_process"});
    std::filesystem::create_directories(context.out);
    const std::vector<int> counts =
        context.quick ? std::vector<int>{1000} : std::vector<int>{1000, 10000, 50000};
    int domain = 150;
    // Every body moving, and one in ten (a world mostly at rest: partial sector samples carry the movers).
    std::vector<std::pair<int, int>> runs;
    for (int n : counts) {
        runs.emplace_back(n, 1);
        runs.emplace_back(n, 10);
    }
    for (const auto& [n, every] : runs) {
        progress(fmt::format("cluster: {} bodies on 2 workers, 1 in {} moving", n, every));
        const Scene scene = drifting(n, every);
        const std::filesystem::path file = context.out / fmt::format("drifting_{}_{}.textproto", n, every);
        std::ofstream(file) << format_scene(scene);
        const std::uint64_t frames = n <= 1000 ? 600 : n <= 10000 ? 200 : 60;
        // The children's logs go to a folder of this run's own, not beside the results.
        const std::filesystem::path logs = std::filesystem::temp_directory_path() /
                                           fmt::format("lpss-bench-cluster-{}-{}-{}", ::getpid(), n, every);
        std::filesystem::create_directories(logs);
        progress("cluster: logs in " + logs.string());
        const ClusterRun run = run_cluster(file.string(), scene.bodies.size(), frames, domain++, logs);
        progress(fmt::format("cluster: {} bodies in one process", n));
        World world = make_world(scene, EngineOptions{});
        for (int f = 0; f < 10; ++f)
            world.step();
        const double in_process = ms_per_frame(fmt::format("cluster/in-process/{}/{}", n, every), world, 1,
                                               context.quick ? 0.2 : 1.0);
        const double ms = 1e3 / run.frames_per_second;
        table.add({std::to_string(n), every == 1 ? "all" : "1/" + std::to_string(every), "2",
                   std::to_string(run.frames), num(run.frames_per_second, 4), num(ms, 4),
                   num(run.latency_p50_ms, 3), num(run.latency_p99_ms, 3), num(run.bytes_per_body_frame, 4),
                   num(run.handoffs_per_second, 4), num(in_process, 4), num(ms / in_process, 3)});
        std::filesystem::remove(file);
    }
    std::string md =
        "lpss-cluster with 2 workers (as fast as they go, not paced), bodies in a lattice without gravity "
        "in sectors of 8 (blocks of 4 sectors are what workers own); all of them, or one in ten (moving), "
        "drifting at up to 2 units/s, crossing sectors and the border between the workers, the others at "
        "rest until hit. frames_per_second: frames "
        "over the wall time between the first and last end-of-frame marks the benchmark saw. latency: from a "
        "worker writing its end-of-frame mark (DDS source timestamp) to this process holding that mark and a "
        "sample "
        "of every sector it lists. bytes_per_body_frame: serialized sector-frame payload (CDR, without RTPS "
        "headers) per body per frame, partial samples (changed bodies) and complete ones together. "
        "in_process_ms_per_frame: the same scene on the engine in one process "
        "(Google Benchmark, one thread).\n\n" +
        table.markdown();
    std::string plot = R"(set title 'Frame time: two worker processes against one process'
set logscale xy
set xlabel 'bodies'
set ylabel 'milliseconds per frame'
set key top left
plot '$CSV' every 2::1 using 1:6 with linespoints pt 7 title 'lpss-cluster, 2 workers, all moving', \
     '$CSV' every 2::1 using 1:11 with linespoints pt 5 title 'one process (lpss-sim engine), all moving', \
     '$CSV' every 2::2 using 1:6 with linespoints pt 6 title 'lpss-cluster, 2 workers, 1 in 10 moving', \
     '$CSV' every 2::1 using 1:8 with linespoints pt 9 title 'latency p99 (worker to client), all moving'
)";
    publish(context, "cluster", table, "cluster: the cost of distribution", md, plot);
#else
    (void)context;
    throw std::runtime_error("cluster runs in the float build only");
#endif
}

}  // namespace lpss::bench
