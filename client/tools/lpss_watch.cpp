// lpss-watch: follows a running lpss world (whole, or a region) and prints it live, or writes the
// body-state CSV of lpss-sim for every frame it sees.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "crash_report.hpp"
#include "lpss/client/client.hpp"
#include "lpss/common/process_memory.hpp"
#include "lpss/common/state_csv.hpp"
#include "stop_signal.hpp"

namespace {

/// The bodies followed and how many are awake, kept from frames of changes.
struct Counts {
    std::unordered_map<lpss::BodyId, bool> awake;
    std::size_t awake_count = 0;
    void take(const lpss::WorldFrame& f) {
        if (f.every_body) {
            awake.clear();
            awake_count = 0;
        }
        for (const lpss::BodyView& b : f.bodies) {
            auto [at, added] = awake.emplace(b.id, b.awake);
            if (!added) awake_count -= at->second ? 1 : 0;
            at->second = b.awake;
            awake_count += b.awake ? 1 : 0;
        }
        for (lpss::BodyId id : f.departed) {
            auto at = awake.find(id);
            if (at == awake.end()) continue;
            awake_count -= at->second ? 1 : 0;
            awake.erase(at);
        }
    }
};

/// The world rebuilt from frames of changes, every body in id order, for the CSV. A client of every body
/// builds a view of the whole world for each frame (176 MB at a million bodies), and one that fell
/// behind, a view for each frame it is behind, in one poll.
struct Rebuilt {
    std::map<lpss::BodyId, lpss::BodyView> bodies;
    void take(const lpss::WorldFrame& f) {
        if (f.every_body) bodies.clear();
        for (const lpss::BodyView& b : f.bodies)
            bodies[b.id] = b;
        for (lpss::BodyId id : f.departed)
            bodies.erase(id);
    }
};

}  // namespace

int main(int argc, char** argv) {
    lpss::runtime::install_crash_report("lpss-watch");
    CLI::App app{"lpss-watch: prints a running lpss world, or writes it as CSV"};
    lpss::ClientOptions options;
    options.name = "lpss-watch";
    std::string region, csv_path;
    std::uint64_t frames = 0;
    int wait_s = 30;
    app.add_option("--domain", options.domain, "DDS domain id")->check(CLI::Range(0, 232));
    app.add_option("--profile", options.profile,
                   "Fast DDS XML profile (default: built-in, this machine only)");
    app.add_option(
        "--name", options.name,
        "this client's name, unique per domain (default lpss-watch): give a second watcher another");
    app.add_option("--security", options.security,
                   "DDS Security identity folder (deploy/security/identities.sh; default: none)");
    app.add_option("--region", region, "follow only sectors i_lo,i_hi,j_lo,j_hi,k_lo,k_hi");
    app.add_option("--csv", csv_path, "write every body of every frame as CSV to this file ('-': stdout)");
    app.add_option("--frames", frames, "exit after this many frames (0: until Ctrl-C)");
    app.add_option("--wait-s", wait_s, "how long to wait for a cluster");
    CLI11_PARSE(app, argc, argv);
    // Frames of changes: printing needs only the counts kept here, and the CSV's every body of every frame
    // is rebuilt here from them.
    options.content = lpss::FrameContent::changes;
    if (!region.empty()) {
        auto r = lpss::parse_region(region);
        if (!r) {
            std::fprintf(stderr, "lpss-watch: %s\n", r.error().message.c_str());
            return 2;
        }
        options.region = r.value();
    }
    auto client = lpss::Client::connect(options);
    if (!client) {
        std::fprintf(stderr, "lpss-watch: cannot start: %s\n", client.error().message.c_str());
        return 2;
    }
    if (!(*client)->wait_for_cluster(std::chrono::seconds(wait_s))) {
        std::fprintf(stderr, "lpss-watch: no lpss cluster found on domain %d within %d s\n", options.domain,
                     wait_s);
        return 3;
    }
    std::FILE* csv = nullptr;
    if (!csv_path.empty()) {
        csv = csv_path == "-" ? stdout : std::fopen(csv_path.c_str(), "w");
        if (csv == nullptr) {
            std::fprintf(stderr, "lpss-watch: cannot write %s\n", csv_path.c_str());
            return 2;
        }
        lpss::write_state_csv_header(csv);
    }
    const lpss::SectorGrid grid = *(*client)->grid();
    std::uint64_t seen = 0;
    Counts world;
    Rebuilt rebuilt;
    auto last_print = std::chrono::steady_clock::now() - std::chrono::seconds(2);
    auto last_data = std::chrono::steady_clock::now();
    int exit_code = 0;
    std::uint64_t newest = 0;  ///< the newest frame shown
    // Ctrl-C or SIGTERM end the watch as the last frame does: the memory line still comes.
    const std::atomic<bool>& stop = lpss::runtime::install_stop_signal();
    while ((frames == 0 || seen < frames) && !stop.load()) {
        std::vector<lpss::WorldFrame> got = (*client)->poll(std::chrono::milliseconds(100));
        if (!got.empty()) last_data = std::chrono::steady_clock::now();
        // A world that stopped ends the watch with its last frame (or, should that never come whole, a
        // second after the last one that did); one that falls silent without a word is gone.
        const std::optional<std::uint64_t> last = (*client)->stopped_after();
        if (last && got.empty() &&
            (newest >= *last || std::chrono::steady_clock::now() - last_data > std::chrono::seconds(1))) {
            std::fprintf(stderr, "lpss-watch: the world stopped after frame %llu\n",
                         static_cast<unsigned long long>(*last));
            break;
        }
        if (!last && std::chrono::steady_clock::now() - last_data > std::chrono::seconds(wait_s)) {
            std::fprintf(stderr, "lpss-watch: no frame for %d s: the cluster is gone\n", wait_s);
            exit_code = 3;
            break;
        }
        for (const lpss::WorldFrame& f : got) {
            if (frames != 0 && seen >= frames) break;
            ++seen;
            newest = f.frame;
            if (csv) {
                rebuilt.take(f);
                for (const auto& [id, b] : rebuilt.bodies) {
                    lpss::BodySnapshot s{
                        b.id, b.position, b.orientation, b.linear_velocity, b.angular_velocity, b.awake};
                    lpss::write_state_csv_row(csv, f.frame, s, grid);
                }
                continue;
            }
            world.take(f);
            if (std::chrono::steady_clock::now() - last_print > std::chrono::seconds(1)) {
                last_print = std::chrono::steady_clock::now();
                fmt::print("frame {:>8}  bodies {:>7}  awake {:>7}  changed {:>7}\n", f.frame,
                           world.awake.size(), world.awake_count,
                           f.every_body ? world.awake.size() : f.bodies.size());
                for (std::size_t n = 0; n < std::min<std::size_t>(f.bodies.size(), 5); ++n) {
                    const auto& b = f.bodies[n];
                    fmt::print("    {:>8} x=({:.6f}, {:.6f}, {:.6f}) sector ({}, {}, {})\n", b.id,
                               b.global.x(), b.global.y(), b.global.z(), b.position.sector.i,
                               b.position.sector.j, b.position.sector.k);
                }
                std::fflush(stdout);
            }
        }
    }
    if (csv && csv != stdout) std::fclose(csv);
    if (const std::optional<lpss::MemoryUse> memory = lpss::memory_use()) {
        std::fprintf(stderr, "lpss-watch: %llu frames; memory %.0f MiB resident, %.0f MiB at most\n",
                     static_cast<unsigned long long>(seen),
                     static_cast<double>(memory->resident_bytes) / 1048576.0,
                     static_cast<double>(memory->peak_bytes) / 1048576.0);
    }
    return exit_code;
}
