// instances (the paper's Figure 6): 128 unit boxes falling on the ground, spread over 1, 2, 4, ... 128
// sectors: time per frame (600 frames, as the baseline notes measured), memory and creation time per
// sector, against one default Bullet world per sector (naive-bullet) in the same run.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "scenes.hpp"
#include "subcommands.hpp"

namespace lpss::bench {
namespace {

constexpr double kL = 64.0;

Scene spread_boxes(int sectors) {
    Scene s;
    s.settings.sector_size = kL;
    s.settings.gravity = Eigen::Vector3d(0, -9.81, 0);
    s.bodies.push_back(scenes::ground_plane(100000, Eigen::Vector3d::Zero().eval()));
    const int per_sector = 128 / sectors;
    const int columns = static_cast<int>(std::ceil(std::sqrt(per_sector)));
    BodyId id = 1;
    for (int sector = 0; sector < sectors; ++sector) {
        // Every other sector along x, so that no two groups share a border.
        const double cx = 2.0 * kL * sector;
        for (int n = 0; n < per_sector; ++n) {
            Eigen::Vector3d p(cx + 1.5 * (n % columns - columns / 2), 2.0, 1.5 * (n / columns - columns / 2));
            s.bodies.push_back(scenes::box_body(id++, Eigen::Vector3d::Constant(0.5), 1.0, p));
        }
    }
    return s;
}

}  // namespace

void run_instances(const Context& context) {
    Table table({"config", "sectors", "ms_per_frame", "ratio_to_one", "bytes_per_sector",
                 "create_us_per_sector", "ratio_low", "ratio_high"});
    std::vector<Config> configs = {{"lpss-float", kL, false, false, "float"},
                                   {"naive-bullet", kL, false, true, "float"}};
    const std::vector<int> counts =
        context.quick ? std::vector<int>{1, 8, 128} : std::vector<int>{1, 2, 4, 8, 16, 32, 64, 128};
    // The sweep is run several times over, one sector count after the other in each round, and each
    // count's time is compared with one sector's of the same round: this shared machine's slow spells
    // last seconds, and a single sweep's ratios moved by 0.84-1.38 from run to run.
    const int rounds = context.quick ? 2 : 7;
    for (const Config& config : configs) {
        if (!config.runs_here()) continue;
        std::map<int, std::vector<double>> ms, ratio;
        for (int round = 0; round < rounds; ++round) {
            double one = 0.0;
            for (int n : counts) {
                progress(fmt::format("instances: {} over {} sectors (round {} of {})", config.label(), n,
                                     round + 1, rounds));
                const Scene scene = spread_boxes(n);
                auto make = [&] { return make_world(scene, config.options()); };
                const double t = ms_per_frame_fresh(fmt::format("instances/{}/{}", config.name, n), make, 600,
                                                    context.quick ? 0.05 : 0.2);
                if (n == 1) one = t;
                ms[n].push_back(t);
                ratio[n].push_back(t / one);
            }
        }
        double one_bytes = 0.0, one_us = 0.0;
        for (int n : counts) {
            const Scene scene = spread_boxes(n);
            auto make = [&] { return make_world(scene, config.options()); };
            const double us = us_to_create(fmt::format("instances-create/{}/{}", config.name, n), make,
                                           context.quick ? 0.05 : 0.3);
            double bytes = 0.0;
            {
                const std::size_t before = heap_bytes();
                World world = make();
                for (int f = 0; f < 10; ++f)
                    world.step();  // manifolds and solver scratch included
                bytes = static_cast<double>(heap_bytes() - before);
            }
            if (n == 1) {
                one_bytes = bytes;
                one_us = us;
            }
            // Per sector: what each sector beyond the first adds, the same 128 boxes being in every run;
            // for one sector, the whole world.
            const double bytes_per = n == 1 ? bytes : (bytes - one_bytes) / (n - 1);
            const double us_per = n == 1 ? us : (us - one_us) / (n - 1);
            const auto [low, high] = std::minmax_element(ratio[n].begin(), ratio[n].end());
            table.add({config.name, std::to_string(n), num(median(ms[n]), 5), num(median(ratio[n]), 4),
                       num(bytes_per, 6), num(us_per, 4), num(*low, 4), num(*high, 4)});
        }
    }

    std::string md =
        "128 unit boxes falling on the ground for 600 frames, spread evenly over N sectors (no two groups "
        "touching). "
        "ms_per_frame: Google Benchmark mean over whole 600-frame runs (each of at least 0.2 s), the median "
        "of "
        "7 rounds of the whole sweep; ratio_to_one: the median, over the rounds, of the ratio to one "
        "sector's "
        "time in the same round, ratio_low and ratio_high its extremes (the bars in the plot). "
        "bytes_per_sector and "
        "create_us_per_sector: "
        "what each sector beyond the first adds (for N = 1: the whole world with its 128 boxes). Targets for "
        "lpss-float: ratio_to_one <= 1.15 at 128 sectors, <= 64 KiB and <= 50 us per sector.\n\n" +
        table.markdown();
    std::string plot = R"(set multiplot layout 1,3 title '128 boxes over N sectors'
set logscale x 2
set xlabel 'sectors'
set key top left
set xrange [0.7:180]
set title 'time per frame relative to one sector'
set ylabel 'ratio to one sector'
set arrow from graph 0, first 1.15 to graph 1, first 1.15 nohead dashtype 2
plot '$CSV' every ::1 using (strcol(1) eq 'lpss-float' ? $2 : 1/0):4:7:8 with yerrorlines pt 7 title 'lpss-float', \
     '$CSV' every ::1 using (strcol(1) eq 'naive-bullet' ? $2 : 1/0):4:7:8 with yerrorlines pt 5 title 'naive-bullet', \
     1/0 with lines dashtype 2 lc rgb 'black' title 'target for lpss (1.15)'
unset arrow
set xrange [1.5:180]
set title 'memory per extra sector'
set logscale y
set ylabel 'bytes'
plot '$CSV' every ::2 using (strcol(1) eq 'lpss-float' && $2 > 1 ? $2 : 1/0):5 with linespoints pt 7 title 'lpss-float', \
     '$CSV' every ::2 using (strcol(1) eq 'naive-bullet' && $2 > 1 ? $2 : 1/0):5 with linespoints pt 5 title 'naive-bullet'
set title 'creation time per extra sector'
set ylabel 'microseconds'
plot '$CSV' every ::2 using (strcol(1) eq 'lpss-float' && $2 > 1 ? $2 : 1/0):6 with linespoints pt 7 title 'lpss-float', \
     '$CSV' every ::2 using (strcol(1) eq 'naive-bullet' && $2 > 1 ? $2 : 1/0):6 with linespoints pt 5 title 'naive-bullet'
unset multiplot
)";
    publish(context, "instances", table, "instances: many sectors (paper Figure 6)", md, plot);
}

}  // namespace lpss::bench
