// pareto: error against milliseconds per frame, for several scenes at several distances from the
// origin, every configuration in one picture: the sector-size trade-off and the price of double
// precision read off one plot. Error is measured against the same configuration at the origin.
#include <fmt/format.h>

#include <cmath>
#include <map>
#include <random>

#include "scenes.hpp"
#include "subcommands.hpp"

namespace lpss::bench {

scenes::Centre place(double distance, const Eigen::Vector3d& axis, double L, std::string& placement);

namespace {

/// About 2,000 spheres, boxes and capsules in a loose block falling on the ground.
Scene mixed_pile(const scenes::Centre& base, double sector_size, int count) {
    Scene s;
    s.settings.sector_size = sector_size;
    s.settings.gravity = Eigen::Vector3d(0, -9.81, 0);
    s.bodies.push_back(scenes::ground_plane(1'000'000, base));
    const int side = static_cast<int>(std::ceil(std::cbrt(count)));
    for (int n = 0; n < count; ++n) {
        Eigen::Vector3d p(1.3 * (n % side - side / 2) + 0.05 * (n % 7), 0.6 + 1.3 * (n / (side * side)),
                          1.3 * (n / side % side - side / 2) - 0.04 * (n % 5));
        BodyDesc b = n % 3 == 0   ? scenes::sphere_body(n + 1, 0.5, 1.0, scenes::shifted(base, p))
                     : n % 3 == 1 ? scenes::box_body(n + 1, Eigen::Vector3d(0.5, 0.4, 0.3), 1.0,
                                                     scenes::shifted(base, p))
                                  : scenes::sphere_body(n + 1, 0.3, 0.5, scenes::shifted(base, p));
        if (n % 3 == 2) b.shape = Capsule{0.25, 0.5};
        s.bodies.push_back(b);
    }
    return s;
}

struct SceneKind {
    std::string name;
    int frames;
    std::function<Scene(const scenes::Centre&, double)> make;
};

std::map<BodyId, Eigen::Vector3d> run_and_read(World& world, int frames, const scenes::Centre& centre) {
    for (int f = 0; f < frames; ++f)
        world.step();
    std::map<BodyId, Eigen::Vector3d> out;
    for (const BodySnapshot& b : world.snapshot())
        out[b.id] = scenes::relative_position(world.grid(), b, centre);
    return out;
}

}  // namespace

void run_pareto(const Context& context) {
    Table table({"scene", "direction", "distance", "config", "sector_size", "error", "ms_per_frame",
                 "collided", "placement"});
    const int pile_count = context.quick ? 300 : 2000;
    const std::vector<SceneKind> kinds = {
        {"two_spheres", 180, [](const scenes::Centre& c, double L) { return scenes::sphere_pair(c, L); }},
        {"box_stack_10", 600, [](const scenes::Centre& c, double L) { return scenes::box_stack(c, 10, L); }},
        {"mixed_pile_" + std::to_string(pile_count), 30,
         [pile_count](const scenes::Centre& c, double L) { return mixed_pile(c, L, pile_count); }},
    };
    // 1e13 + 37.3: not a multiple of any sector size, so that the far run's local coordinates differ.
    const std::vector<double> distances = {1e3 + 0.7, 1e6 + 3.1, 1e9 + 11.9, 1e13 + 37.3};
    for (const Config& config : comparison_configs()) {
        if (!config.runs_here()) continue;
        const double L = config.sector_size > 0 ? config.sector_size : 1024.0;
        for (const SceneKind& kind : kinds) {
            progress("pareto: " + kind.name + " with " + config.label());
            World origin = make_world(kind.make(Eigen::Vector3d::Zero().eval(), L), config.options());
            const auto truth = run_and_read(origin, kind.frames, Eigen::Vector3d::Zero().eval());
            for (double d : distances) {
                std::string placement;
                const scenes::Centre centre = place(d, Eigen::Vector3d::UnitX(), L, placement);
                const Scene scene = kind.make(centre, L);
                World far = make_world(scene, config.options());
                const auto got = run_and_read(far, kind.frames, centre);
                double error = 0.0;
                for (const auto& [id, p] : got)
                    error += (p - truth.at(id)).norm();
                if (kind.name != "two_spheres") error /= static_cast<double>(got.size());  // mean per body
                const bool collided = kind.name != "two_spheres" || far.body(1)->linear_velocity.x() < 0.0;
                // The same run the error was measured on, from a fresh world each time.
                const double ms = ms_per_frame_fresh(
                    fmt::format("pareto/{}/{}", kind.name, config.label()),
                    [&] { return make_world(scene, config.options()); }, kind.frames, 0.05);
                table.add({kind.name, "x", num(d, 17), config.name, num(config.sector_size), num(error, 6),
                           num(ms, 4), collided ? "1" : "0", placement});
            }
        }
    }
    merge_twin(context, "pareto", table);

    std::string md =
        "Each point: one configuration, one scene, one distance along x. error: against the same "
        "configuration run "
        "at the origin (two spheres: summed distance after 3 s; stack: mean over boxes after 10 s; pile: "
        "mean over "
        "bodies after 0.5 s of falling, a chaotic scene where small differences grow). ms_per_frame: Google "
        "Benchmark. Distances are offset from round numbers (1e3 + 0.7 ... 1e13 + 37.3) so that no run sits "
        "on a sector multiple; the last is placed by sector position.\n\n" +
        table.markdown({"scene", "distance", "config", "sector_size", "error", "ms_per_frame", "collided"});
    std::string plot =
        "set multiplot layout 1,3 title 'Error against cost (point shape: distance; colour: "
        "configuration)'\nset logscale xy\nset xlabel 'milliseconds per frame'\nset ylabel 'error'\n"
        "set key bottom right font ',8'\nset format y '1e%L'\n"
        "set termoption noenhanced\n"
        // Distances are matched within a relative 1e-9: printed with %g, 1e13 + 37.3 is not equal to the
        // CSV's value, and the farthest points (plain Bullet's worst) fell off the plot.
        "e(s,c,l,d) = (strcol(1) eq s && strcol(4) eq c && $5 == l && abs($3 / d - 1) < 1e-9) ? "
        "($6 > 1e-12 ? $6 : 1e-12) : 1/0\n";
    for (const SceneKind& kind : kinds) {
        // The key where the panel has no points: the pile's costs sit to the right, the others' to the left.
        plot += std::string(kind.name == "mixed_pile_2000" ? "set key top left\n" : "set key bottom right\n") +
                "set title '" + kind.name + "'\nplot ";
        int colour = 1;
        for (const Config& c : comparison_configs()) {
            int shape = 5;
            for (double d : distances) {
                plot += fmt::format(
                    "'$CSV' every ::1 using 7:(e('{}','{}',{:g},{:.17g})) with points lc {} pt {} ps 1.3 "
                    "title '{}', ",
                    kind.name, c.name, c.sector_size, d, colour, shape,
                    fmt::format("{} at {:g}", c.label(), d));
                shape += 2;
            }
            ++colour;
        }
        plot.erase(plot.size() - 2);
        plot += "\n";
    }
    plot += "unset multiplot\n";
    publish(context, "pareto", table, "pareto: error against run time", md, plot);
}

}  // namespace lpss::bench
