// Running lpss-cluster from a test: each test on a DDS domain of its own, the whole test process (and so
// its children) in a network namespace holding only loopback when the machine allows it (see main in
// cluster_test_main.cpp), children stopped and logs kept in the test process's folder (test_workspace.hpp).
#pragma once

#include <dirent.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "child_process.hpp"
#include "lpss/client/client.hpp"
#include "lpss/common/scene.hpp"
#include "lpss/common/state_csv.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#include "test_workspace.hpp"

namespace lpss::testing {

/// Writes a scene to a file of the test's own and returns its path.
inline std::string write_scene(const Scene& scene, const std::string& name) {
    const std::string path = workspace_path(name + ".textproto");
    std::ofstream(path) << format_scene(scene);
    return path;
}

/// Removes what an earlier run left under `stem` (a file or folder, and the files beside it named after it:
/// stem.x, stem-x). ChildProcess appends to a log that exists, so a test would read an earlier run's lines
/// as its own (seen: an example's output holding two runs, a test counting twice the reports it expected).
/// The process's folder starts empty (test_workspace.hpp); this covers a test run again in one process
/// (--gtest_repeat).
inline void remove_stale(const std::string& stem) {
    namespace fs = std::filesystem;
    const fs::path path(stem);
    const std::string name = path.filename().string();
    std::error_code ec;
    std::vector<fs::path> stale;
    for (const fs::directory_entry& e : fs::directory_iterator(path.parent_path(), ec)) {
        const std::string other = e.path().filename().string();
        const bool beside = other.size() > name.size() && other.compare(0, name.size(), name) == 0 &&
                            (other[name.size()] == '.' || other[name.size()] == '-');
        if (other == name || beside) stale.push_back(e.path());
    }
    for (const fs::path& p : stale)
        fs::remove_all(p, ec);
}

/// Removes what the test's processes leave in /dev/shm on its domain (a killed worker's segment, every
/// participant's port files) when the test ends. Declare it before the test's clients and clusters, so that
/// they have gone by then.
class DomainCleanup {
public:
    explicit DomainCleanup(int domain) : domain_(domain) {}
    ~DomainCleanup() { dds::remove_abandoned_shm(domain_); }
    DomainCleanup(const DomainCleanup&) = delete;
    DomainCleanup& operator=(const DomainCleanup&) = delete;

private:
    int domain_;
};

/// The last lines of every log of a cluster run: the files in `log_dir` and those beside it named after it
/// (its output, workers started by the test), so that a test failing where no one kept its folder (CI) says
/// what the processes were doing.
inline std::string log_tails(const std::string& log_dir, std::size_t lines = 30) {
    namespace fs = std::filesystem;
    std::vector<fs::path> files;
    std::error_code ec;
    for (const fs::directory_entry& e : fs::directory_iterator(log_dir, ec))
        files.push_back(e.path());
    const fs::path dir(log_dir);
    for (const fs::directory_entry& e : fs::directory_iterator(dir.parent_path(), ec)) {
        const std::string name = e.path().filename().string();
        if (e.is_regular_file() && name.rfind(dir.filename().string() + ".", 0) == 0)
            files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    std::string out;
    for (const fs::path& file : files) {
        std::ifstream in(file);
        std::vector<std::string> all;
        for (std::string line; std::getline(in, line);)
            all.push_back(std::move(line));
        out += "---- " + file.string() + " (last " + std::to_string(std::min(lines, all.size())) + " of " +
               std::to_string(all.size()) + " lines)\n";
        for (std::size_t n = all.size() > lines ? all.size() - lines : 0; n < all.size(); ++n)
            out += all[n] + "\n";
    }
    return out;
}

/// Prints the tails of a cluster's logs when it goes, if the test has failed by then.
class LogsOnFailure {
public:
    explicit LogsOnFailure(std::string log_dir = {}) : log_dir_(std::move(log_dir)) {}
    LogsOnFailure(LogsOnFailure&& other) noexcept : log_dir_(std::exchange(other.log_dir_, {})) {}
    LogsOnFailure& operator=(LogsOnFailure&& other) noexcept {
        log_dir_ = std::exchange(other.log_dir_, {});
        return *this;
    }
    ~LogsOnFailure() {
        if (!log_dir_.empty() && ::testing::Test::HasFailure())
            std::printf("the cluster's logs, as the test ends:\n%s", log_tails(log_dir_).c_str());
    }

private:
    std::string log_dir_;
};

struct ClusterRun {
    LogsOnFailure logs;  ///< first, so that it goes last, once the processes have stopped
    std::optional<runtime::ChildProcess> process;
    std::string log_dir;
};

/// Starts lpss-cluster on `domain` (--realtime unless `fast`), its logs in a folder of the test's own.
inline ClusterRun start_cluster(const std::string& scene, int domain, int workers, std::uint64_t frames,
                                std::vector<std::string> extra = {}, bool fast = false) {
    ClusterRun run;
    run.log_dir = workspace_path("lpss_cluster_" + std::to_string(domain));
    remove_stale(run.log_dir);
    std::vector<std::string> args = {scene,
                                     "--workers",
                                     std::to_string(workers),
                                     "--frames",
                                     std::to_string(frames),
                                     "--domain",
                                     std::to_string(domain),
                                     "--quiet",
                                     "--log-dir",
                                     run.log_dir};
    if (!fast) args.push_back("--realtime");
    args.insert(args.end(), extra.begin(), extra.end());
    run.process = runtime::ChildProcess::start(LPSS_CLUSTER, args, run.log_dir + ".out");
    run.logs = LogsOnFailure(run.log_dir);
    return run;
}

/// A client on `domain`, waiting for a cluster; `security`: its DDS Security identity folder, if any.
inline std::unique_ptr<Client> connect(int domain, const std::string& name, std::optional<Region> region = {},
                                       FrameContent content = FrameContent::every_body,
                                       const std::string& security = "") {
    ClientOptions o;
    o.security = security;
    o.domain = domain;
    o.name = name;
    o.region = region;
    o.content = content;
    auto client = Client::connect(o);
    if (!client) {
        ADD_FAILURE() << client.error().message;
        return nullptr;
    }
    return std::move(client).value();
}

/// The whole of a file (a log, a program's output); empty if it cannot be read.
inline std::string read_file(const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// Polls until frame `last` is in `frames` (or the limit passes), adding every frame seen by number;
/// `arrived` is told each frame's number as it comes.
inline void collect_into(Client& client, std::map<std::uint64_t, WorldFrame>& frames, std::uint64_t last,
                         std::chrono::seconds limit, const std::function<void(std::uint64_t)>& arrived = {},
                         std::chrono::milliseconds poll = std::chrono::milliseconds(20)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end && (frames.empty() || frames.rbegin()->first < last)) {
        for (WorldFrame& f : client.poll(poll)) {
            if (arrived) arrived(f.frame);
            frames[f.frame] = std::move(f);
        }
    }
}

/// Polls until frame `last` has been seen (or the limit passes); returns every frame seen, by number.
inline std::map<std::uint64_t, WorldFrame> collect(Client& client, std::uint64_t last,
                                                   std::chrono::seconds limit = std::chrono::seconds(120)) {
    std::map<std::uint64_t, WorldFrame> frames;
    collect_into(client, frames, last, limit);
    return frames;
}

/// A client's frames by number and the time each arrived, for the tests that measure what a fault costs a
/// client; `on_frame`, if given, runs as each frame arrives (to read the workers' marks meanwhile).
class FrameRecorder {
public:
    using Clock = std::chrono::steady_clock;

    explicit FrameRecorder(Client& client, std::function<void()> on_frame = {})
        : client_(client), on_frame_(std::move(on_frame)) {}

    /// Polls every 5 ms until frame `last` is in (or `limit` has passed).
    void gather(std::uint64_t last, std::chrono::seconds limit) {
        collect_into(
            client_, frames, last, limit,
            [&](std::uint64_t f) {
                arrived[f] = Clock::now();
                if (on_frame_) on_frame_();
            },
            std::chrono::milliseconds(5));
    }

    /// Keeps what one poll of at most `wait` returns.
    void poll(std::chrono::milliseconds wait) {
        for (WorldFrame& f : client_.poll(wait)) {
            arrived[f.frame] = Clock::now();
            if (on_frame_) on_frame_();
            frames[f.frame] = std::move(f);
        }
    }

    /// The pause after a fault: the longest wait, in seconds, from `since` for the first frame after `after`,
    /// and between each frame after it and the next, by the times the frames arrived.
    double longest_wait(std::uint64_t after, Clock::time_point since) const {
        double pause = 0.0;
        for (auto it = arrived.upper_bound(after); it != arrived.end(); ++it) {
            pause = std::max(pause, std::chrono::duration<double>(it->second - since).count());
            since = it->second;
        }
        return pause;
    }

    std::map<std::uint64_t, WorldFrame> frames;
    std::map<std::uint64_t, Clock::time_point> arrived;

private:
    Client& client_;
    std::function<void()> on_frame_;
};

struct SimRow {
    SectorPosition position;
    Eigen::Quaterniond orientation;
};

/// Runs lpss-sim (LPSS_SIM) on the scene and reads its CSV: frame -> id -> state; with `every` > 1, only
/// every every-th frame (and the last), for worlds too large to keep every frame of.
inline std::map<std::uint64_t, std::map<BodyId, SimRow>> run_sim(const std::string& scene, int frames,
                                                                 int every = 1) {
    const std::string csv = scene + ".sim.csv";
    const std::string command = std::string(LPSS_SIM) + " " + scene + " --frames " + std::to_string(frames) +
                                " --csv " + csv + " --every " + std::to_string(every) + " 2>/dev/null";
    EXPECT_EQ(std::system(command.c_str()), 0);
    std::map<std::uint64_t, std::map<BodyId, SimRow>> out;
    const Expected<std::vector<StateCsvRow>> rows = read_state_csv(csv);
    EXPECT_TRUE(rows) << rows.error().message;
    if (!rows) return out;
    for (const StateCsvRow& r : rows.value())
        out[r.frame][r.body.id] = SimRow{r.body.position, r.body.orientation};
    return out;
}

using SimFrames = std::map<std::uint64_t, std::map<BodyId, SimRow>>;

/// Checks every frame a client saw against lpss-sim's run of the same scene: empty if each frame holds
/// exactly lpss-sim's bodies, else what the first that does not holds; `worst` is set to the largest
/// distance of a body from where lpss-sim has it.
inline std::string against_sim(const std::map<std::uint64_t, WorldFrame>& frames, const SimFrames& sim,
                               double& worst, double sector_size) {
    const SectorGrid grid(sector_size);
    worst = 0.0;
    for (const auto& [f, frame] : frames) {
        const auto& expected = sim.at(f);
        bool same = frame.bodies.size() == expected.size();
        std::set<BodyId> seen;
        for (const BodyView& b : frame.bodies)
            same = same && expected.count(b.id) && seen.insert(b.id).second;
        if (!same) {
            std::string held;
            for (const BodyView& b : frame.bodies)
                held += " " + std::to_string(b.id) + "@" + std::to_string(b.position.sector.i) + "," +
                        std::to_string(b.position.sector.j) + "," + std::to_string(b.position.sector.k);
            return "frame " + std::to_string(f) + " holds " + std::to_string(frame.bodies.size()) +
                   " bodies, lpss-sim " + std::to_string(expected.size()) + ":" + held;
        }
        for (const BodyView& b : frame.bodies)
            worst = std::max(
                worst, (grid.to_global(b.position) - grid.to_global(expected.at(b.id).position)).norm());
    }
    return {};
}

/// A pkill -f pattern for one worker of a test's cluster. The bracket keeps it from matching the shell
/// that runs pkill, whose own command line holds the pattern.
inline std::string worker_process(int domain, int id) {
    return "'[l]pss-worker --domain " + std::to_string(domain) + " --id " + std::to_string(id) + " '";
}

/// The pkill -f pattern of lpss-cluster's coordinator on `domain` (not its standby: the coordinator is the
/// one that awaits a standby).
inline std::string primary_coordinator_process(int domain) {
    return "'[l]pss-coordinator --domain " + std::to_string(domain) + " .*--await-standby'";
}

/// The pkill -f pattern of lpss-cluster's standby coordinator on `domain` (its last argument: the
/// coordinator's --standby-wait-s would match a pattern that did not end there).
inline std::string standby_process(int domain) {
    return "'[l]pss-coordinator --domain " + std::to_string(domain) + " .*--standby$'";
}

/// The lpss processes of a domain, by pid, with a name: "coordinator", "standby" or "worker N".
inline std::map<int, std::string> processes_of(int domain) {
    std::map<int, std::string> out;
    DIR* proc = opendir("/proc");
    if (proc == nullptr) return out;
    while (dirent* entry = readdir(proc)) {
        const int pid = std::atoi(entry->d_name);
        if (pid <= 0) continue;
        std::ifstream in("/proc/" + std::string(entry->d_name) + "/cmdline");
        std::vector<std::string> args;
        for (std::string arg; std::getline(in, arg, '\0');)
            args.push_back(arg);
        if (args.empty()) continue;
        auto value_of = [&](const std::string& flag) {
            auto it = std::find(args.begin(), args.end(), flag);
            return it != args.end() && std::next(it) != args.end() ? *std::next(it) : std::string();
        };
        if (value_of("--domain") != std::to_string(domain)) continue;
        const std::string program = args[0].substr(args[0].rfind('/') + 1);
        if (program == "lpss-worker") {
            out[pid] = "worker " + value_of("--id");
        } else if (program == "lpss-coordinator") {
            out[pid] =
                std::find(args.begin(), args.end(), "--standby") != args.end() ? "standby" : "coordinator";
        }
    }
    closedir(proc);
    return out;
}

}  // namespace lpss::testing
