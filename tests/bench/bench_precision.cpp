// precision (the paper's Figure 5): two spheres pushed towards each other at distances from 0 to 1e15,
// along x and the diagonal; error = summed distance between each sphere's final position (relative to
// the offset) and the same configuration's run at the origin.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "scenes.hpp"
#include "subcommands.hpp"

namespace lpss::bench {
namespace {

constexpr int kFrames = 180;

struct PairResult {
    double error = 0.0;
    bool collided = false;
};

std::map<BodyId, Eigen::Vector3d> final_relative(World& world, const scenes::Centre& centre) {
    for (int f = 0; f < kFrames; ++f)
        world.step();
    std::map<BodyId, Eigen::Vector3d> out;
    for (const BodySnapshot& b : world.snapshot())
        out[b.id] = scenes::relative_position(world.grid(), b, centre);
    return out;
}

}  // namespace

std::vector<double> precision_distances(bool quick) {
    std::set<double> d{0.0};
    for (int e = 0; e <= 49; e += quick ? 7 : 1)
        d.insert(std::ldexp(1.0, e));
    for (int e = 0; e <= 15; e += quick ? 3 : 1)
        d.insert(std::pow(10.0, e));
    return {d.begin(), d.end()};
}

/// Far distances are placed by sector position: a double global position cannot hold a sphere's place
/// there (at 1e15 its spacing is 0.125).
scenes::Centre place(double distance, const Eigen::Vector3d& axis, double L, std::string& placement) {
    Eigen::Vector3d offset = distance * axis;
    if (distance < 1e12) {
        placement = "global";
        return offset;
    }
    placement = "sector";
    SectorPosition p;
    for (int a = 0; a < 3; ++a) {
        double index = std::floor(offset[a] / L + 0.5);
        (&p.sector.i)[a] = static_cast<std::int64_t>(index);
        p.local[a] = offset[a] - index * L;  // exact enough: only the placement's own rounding
    }
    return p;
}

void run_precision(const Context& context) {
    Table table({"scene", "direction", "distance", "config", "sector_size", "error", "ms_per_frame",
                 "collided", "placement"});
    const Eigen::Vector3d diagonal = Eigen::Vector3d::Ones().normalized();
    const std::vector<double> distances = precision_distances(context.quick);
    for (const Config& config : comparison_configs()) {
        if (!config.runs_here()) continue;
        const double L = config.sector_size > 0 ? config.sector_size : 128.0;
        for (const auto& [direction, axis] :
             {std::pair{"x", Eigen::Vector3d::UnitX().eval()}, {"diagonal", diagonal}}) {
            progress("precision: " + config.label() + " along " + direction);
            World origin =
                make_world(scenes::sphere_pair(Eigen::Vector3d::Zero().eval(), L, axis), config.options());
            const auto truth = final_relative(origin, Eigen::Vector3d::Zero().eval());
            for (double d : distances) {
                std::string placement;
                const scenes::Centre centre = place(d, axis, L, placement);
                const Scene scene = scenes::sphere_pair(centre, L, axis);
                World far = make_world(scene, config.options());
                const auto got = final_relative(far, centre);
                double error = 0.0;
                for (const auto& [id, p] : got)
                    error += (p - truth.at(id)).norm();
                const bool collided = far.body(1)->linear_velocity.dot(axis) < 0.0;
                const double ms = ms_per_frame_fresh(
                    "precision/" + config.label(), [&] { return make_world(scene, config.options()); },
                    kFrames, 0.01);
                table.add({"two_spheres", direction, num(d, 17), config.name, num(config.sector_size),
                           num(error, 6), num(ms, 4), collided ? "1" : "0", placement});
            }
        }
    }
    merge_twin(context, "precision", table);

    // The markdown: error at a few telling distances, one column per configuration.
    std::vector<std::string> labels;
    std::map<std::string, std::map<std::pair<std::string, double>, std::string>> cells;
    const std::size_t c_dir = table.column("direction"), c_d = table.column("distance"),
                      c_cfg = table.column("config"), c_l = table.column("sector_size"),
                      c_err = table.column("error"), c_hit = table.column("collided");
    for (const auto& row : table.rows()) {
        std::string label = row[c_cfg] + (row[c_l] != "0" ? " L=" + row[c_l] : "");
        if (std::find(labels.begin(), labels.end(), label) == labels.end()) labels.push_back(label);
        cells[label][{row[c_dir], std::stod(row[c_d])}] =
            row[c_hit] == "1" ? num(std::stod(row[c_err]), 2) : "no collision";
    }
    std::string md =
        "Summed error of the two spheres' final positions against the same configuration at the origin "
        "(lower is better; \"no collision\": the spheres passed through each other or never moved).\n\n";
    for (const char* direction : {"x", "diagonal"}) {
        md += std::string("Along ") + direction + ":\n\n| distance |";
        for (const auto& l : labels)
            md += " " + l + " |";
        md += "\n|---|";
        for (std::size_t n = 0; n < labels.size(); ++n)
            md += "---|";
        md += "\n";
        for (double d : {0.0, 1e3, 1e6, 16777216.0, 1e9, 1e12, 1e15}) {
            md += "| " + num(d, 6) + " |";
            for (const auto& l : labels) {
                auto it = cells[l].find({direction, d});
                md += " " + (it == cells[l].end() ? std::string("-") : it->second) + " |";
            }
            md += "\n";
        }
        md += "\n";
    }
    md +=
        "Distances from 1e12 on are placed by sector position; below, by double global position, whose "
        "rounding "
        "is part of the error. Full data: precision.csv.";

    std::string plot =
        R"(set multiplot layout 1,2 title 'Two spheres: error against distance from the origin (crosses: no collision)'
set logscale xy
set xrange [0.5:2e15]
set yrange [1e-12:1e5]
set format x '10^{%L}'
set format y '10^{%L}'
set xlabel 'distance from the origin'
set ylabel 'summed final position error'
set key top left font ',9'
e(c,l,d) = (strcol(4) eq c && $5 == l && strcol(2) eq d && $8 == 1) ? ($6 > 1e-12 ? $6 : 1e-12) : 1/0
m(c,l,d) = (strcol(4) eq c && $5 == l && strcol(2) eq d && $8 == 0) ? ($6 > 1e-12 ? ($6 < 1e5 ? $6 : 1e5) : 1e-12) : 1/0
)";
    for (const char* direction : {"x", "diagonal"}) {
        plot += std::string("set title 'along ") + direction + "'\nplot ";
        int n = 1;
        for (const Config& c : comparison_configs()) {
            plot += fmt::format(
                "'$CSV' every ::1 using 3:(e('{0}',{1:g},'{2}')) with linespoints lc {3} pt 7 ps 0.6 "
                "title '{4}', '$CSV' every ::1 using 3:(m('{0}',{1:g},'{2}')) with points lc {3} pt 2 "
                "ps 1.2 notitle, ",
                c.name, c.sector_size, direction, n++, c.label());
        }
        plot.erase(plot.size() - 2);
        plot += "\n";
    }
    plot += "unset multiplot\n";
    publish(context, "precision", table, "precision: two spheres at any distance (paper Figure 5)", md, plot);
}

}  // namespace lpss::bench
