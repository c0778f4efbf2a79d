// scaling: frame time against body count (1k to 100k) and threads, with monolithic float and double
// Bullet on the same scenes, to show where real time at 60 Hz ends on this machine.
#include <fmt/format.h>

#include <cmath>

#include "scenes.hpp"
#include "subcommands.hpp"

namespace lpss::bench {
namespace {

/// A field of boxes and spheres, four layers deep, resting on the ground and kept awake: the cost of a
/// busy scene. It is about 0.6 sqrt(n) units wide: one world with L = 4096, a few dozen with L = 32.
Scene field(int count, double sector_size) {
    Scene s;
    s.settings.sector_size = sector_size;
    s.settings.gravity = Eigen::Vector3d(0, -9.81, 0);
    s.settings.sleeping = false;
    s.bodies.push_back(scenes::ground_plane(10'000'000, Eigen::Vector3d::Zero().eval()));
    const int side = static_cast<int>(std::ceil(std::sqrt(count / 4.0)));
    for (int n = 0; n < count; ++n) {
        const int layer = n / (side * side), cell = n % (side * side);
        Eigen::Vector3d p(1.2 * (cell % side - side / 2), 0.5 + 1.05 * layer, 1.2 * (cell / side - side / 2));
        s.bodies.push_back(n % 3 ? scenes::box_body(n + 1, Eigen::Vector3d::Constant(0.45), 1.0, p)
                                 : scenes::sphere_body(n + 1, 0.45, 1.0, p));
    }
    return s;
}

}  // namespace

void run_scaling(const Context& context) {
    Table table({"config", "sector_size", "threads", "bodies", "sectors", "ms_per_frame", "realtime_60hz"});
    const std::vector<int> counts =
        context.quick ? std::vector<int>{1000, 5000} : std::vector<int>{1000, 3000, 10000, 30000, 100000};
    struct Variant {
        Config config;
        int threads;
    };
    const std::vector<Variant> variants = {
        {{"bullet-float", 0, true, false, "float"}, 1},   {{"bullet-double", 0, true, false, "double"}, 1},
        {{"lpss-float", 4096, false, false, "float"}, 1}, {{"lpss-float", 32, false, false, "float"}, 1},
        {{"lpss-float", 32, false, false, "float"}, 2},   {{"lpss-double", 32, false, false, "double"}, 1},
        {{"lpss-double", 32, false, false, "double"}, 2},
    };
    for (const Variant& v : variants) {
        if (!v.config.runs_here()) continue;
        for (int n : counts) {
            progress(fmt::format("scaling: {} on {} thread(s), {} bodies", v.config.label(), v.threads, n));
            const double L = v.config.sector_size > 0 ? v.config.sector_size : 4096.0;
            World world = make_world(field(n, L), v.config.options(v.threads));
            for (int f = 0; f < 30; ++f)
                world.step();  // contacts established
            const double ms = ms_per_frame(fmt::format("scaling/{}/{}/{}", v.config.label(), v.threads, n),
                                           world, 1, context.quick ? 0.2 : 1.0);
            table.add({v.config.name, num(v.config.sector_size), std::to_string(v.threads), std::to_string(n),
                       std::to_string(world.sectors().size()), num(ms, 4), ms <= 1000.0 / 60.0 ? "1" : "0"});
        }
    }
    merge_twin(context, "scaling", table);

    // The targets, as ratios measured in this run.
    auto find = [&](const std::string& config, const std::string& size, const std::string& threads, int n) {
        for (const auto& row : table.rows()) {
            if (row[0] == config && row[1] == size && row[2] == threads && row[3] == std::to_string(n)) {
                return std::stod(row[5]);
            }
        }
        return std::nan("");
    };
    std::string ratios =
        "| bodies | lpss-float L=4096 / bullet-float (1 thread; target <= 1.10) | best lpss-float / "
        "bullet-double (target <= 0.85) |\n|---|---|---|\n";
    for (int n : counts) {
        const double one_world = find("lpss-float", "4096", "1", n) / find("bullet-float", "0", "1", n);
        const double best = std::min({find("lpss-float", "4096", "1", n), find("lpss-float", "32", "1", n),
                                      find("lpss-float", "32", "2", n)});
        ratios += fmt::format("| {} | {:.3f} | {:.3f} |\n", n, one_world,
                              best / find("bullet-double", "0", "1", n));
    }
    std::string md =
        "A field of boxes and spheres four layers deep, resting on the ground, all awake (sleeping off). "
        "ms_per_frame: Google Benchmark, one frame per iteration after 30 frames of settling. "
        "realtime_60hz: 1 when a frame takes at most 16.7 ms.\n\n" +
        table.markdown() + "\nRatios from this run:\n\n" + ratios;
    std::string plot = R"(set title 'Frame time against bodies (dashed: real time at 60 Hz)'
set logscale xy
set xlabel 'bodies'
set ylabel 'milliseconds per frame'
set key top left
set arrow from graph 0, first 16.667 to graph 1, first 16.667 nohead dt 2 lc rgb 'gray'
s(c,l,t) = (strcol(1) eq c && $2 == l && $3 == t) ? $4 : 1/0
plot '$CSV' every ::1 using (s('bullet-float',0,1)):6 with linespoints pt 7 title 'bullet-float', \
     '$CSV' every ::1 using (s('bullet-double',0,1)):6 with linespoints pt 5 title 'bullet-double', \
     '$CSV' every ::1 using (s('lpss-float',4096,1)):6 with linespoints pt 9 title 'lpss-float L=4096 (one world)', \
     '$CSV' every ::1 using (s('lpss-float',32,1)):6 with linespoints pt 11 title 'lpss-float L=32, 1 thread', \
     '$CSV' every ::1 using (s('lpss-float',32,2)):6 with linespoints pt 13 title 'lpss-float L=32, 2 threads', \
     '$CSV' every ::1 using (s('lpss-double',32,1)):6 with linespoints pt 4 title 'lpss-double L=32, 1 thread', \
     '$CSV' every ::1 using (s('lpss-double',32,2)):6 with linespoints pt 6 title 'lpss-double L=32, 2 threads'
)";
    publish(context, "scaling", table, "scaling: bodies and threads", md, plot);
}

}  // namespace lpss::bench
