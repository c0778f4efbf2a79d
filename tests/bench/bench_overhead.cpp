// overhead (the paper's Figure 7): the time of sectorization and of cloning against the number of
// bodies, up to 100,000, with many bodies near borders, beside the time of stepping.
#include <fmt/format.h>

#include "scenes.hpp"
#include "subcommands.hpp"

namespace lpss::bench {

void run_overhead(const Context& context) {
    Table table({"config", "sector_size", "bodies", "frames", "sectors", "border_bodies", "clones",
                 "ms_per_frame", "sectorize_ms", "clone_ms", "step_ms", "overhead_fraction", "refreshes",
                 "candidates", "clones_made", "clones_released"});
    std::vector<int> counts =
        context.quick ? std::vector<int>{1000, 10000} : std::vector<int>{1000, 3000, 10000, 30000, 100000};
    if (!context.sizes.empty()) counts.assign(context.sizes.begin(), context.sizes.end());
    // Two fixed windows of each world's history, the same at every size: its start, when every body takes
    // its first fat box and leaves it within a few frames of the others (all start at their lattice
    // points), and a running world, when they have been colliding for most of a second.
    struct Window {
        const char* name;
        int first, last;
    };
    const Window windows[] = {{"6-35", 6, 35}, {"61-120", 61, 120}};
    for (double L : {8.0, 32.0}) {
        const Config config{"lpss-float", L, false, false, "float"};
        if (!config.runs_here()) continue;
        // Each window's rows together, so that the plot's lines join them.
        std::vector<std::vector<std::string>> rows[2];
        for (int n : counts) {
            progress(fmt::format("overhead: {} with {} bodies", config.label(), n));
            World world = make_world(scenes::drifting_lattice(n, L), config.options());
            int frame = 0;
            for (int w = 0; w < 2; ++w) {
                const Window& window = windows[w];
                for (; frame + 1 < window.first; ++frame)
                    world.step();
                double sectorize = 0, clone = 0, step = 0, frames = 0, border = 0, clones = 0, sectors = 0;
                double refreshes = 0, candidates = 0, made = 0, released = 0;
                const int count = window.last - window.first + 1;
                const double ms = ms_over_frames(fmt::format("overhead/{}/{}/{}", L, n, window.name), world,
                                                 count, [&](const FrameStats& s) {
                                                     sectorize += s.sectorize_seconds;
                                                     clone += s.clone_seconds;
                                                     step += s.step_seconds;
                                                     border += static_cast<double>(s.border_bodies);
                                                     clones += static_cast<double>(s.clones);
                                                     sectors += static_cast<double>(s.sectors);
                                                     refreshes += static_cast<double>(s.fat_box_refreshes);
                                                     candidates += static_cast<double>(s.border_candidates);
                                                     made += static_cast<double>(s.clones_made);
                                                     released += static_cast<double>(s.clones_released);
                                                     frames += 1;
                                                 });
                frame += count;
                const double total = sectorize + clone + step;
                rows[w].push_back({config.name, num(L), std::to_string(n), window.name,
                                   num(sectors / frames, 5), num(border / frames, 5), num(clones / frames, 5),
                                   num(ms, 4), num(1e3 * sectorize / frames, 4), num(1e3 * clone / frames, 4),
                                   num(1e3 * step / frames, 4), num((sectorize + clone) / total, 3),
                                   num(refreshes / frames, 5), num(candidates / frames, 5),
                                   num(made / frames, 5), num(released / frames, 5)});
            }
        }
        for (const auto& window_rows : rows)
            for (const auto& row : window_rows)
                table.add(row);
    }
    std::string md =
        "Bodies in a lattice 1.2 apart drifting at up to 1 unit/s without gravity (about half of them near a "
        "border with L = 8), over two fixed windows of frames of the same world: frames 6-35 (its start: "
        "every body leaves its first fat box within a few frames of the others) and frames 61-120 (a running "
        "world: the bodies have been colliding for most of a second). ms_per_frame: Google Benchmark, one "
        "iteration of the window; the stage split is the engine's own clock over the same frames. "
        "overhead_fraction = (sectorize + clone) / (sectorize + clone + step); target: under 0.10 at L = 8, "
        "0.05 at L = 32. What the cloning stage did, per frame (FrameStats): refreshes, bodies given a new "
        "fat box; candidates, what their queries found; clones_made and clones_released, clones put into "
        "sectors and let go.\n\n" +
        table.markdown();
    std::string plot =
        R"(set multiplot layout 1,3 title 'Cost of sectorization and cloning (solid: frames 61-120, dashed: frames 6-35)'
set logscale xy
set format y '%g'
set xrange [600:170000]
set xlabel 'bodies'
set ylabel 'milliseconds per frame'
set key top left
do for [L in '8 32'] {
  set title sprintf('L = %s', L)
  plot '$CSV' every ::1 using ($2 == L+0 && strcol(4) eq '61-120' ? $3 : 1/0):11 with linespoints lc 1 pt 7 title 'step', \
       '$CSV' every ::1 using ($2 == L+0 && strcol(4) eq '61-120' ? $3 : 1/0):9 with linespoints lc 2 pt 5 title 'sectorize', \
       '$CSV' every ::1 using ($2 == L+0 && strcol(4) eq '61-120' ? $3 : 1/0):10 with linespoints lc 3 pt 9 title 'clone', \
       '$CSV' every ::1 using ($2 == L+0 && strcol(4) eq '6-35' ? $3 : 1/0):11 with linespoints lc 1 pt 6 dt 2 notitle, \
       '$CSV' every ::1 using ($2 == L+0 && strcol(4) eq '6-35' ? $3 : 1/0):9 with linespoints lc 2 pt 4 dt 2 notitle, \
       '$CSV' every ::1 using ($2 == L+0 && strcol(4) eq '6-35' ? $3 : 1/0):10 with linespoints lc 3 pt 8 dt 2 notitle
}
set title '(sectorize + clone) / (sectorize + clone + step)'
unset logscale y
set yrange [0:0.35]
set key top left
set ylabel 'fraction of the frame'
plot '$CSV' every ::1 using ($2 == 8 && strcol(4) eq '61-120' ? $3 : 1/0):12 with linespoints lc 1 pt 7 title 'L = 8', \
     '$CSV' every ::1 using ($2 == 32 && strcol(4) eq '61-120' ? $3 : 1/0):12 with linespoints lc 2 pt 5 title 'L = 32', \
     '$CSV' every ::1 using ($2 == 8 && strcol(4) eq '6-35' ? $3 : 1/0):12 with linespoints lc 1 pt 6 dt 2 title 'L = 8, frames 6-35', \
     '$CSV' every ::1 using ($2 == 32 && strcol(4) eq '6-35' ? $3 : 1/0):12 with linespoints lc 2 pt 4 dt 2 title 'L = 32, frames 6-35', \
     0.10 with lines dashtype 3 lc 1 title 'target at L = 8', \
     0.05 with lines dashtype 3 lc 2 title 'target at L >= 32'
unset multiplot
)";
    publish(context, "overhead", table, "overhead: sectorization and cloning (paper Figure 7)", md, plot);
}

}  // namespace lpss::bench
