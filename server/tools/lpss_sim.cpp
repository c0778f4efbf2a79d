// lpss-sim: runs a scene in one process with the in-process engine and writes what happened, as a
// short summary or as the body-state CSV shared with lpss-watch. Built against float Bullet (lpss-sim)
// and float64 Bullet (lpss-sim-f64); --monolithic runs plain Bullet in global coordinates instead.
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

#include "lpss/common/logging.hpp"
#include "lpss/common/process_memory.hpp"
#include "lpss/common/scene.hpp"
#include "lpss/common/state_csv.hpp"
#include "lpss/engine/world.hpp"

namespace {

struct FileCloser {
    void operator()(std::FILE* f) const {
        if (f != nullptr && f != stdout) std::fclose(f);
    }
};

/// Seconds since `start`.
double since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct Totals {
    double parse = 0, build = 0;  ///< loading: reading and checking the scene; creating the world from it
    std::vector<double> frame_seconds;
    double sectorize = 0, clone = 0, step = 0, total = 0;
    std::size_t stepped_sectors = 0, sector_changes = 0, contacts_begun = 0, max_clones = 0, max_sectors = 0;
    std::size_t max_border_bodies = 0;
    std::size_t clones_made = 0, clones_released = 0;
};

void print_summary(const lpss::World& world, const std::string& scene, std::uint64_t frames, const Totals& t,
                   double wall) {
    const lpss::FrameStats& last = world.last_frame_stats();
    const double per = frames ? 1e3 / static_cast<double>(frames) : 0.0;
    fmt::print("scene        {}\n", scene);
    const lpss::EngineOptions& o = world.options();
    fmt::print("engine       {} Bullet, {}, {} thread(s)\n", lpss::World::physics_precision(),
               o.monolithic
                   ? "monolithic (one world, global coordinates)"
                   : fmt::format("sectorized, L = {:g}{}", world.settings().sector_size,
                                 o.double_positions || o.floating_origins ? "" : ", plain sector frames"),
               o.threads);
    fmt::print("frames       {} of {:g} s ({:g} s simulated) in {:.3f} s wall\n", frames, world.settings().dt,
               static_cast<double>(frames) * world.settings().dt, wall);
    fmt::print("load         {:.3f} s (scene {:.3f} s, world {:.3f} s)\n", t.parse + t.build, t.parse,
               t.build);
    fmt::print("bodies       {}\n", world.body_count());
    fmt::print("sectors      {} at the end, {} at most; {:.1f} stepped per frame on average\n", last.sectors,
               t.max_sectors,
               frames ? static_cast<double>(t.stepped_sectors) / static_cast<double>(frames) : 0.0);
    fmt::print(
        "borders      {} sector changes, up to {} border bodies and {} clones at once; {} clones made, "
        "{} let go\n",
        t.sector_changes, t.max_border_bodies, t.max_clones, t.clones_made, t.clones_released);
    fmt::print("contacts     {} began\n", t.contacts_begun);
    fmt::print("time/frame   {:.4f} ms (sectorize {:.4f}, clone {:.4f}, step {:.4f})\n", t.total * per,
               t.sectorize * per, t.clone * per, t.step * per);
    // The first frame places every body in the reach index: a cost of loading. The frames after it are
    // what the world costs to run.
    if (t.frame_seconds.size() > 1) {
        std::vector<double> after(t.frame_seconds.begin() + 1, t.frame_seconds.end());
        double sum = 0.0;
        for (double v : after)
            sum += v;
        std::sort(after.begin(), after.end());
        const double p99 = after[std::min(after.size() - 1, after.size() * 99 / 100)];
        fmt::print("running      first frame {:.4f} ms; frames 2-{}: mean {:.4f} ms, p99 {:.4f} ms\n",
                   t.frame_seconds.front() * 1e3, t.frame_seconds.size(),
                   1e3 * sum / static_cast<double>(after.size()), p99 * 1e3);
    }
    if (const std::optional<lpss::MemoryUse> m = lpss::memory_use()) {
        fmt::print(
            "memory       {:.1f} MiB resident at the end, {:.1f} MiB at most; proportional set {:.1f} MiB\n",
            static_cast<double>(m->resident_bytes) / 1048576.0,
            static_cast<double>(m->peak_bytes) / 1048576.0,
            static_cast<double>(lpss::proportional_resident_bytes().value_or(0)) / 1048576.0);
    }
    std::vector<lpss::BodySnapshot> bodies = world.snapshot();
    const std::size_t shown = std::min<std::size_t>(bodies.size(), 12);
    fmt::print("final state  (first {} of {} bodies; global position and sector)\n", shown, bodies.size());
    for (std::size_t n = 0; n < shown; ++n) {
        const lpss::BodySnapshot& b = bodies[n];
        Eigen::Vector3d g = world.grid().to_global(b.position);
        const auto desc = world.description(b.id);
        fmt::print(
            "  {:>6} {:<14} x=({:.6f}, {:.6f}, {:.6f}) v=({:.3f}, {:.3f}, {:.3f}) sector ({}, {}, {}){}\n",
            b.id, desc ? desc->name : "", g.x(), g.y(), g.z(), b.linear_velocity.x(), b.linear_velocity.y(),
            b.linear_velocity.z(), b.position.sector.i, b.position.sector.j, b.position.sector.k,
            b.awake ? "" : " asleep");
    }
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Runs a scene in one process with the LPSS engine and prints what happened."};
    std::string scene_path;
    std::uint64_t frames = 60;
    std::string csv_path;
    std::uint64_t every = 1;
    int threads = 1;
    bool monolithic = false;
    bool plain_sectors = false;
    std::string log_level = "warn";
    app.add_option("scene", scene_path, "scene file (Protobuf text format)")->required();
    app.add_option("--frames", frames, "frames to run")
        ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{1} << 40));
    app.add_option("--csv", csv_path, "write body states as CSV to this file ('-' for stdout)");
    app.add_option("--every", every, "with --csv: write every K-th frame (the first and last always)")
        ->check(CLI::PositiveNumber);
    app.add_option("--threads", threads, "threads stepping sectors concurrently")->check(CLI::Range(1, 256));
    app.add_flag("--monolithic", monolithic, "no sectors: one world in global coordinates (plain Bullet)");
    app.add_flag("--plain-sectors", plain_sectors,
                 "the paper's scheme alone: sector-centred float frames, no double positions");
    app.add_option("--log-level", log_level, "trace, debug, info, warn, error, off");
    CLI11_PARSE(app, argc, argv);

    if (lpss::Status st = lpss::set_log_level(log_level); !st) {
        std::fprintf(stderr, "lpss-sim: %s\n", st.error().message.c_str());
        return 2;
    }
    Totals totals;
    const auto load_start = std::chrono::steady_clock::now();
    lpss::Expected<lpss::Scene> scene = lpss::load_scene(scene_path, !monolithic);
    totals.parse = since(load_start);
    if (!scene) {
        std::fprintf(stderr, "lpss-sim: scene refused:\n%s\n", scene.error().message.c_str());
        return 2;
    }
    lpss::EngineOptions options;
    options.threads = threads;
    options.monolithic = monolithic;
    options.double_positions = !plain_sectors;
    options.floating_origins = !plain_sectors;
    const auto build_start = std::chrono::steady_clock::now();
    lpss::Expected<lpss::World> created = lpss::World::create(scene.value(), options);
    totals.build = since(build_start);
    if (!created) {
        std::fprintf(stderr, "lpss-sim: %s\n", created.error().message.c_str());
        return 2;
    }
    lpss::World& world = created.value();

    std::unique_ptr<std::FILE, FileCloser> csv;
    if (!csv_path.empty()) {
        csv.reset(csv_path == "-" ? stdout : std::fopen(csv_path.c_str(), "w"));
        if (!csv) {
            std::fprintf(stderr, "lpss-sim: cannot write %s\n", csv_path.c_str());
            return 2;
        }
        lpss::write_state_csv_header(csv.get());
    }
    auto write_frame = [&] {
        for (const lpss::BodySnapshot& b : world.snapshot()) {
            lpss::write_state_csv_row(csv.get(), world.frame(), b, world.grid());
        }
    };
    if (csv) write_frame();

    totals.frame_seconds.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(frames, 1u << 24)));
    auto start = std::chrono::steady_clock::now();
    for (std::uint64_t f = 1; f <= frames; ++f) {
        world.step();
        const lpss::FrameStats& s = world.last_frame_stats();
        totals.sectorize += s.sectorize_seconds;
        totals.clone += s.clone_seconds;
        totals.step += s.step_seconds;
        totals.total += s.total_seconds;
        totals.frame_seconds.push_back(s.total_seconds);
        totals.stepped_sectors += s.stepped_sectors;
        totals.sector_changes += s.sector_changes;
        totals.max_clones = std::max(totals.max_clones, s.clones);
        totals.clones_made += s.clones_made;
        totals.clones_released += s.clones_released;
        totals.max_sectors = std::max(totals.max_sectors, s.sectors);
        totals.max_border_bodies = std::max(totals.max_border_bodies, s.border_bodies);
        for (const lpss::ContactEvent& e : world.contact_events()) {
            if (e.kind == lpss::ContactEvent::Kind::Begin) ++totals.contacts_begun;
        }
        if (csv && (f % every == 0 || f == frames)) write_frame();
    }
    double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (csv) {
        if (std::fflush(csv.get()) != 0) {
            std::fprintf(stderr, "lpss-sim: writing %s failed\n", csv_path.c_str());
            return 1;
        }
        if (csv_path != "-")
            std::fprintf(stderr, "lpss-sim: %llu frames written to %s\n",
                         static_cast<unsigned long long>(frames), csv_path.c_str());
    } else {
        print_summary(world, scene_path, frames, totals, wall);
    }
    return 0;
}
