// stacks (the paper's Figure 8): box stacks of 10 and 30 at the origin and at 2^24, 2^40 and 1e15 on all
// three axes, 10 s: drift of the top box and whether the stack stands, per configuration; and a side
// view of the 10-box stacks after 10 s.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "scenes.hpp"
#include "subcommands.hpp"

namespace lpss::bench {
namespace {

scenes::Centre place_on_diagonal(double d, double L, std::string& placement) {
    if (d < 1e12) {
        placement = "global";
        return Eigen::Vector3d::Constant(d).eval();
    }
    placement = "sector";
    const auto index = static_cast<std::int64_t>(std::floor(d / L + 0.5));
    const double local = d - static_cast<double>(index) * L;
    return SectorPosition{{index, index, index}, Eigen::Vector3d::Constant(local)};
}

}  // namespace

void run_stacks(const Context& context) {
    Table table({"config", "sector_size", "boxes", "distance", "placement", "top_drift", "top_height",
                 "stands", "ms_per_frame"});
    // Side views go to one file per Bullet build: the twin writes the double configurations' own.
    auto view_file = [&](const std::string& precision) {
        return context.out / ("stacks_view_" + precision + ".dat");
    };
    std::filesystem::create_directories(context.out);
    std::ofstream outlines(view_file(World::physics_precision()));
    const std::vector<double> distances = {0.0, 16777216.0, 1099511627776.0, 1e15};
    for (const Config& config : comparison_configs()) {
        if (!config.runs_here()) continue;
        const double L = config.sector_size > 0 ? config.sector_size : 1000.0;
        for (int boxes : {10, 30}) {
            for (double d : distances) {
                progress(fmt::format("stacks: {} with {} boxes at {:g}", config.label(), boxes, d));
                std::string placement;
                const scenes::Centre base = place_on_diagonal(d, L, placement);
                Scene scene = scenes::box_stack(base, boxes, L);
                if (boxes == 30) {
                    // A 30-box tower needs a careful set-up in any Bullet (see the stability suite).
                    scene.settings.substeps = 4;
                    scene.settings.solver_iterations = 20;
                }
                World world = make_world(scene, config.options());
                for (int f = 0; f < 600; ++f)
                    world.step();
                const Eigen::Vector3d top = scenes::relative_position(world.grid(), *world.body(boxes), base);
                const double drift = (top - Eigen::Vector3d(0, boxes - 0.5, 0)).norm();
                const bool stands = top.y() > boxes - 1.0 && std::isfinite(drift);
                // The whole 10 s run (it falls asleep on the way), from a fresh world each time.
                const double ms = ms_per_frame_fresh(
                    fmt::format("stacks/{}/{}", config.label(), boxes),
                    [&] { return make_world(scene, config.options()); }, 600, 0.05);
                table.add({config.name, num(config.sector_size), std::to_string(boxes), num(d, 17), placement,
                           num(drift, 4), num(top.y(), 5), stands ? "1" : "0", num(ms, 4)});
                if (boxes == 10 && outlines) {
                    // Side view: each box's x-y outline, relative to the stack's base.
                    outlines << "# " << config.label() << " at " << d << "\n";
                    for (int id = 1; id <= boxes; ++id) {
                        const BodySnapshot b = *world.body(static_cast<BodyId>(id));
                        const Eigen::Vector3d c = scenes::relative_position(world.grid(), b, base);
                        for (int k = 0; k <= 4; ++k) {
                            const double sx = (k == 1 || k == 2) ? 0.5 : -0.5,
                                         sy = k >= 2 && k < 4 ? 0.5 : -0.5;
                            const Eigen::Vector3d corner = c + b.orientation * Eigen::Vector3d(sx, sy, 0);
                            outlines << corner.x() << " " << corner.y() << "\n";
                        }
                        outlines << "\n";
                    }
                    outlines << "\n";
                }
            }
        }
    }
    outlines.close();
    merge_twin(context, "stacks", table);

    std::string md =
        "Top box of a stack after 10 s: drift from its start and whether the stack stands (top above n - 1). "
        "30-box "
        "stacks use 4 substeps and 20 solver iterations in every configuration. Offsets are on all three "
        "axes; "
        "1e15 is placed by sector position (monolithic configurations get the same point as a global "
        "double).\n\n" +
        table.markdown({"config", "sector_size", "boxes", "distance", "top_drift", "stands", "ms_per_frame"});
    const std::vector<Config> configs = comparison_configs();
    std::string plot = fmt::format(
        "set multiplot layout {},{} title 'Side view of the 10-box stacks after 10 s "
        "(columns: distance from the origin)'\nset datafile separator whitespace\nset size ratio -1\nunset "
        "key\nset xrange "
        "[-6:6]\nset yrange [-1:11]\nset xtics 5 font ',7'\nset ytics 5 font ',7'\n",
        configs.size(), distances.size());
    std::map<std::string, int> next_index;
    for (const Config& config : configs) {
        for (double d : distances) {
            const int index = next_index[config.precision]++;
            plot += fmt::format("set title '{} at {:g}' font ',8'\nplot '{}' index {} with lines lw 1.5\n",
                                config.label(), d, view_file(config.precision).string(), index);
        }
    }
    plot += "unset multiplot\n";
    publish(context, "stacks", table, "stacks: standing far from the origin (paper Figure 8)", md, plot);
}

}  // namespace lpss::bench
