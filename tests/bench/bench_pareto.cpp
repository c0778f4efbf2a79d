// pareto: error against milliseconds per frame, for three scenes at four distances from the origin, every
// configuration on the same axes: plain float and double Bullet, lpss at several sector sizes (on float and
// on double Bullet) and lpss-cluster with 1, 2 and 3 workers, so that the price of precision and the price
// of distribution read off one figure. Error is measured twice: against one reference for every
// configuration (plain double Bullet run at the origin) and against the same configuration run at the
// origin, which shows what distance alone does.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "scenes.hpp"
#include "subcommands.hpp"

#if LPSS_BENCH_DRIVER
#include <unistd.h>

#include <chrono>
#include <optional>

#include "child_process.hpp"
#include "lpss/client/client.hpp"
#include "lpss_dds/shm_cleanup.hpp"
#endif

namespace lpss::bench {

scenes::Centre place(double distance, const Eigen::Vector3d& axis, double L, std::string& placement);

namespace {

using Positions = std::map<BodyId, Eigen::Vector3d>;

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
    bool summed;  ///< error summed over the bodies (two spheres) rather than a mean per body
    std::function<Scene(const scenes::Centre&, double)> make;
};

/// The sector size of the cluster runs and of the in-process run beside them: small enough that the pile
/// spans several sectors (and so several workers), as a distributed world does.
constexpr double kClusterSectorSize = 16.0;
constexpr int kClusterDomain = 160;

/// The configurations run in one process: the standard comparison plus lpss at the cluster's sector size.
std::vector<Config> in_process_configs() {
    std::vector<Config> out = comparison_configs();
    out.insert(out.begin() + 2, Config{"lpss-float", kClusterSectorSize, false, false, "float"});
    return out;
}

Positions run_and_read(World& world, int frames, const scenes::Centre& centre) {
    for (int f = 0; f < frames; ++f)
        world.step();
    Positions out;
    for (const BodySnapshot& b : world.snapshot())
        out[b.id] = scenes::relative_position(world.grid(), b, centre);
    return out;
}

/// Distance of `got` from `truth`: summed over the bodies, or a mean per body.
double error_between(const SceneKind& kind, const Positions& got, const Positions& truth) {
    if (got.size() != truth.size())
        throw std::runtime_error(fmt::format("pareto: {} bodies in a run of {} where {} were expected",
                                             got.size(), kind.name, truth.size()));
    double error = 0.0;
    for (const auto& [id, p] : got) {
        auto it = truth.find(id);
        if (it == truth.end())
            throw std::runtime_error(
                fmt::format("pareto: body {} of {} not in the reference", id, kind.name));
        error += (p - it->second).norm();
    }
    return kind.summed ? error : error / static_cast<double>(got.size());
}

// The reference (plain double Bullet at the origin) runs in the float64 twin, which runs first and leaves
// it in a file for the driver.
std::filesystem::path reference_file(const Context& context, const SceneKind& kind) {
    return context.out / ("reference_" + kind.name + ".csv");
}

void write_positions(const std::filesystem::path& file, const Positions& positions) {
    std::ofstream out(file);
    for (const auto& [id, p] : positions)
        out << fmt::format("{},{:.17g},{:.17g},{:.17g}\n", id, p.x(), p.y(), p.z());
    if (!out) throw std::runtime_error("pareto: cannot write " + file.string());
}

Positions read_positions(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw std::runtime_error("pareto: the twin left no reference in " + file.string());
    Positions out;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        BodyId id = 0;
        Eigen::Vector3d p;
        char comma = 0;
        if (!(fields >> id >> comma >> p.x() >> comma >> p.y() >> comma >> p.z()))
            throw std::runtime_error("pareto: unreadable reference line '" + line + "' in " + file.string());
        out[id] = p;
    }
    return out;
}

#if LPSS_BENCH_DRIVER
struct ClusterResult {
    Positions positions;
    double ms_per_frame = 0.0;
    bool collided = true;
};

/// Runs `scene` on lpss-cluster with `workers` workers, unpaced, and reads its last frame through
/// lpss::Client. ms per frame is the coordinator's own cadence (the frames' start times) after frame 1.
ClusterResult run_on_cluster(const SceneKind& kind, const Scene& scene, const scenes::Centre& centre,
                             int workers, const std::filesystem::path& logs) {
    std::filesystem::create_directories(logs);
    const std::filesystem::path file = logs / "scene.textproto";
    std::ofstream(file) << format_scene(scene);
    const std::uint64_t last = static_cast<std::uint64_t>(kind.frames);
    auto cluster = runtime::ChildProcess::start(
        LPSS_CLUSTER_PROGRAM,
        {file.string(), "--workers", std::to_string(workers), "--frames", std::to_string(last), "--domain",
         std::to_string(kClusterDomain), "--await-clients", "1", "--quiet", "--log-dir",
         (logs / "cluster-logs").string()},
        (logs / "cluster.out").string());
    if (!cluster) throw std::runtime_error("cannot start lpss-cluster");
    ClientOptions options;
    options.domain = kClusterDomain;
    options.name = "lpss-bench-pareto";
    Expected<std::unique_ptr<Client>> client = Client::connect(options);
    if (!client) throw std::runtime_error(client.error().message);
    std::map<std::uint64_t, std::chrono::system_clock::time_point> started;
    std::optional<WorldFrame> final_frame;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    while (!final_frame && std::chrono::steady_clock::now() < deadline) {
        for (WorldFrame& f : (*client)->poll(std::chrono::milliseconds(20))) {
            started[f.frame] = f.started;
            if (f.frame == last) final_frame = std::move(f);
        }
    }
    const std::optional<WorldSettings> settings = (*client)->settings();
    client->reset();
    const bool ended = cluster->wait(std::chrono::seconds(30));
    const int exit_code = ended ? cluster->exit_code().value_or(1) : cluster->stop();
    dds::remove_abandoned_shm(kClusterDomain);
    if (!final_frame || !settings)
        throw std::runtime_error(fmt::format("pareto: no frame {} from lpss-cluster (exit {}): see {}", last,
                                             exit_code, logs.string()));
    if (exit_code != 0)
        throw std::runtime_error(
            fmt::format("pareto: lpss-cluster ended with {}: see {}", exit_code, logs.string()));
    ClusterResult out;
    const SectorGrid grid(settings->sector_size);
    const SectorPosition c = scenes::centre_on(grid, centre);
    for (const BodyView& b : final_frame->bodies) {
        out.positions[b.id] = grid.offset_in(b.position, c.sector) - c.local;
        if (b.id == 1 && kind.summed) out.collided = b.linear_velocity.x() < 0.0;
    }
    // Frames 2..last, so that start-up (the first frame waits for the client) is not counted.
    auto second = started.upper_bound(1);
    if (second == started.end() || second->first >= last)
        throw std::runtime_error("pareto: too few frames seen from lpss-cluster: see " + logs.string());
    out.ms_per_frame = std::chrono::duration<double, std::milli>(started.at(last) - second->second).count() /
                       static_cast<double>(last - second->first);
    return out;
}
#endif

// ---- the figure

/// How one configuration is drawn. lpss at several sector sizes (and the cluster at several worker counts)
/// give the same answers at nearly the same cost: they are concentric open markers of growing size, so
/// that points on top of each other stay visible as rings.
struct Series {
    std::string config;  ///< the CSV's config column
    double sector_size;
    int workers;
    std::string label;
    std::string colour;
    int point_type;
    double point_size;
};

std::vector<Series> figure_series() {
    return {
        {"bullet-float", 0, 0, "plain float Bullet", "#9400d3", 9, 1.5},
        {"bullet-double", 0, 0, "plain double Bullet", "#009e73", 5, 1.1},
        {"lpss-float", 16, 0, "lpss float L=16", "#0072b2", 6, 0.9},
        {"lpss-float", 64, 0, "lpss float L=64", "#0072b2", 6, 1.4},
        {"lpss-float", 128, 0, "lpss float L=128", "#0072b2", 6, 1.9},
        {"lpss-float", 1024, 0, "lpss float L=1024", "#0072b2", 6, 2.4},
        {"lpss-float", 4096, 0, "lpss float L=4096", "#0072b2", 6, 2.9},
        {"lpss-double", 1024, 0, "lpss double L=1024", "#d55e00", 12, 2.2},
        {"lpss-cluster", 16, 1, "lpss-cluster L=16, 1 worker", "#e69f00", 4, 1.3},
        {"lpss-cluster", 16, 2, "lpss-cluster L=16, 2 workers", "#e69f00", 4, 2.0},
        {"lpss-cluster", 16, 3, "lpss-cluster L=16, 3 workers", "#e69f00", 4, 2.7},
    };
}

struct Row {
    std::string scene, config;
    double distance = 0, sector_size = 0, error = 0, reference_error = 0, ms = 0;
    int workers = 0;
    bool collided = true;
};

std::vector<Row> rows_of(const Table& table) {
    std::vector<Row> out;
    auto col = [&](const char* name) { return table.column(name); };
    for (const auto& r : table.rows())
        out.push_back(Row{r[col("scene")], r[col("config")], std::stod(r[col("distance")]),
                          std::stod(r[col("sector_size")]), std::stod(r[col("error")]),
                          std::stod(r[col("error_vs_reference")]), std::stod(r[col("ms_per_frame")]),
                          std::stoi(r[col("workers")]), r[col("collided")] == "1"});
    return out;
}

bool same_distance(double a, double b) { return std::abs(a / b - 1.0) < 1e-9; }

/// A number in few characters: 2 digits, no leading zeros in the exponent ("1.4e-7").
std::string short_number(double v) {
    if (v == 0) return "0";
    if (v >= 10 && v < 1e4) return fmt::format("{:.0f}", v);
    std::string text = fmt::format("{:.2g}", v);
    const std::size_t e = text.find('e');
    if (e != std::string::npos) {
        std::string exponent = text.substr(e + 1);
        const bool negative = exponent[0] == '-';
        exponent.erase(0, exponent.find_first_not_of("+-0"));
        text = text.substr(0, e + 1) + (negative ? "-" : "") + exponent;
    }
    return text;
}

std::string short_range(double lo, double hi, const std::string& unit = "") {
    return hi > 1.5 * lo ? short_number(lo) + ".." + short_number(hi) + unit : short_number(hi) + unit;
}

/// One line under a panel: the errors each family reached there (and the cost of lpss and of the
/// cluster), from the numbers drawn in it.
std::string panel_reading(const std::vector<const Row*>& points, bool reference) {
    struct Span {
        double lo = std::numeric_limits<double>::infinity(), hi = 0;
        double ms_lo = std::numeric_limits<double>::infinity(), ms_hi = 0;
        bool missed = false;
    };
    std::map<std::string, Span> family;
    for (const Row* r : points) {
        const std::string name = r->config == "lpss-float"     ? "lpss"
                                 : r->config == "lpss-cluster" ? "cluster"
                                 : r->config == "lpss-double"  ? "lpss double"
                                 : r->config == "bullet-float" ? "float"
                                                               : "double";
        Span& s = family[name];
        const double v = reference ? r->reference_error : r->error;
        s.lo = std::min(s.lo, v);
        s.hi = std::max(s.hi, v);
        s.ms_lo = std::min(s.ms_lo, r->ms);
        s.ms_hi = std::max(s.ms_hi, r->ms);
        s.missed = s.missed || !r->collided;
    }
    std::string line;
    for (const std::string name : {"lpss", "cluster", "float", "double"}) {
        auto it = family.find(name);
        if (it == family.end()) continue;
        const Span& s = it->second;
        std::string cost;
        if (name == "lpss")
            cost = " @ " + (s.ms_hi < 0.1 ? short_range(s.ms_lo * 1e3, s.ms_hi * 1e3, "us")
                                          : short_range(s.ms_lo, s.ms_hi, "ms"));
        if (name == "cluster") cost = " @ " + short_range(s.ms_lo, s.ms_hi, "ms");
        line += fmt::format("{}{} {}{}{}", line.empty() ? "" : "; ", name, short_range(s.lo, s.hi),
                            s.missed ? " missed" : "", cost);
    }
    return line;
}

/// A gnuplot script drawing one figure: a row per scene, a column per distance, error (log) against ms
/// per frame (log). `reference`: errors against plain double Bullet at the origin, else against each
/// configuration's own run at the origin.
std::string figure_script(const std::vector<Row>& rows, const std::vector<SceneKind>& kinds,
                          const std::vector<double>& distances, bool reference, const std::string& png) {
    const std::vector<Series> series = figure_series();
    const double key_height = 0.08, title_height = 0.04;
    const double panel_w = 1.0 / static_cast<double>(distances.size());
    const double panel_h = (1.0 - title_height - key_height) / static_cast<double>(kinds.size());
    // reset: nothing of the figure before (the key's blank axes) carries over.
    std::string s =
        fmt::format("reset\nset terminal pngcairo size 2300,1500 font 'Sans,10'\nset output '{}'\n", png);
    s += "set datafile separator whitespace\nset termoption noenhanced\nset logscale xy\nset format y "
         "'1e%L'\nset format x '%g'\n"
         "set grid xtics ytics mxtics mytics lc rgb '#e8e8e8'\nunset key\n"
         "set lmargin 8\nset rmargin 2\nset tmargin 2\nset bmargin 4.5\n";
    s += fmt::format(
        "set multiplot\nset label 999 \"{}\" at screen 0.5, screen 0.985 center font ',14'\n",
        reference
            ? "Error against cost. Error: distance of every body from plain double Bullet's run of the scene "
              "at the origin (the reference for all)"
            : "Error against cost. Error: distance of every body from the same configuration's own run of "
              "the "
              "scene at the origin (what distance alone does)");
    for (std::size_t k = 0; k < kinds.size(); ++k) {
        // One y range per row, holding every point of the row; zero errors drawn on a line of their own
        // below.
        double lo = std::numeric_limits<double>::infinity(), hi = 0, ms_lo = lo, ms_hi = 0;
        for (const Row& r : rows) {
            if (r.scene != kinds[k].name) continue;
            const double v = reference ? r.reference_error : r.error;
            if (v > 0) lo = std::min(lo, v), hi = std::max(hi, v);
            ms_lo = std::min(ms_lo, r.ms), ms_hi = std::max(ms_hi, r.ms);
        }
        if (hi == 0) lo = 1e-16, hi = 1;
        const double floor_decade = std::pow(10.0, std::floor(std::log10(lo)) - 1);
        const double zero_at = floor_decade / 10;
        const double top = std::pow(10.0, std::ceil(std::log10(hi * 3)));
        const double x_lo = std::pow(10.0, std::floor(std::log10(ms_lo))),
                     x_hi = std::pow(10.0, std::ceil(std::log10(ms_hi)));
        for (std::size_t d = 0; d < distances.size(); ++d) {
            std::vector<const Row*> points;
            for (const Row& r : rows)
                if (r.scene == kinds[k].name && same_distance(r.distance, distances[d])) points.push_back(&r);
            s += fmt::format("set origin {},{}\nset size {},{}\n", d * panel_w,
                             1.0 - title_height - (k + 1) * panel_h, panel_w, panel_h);
            s += fmt::format("set title '{} at {:.15g}'\n", kinds[k].name, distances[d]);
            s += fmt::format("set xrange [{:g}:{:g}]\nset yrange [{:g}:{:g}]\n", x_lo / 1.5, x_hi * 1.5,
                             zero_at / 3, top);
            s += fmt::format("set ytics auto\nset ytics add ('0' {:g})\n", zero_at);
            s += fmt::format(
                "set arrow 1 from graph 0, first {:g} to graph 1, first {:g} nohead dt 3 lc rgb '#999999'\n",
                std::sqrt(zero_at * floor_decade), std::sqrt(zero_at * floor_decade));
            // The panel's reading goes under its axis label, so that it stays with its panel.
            s += fmt::format(
                "set xlabel \"ms per frame\\n{}\" offset 0,0.3 font ',8.5'\nset ylabel 'error' offset "
                "1.5,0\n",
                panel_reading(points, reference));
            // One data block per panel: x, y as drawn, series index, 1 when the run failed (no collision).
            s += fmt::format("$P{}{} << EOD\n", k, d);
            for (const Row* r : points) {
                for (std::size_t i = 0; i < series.size(); ++i) {
                    const Series& sr = series[i];
                    if (sr.config != r->config || sr.sector_size != r->sector_size ||
                        sr.workers != r->workers)
                        continue;
                    const double v = reference ? r->reference_error : r->error;
                    s += fmt::format("{:.6g} {:.6g} {} {}\n", r->ms, v > 0 ? v : zero_at, i,
                                     r->collided ? 0 : 1);
                }
            }
            s += "EOD\nplot ";
            std::vector<bool> present(series.size(), false);
            bool failed = false;
            for (const Row* r : points) {
                for (std::size_t i = 0; i < series.size(); ++i)
                    if (series[i].config == r->config && series[i].sector_size == r->sector_size &&
                        series[i].workers == r->workers)
                        present[i] = true;
                failed = failed || !r->collided;
            }
            std::string elements;
            for (std::size_t i = 0; i < series.size(); ++i)
                if (present[i])
                    elements += fmt::format(
                        "{}$P{}{} using 1:($3 == {} ? $2 : 1/0) with points lc rgb '{}' pt {} ps {} lw 1.5",
                        elements.empty() ? "" : ", ", k, d, i, series[i].colour, series[i].point_type,
                        series[i].point_size);
            if (failed)
                elements += fmt::format(
                    ", $P{}{} using 1:($4 == 1 ? $2 : 1/0) with points lc rgb 'black' pt 2 ps 3.2 lw 2", k,
                    d);
            s += (elements.empty() ? "NaN notitle" : elements) + "\n";
            s += "unset arrow 1\nunset label 999\n";
        }
    }
    // The key, once, in a strip of its own under the panels.
    s += fmt::format(
        "set origin 0,0\nset size 1,{}\nunset title\nunset logscale\nunset border\nunset tics\nunset grid\n"
        "unset xlabel\nunset ylabel\nset xrange [0:1]\nset yrange [0:1]\nset lmargin 0\nset rmargin 0\n"
        "set tmargin 0\nset bmargin 0\n"
        "set key at graph 0.03, graph 0.95 left top Left reverse horizontal maxrows 3 width 3 spacing 1.5 "
        "font ',11'\nplot ",
        key_height);
    for (const Series& sr : series)
        s += fmt::format("NaN with points lc rgb '{}' pt {} ps {} lw 1.5 title '{}', ", sr.colour,
                         sr.point_type, sr.point_size, sr.label);
    s += "NaN with points lc rgb 'black' pt 2 ps 3.2 lw 2 title 'x: the spheres did not collide', "
         "NaN with lines dt 3 lc rgb '#999999' title '0: error exactly 0 (below the line)'\n";
    s += "unset multiplot\n";
    return s;
}

}  // namespace

void run_pareto(const Context& context) {
    Table table({"scene", "direction", "distance", "config", "sector_size", "workers", "error",
                 "error_vs_reference", "ms_per_frame", "collided", "placement"});
    std::filesystem::create_directories(context.out);
    const int pile_count = context.quick ? 300 : 2000;
    const std::vector<SceneKind> kinds = {
        {"two_spheres", 180, true,
         [](const scenes::Centre& c, double L) { return scenes::sphere_pair(c, L); }},
        {"box_stack_10", 600, false,
         [](const scenes::Centre& c, double L) { return scenes::box_stack(c, 10, L); }},
        {"mixed_pile_" + std::to_string(pile_count), 30, false,
         [pile_count](const scenes::Centre& c, double L) { return mixed_pile(c, L, pile_count); }},
    };
    // 1e13 + 37.3: not a multiple of any sector size, so that the far run's local coordinates differ.
    const std::vector<double> distances = {1e3 + 0.7, 1e6 + 3.1, 1e9 + 11.9, 1e13 + 37.3};
    const Eigen::Vector3d origin = Eigen::Vector3d::Zero();

    // The reference: plain double Bullet at the origin, from the twin (which runs first) or made here.
    std::map<std::string, Positions> reference;
    if (context.as_twin) {
        const Config double_bullet{"bullet-double", 0.0, true, false, "double"};
        for (const SceneKind& kind : kinds) {
            World world = make_world(kind.make(origin, 1024.0), double_bullet.options());
            reference[kind.name] = run_and_read(world, kind.frames, origin);
            write_positions(reference_file(context, kind), reference[kind.name]);
        }
    } else {
        merge_twin(context, "pareto", table);
        for (const SceneKind& kind : kinds) {
            reference[kind.name] = read_positions(reference_file(context, kind));
            if (!context.keep) std::filesystem::remove(reference_file(context, kind));
        }
    }

    for (const Config& config : in_process_configs()) {
        if (!config.runs_here()) continue;
        const double L = config.sector_size > 0 ? config.sector_size : 1024.0;
        for (const SceneKind& kind : kinds) {
            progress("pareto: " + kind.name + " with " + config.label());
            World at_origin = make_world(kind.make(origin, L), config.options());
            const Positions own = run_and_read(at_origin, kind.frames, origin);
            for (double d : distances) {
                std::string placement;
                const scenes::Centre centre = place(d, Eigen::Vector3d::UnitX(), L, placement);
                const Scene scene = kind.make(centre, L);
                World far = make_world(scene, config.options());
                const Positions got = run_and_read(far, kind.frames, centre);
                const bool collided = !kind.summed || far.body(1)->linear_velocity.x() < 0.0;
                // The same run the error was measured on, from a fresh world each time.
                const double ms = ms_per_frame_fresh(
                    fmt::format("pareto/{}/{}", kind.name, config.label()),
                    [&] { return make_world(scene, config.options()); }, kind.frames, 0.05);
                table.add({kind.name, "x", num(d, 17), config.name, num(config.sector_size), "0",
                           num(error_between(kind, got, own), 6),
                           num(error_between(kind, got, reference.at(kind.name)), 6), num(ms, 4),
                           collided ? "1" : "0", placement});
            }
        }
    }

#if LPSS_BENCH_DRIVER
    // The cluster on the same scenes: each worker count at the origin and at every distance.
    const std::filesystem::path logs =
        std::filesystem::temp_directory_path() / fmt::format("lpss-bench-pareto-{}", ::getpid());
    progress("pareto: cluster logs in " + logs.string());
    const std::vector<int> worker_counts = context.quick ? std::vector<int>{1, 2} : std::vector<int>{1, 2, 3};
    for (const SceneKind& kind : kinds) {
        for (int workers : worker_counts) {
            progress(fmt::format("pareto: {} on lpss-cluster with {} worker(s)", kind.name, workers));
            const double L = kClusterSectorSize;
            const ClusterResult own = run_on_cluster(kind, kind.make(origin, L), origin, workers,
                                                     logs / fmt::format("{}-{}-0", kind.name, workers));
            for (double d : distances) {
                std::string placement;
                const scenes::Centre centre = place(d, Eigen::Vector3d::UnitX(), L, placement);
                const ClusterResult got =
                    run_on_cluster(kind, kind.make(centre, L), centre, workers,
                                   logs / fmt::format("{}-{}-{:g}", kind.name, workers, d));
                table.add({kind.name, "x", num(d, 17), "lpss-cluster", num(L), std::to_string(workers),
                           num(error_between(kind, got.positions, own.positions), 6),
                           num(error_between(kind, got.positions, reference.at(kind.name)), 6),
                           num(got.ms_per_frame, 4), got.collided ? "1" : "0", placement});
            }
        }
    }
    if (!context.keep) std::filesystem::remove_all(logs);
#endif

    const std::string md =
        "Each point: one configuration, one scene, one distance along x. Two errors: `error_vs_reference` "
        "against plain double Bullet's run of the scene at the origin, one reference for every configuration "
        "(first figure), and `error` against the same configuration's own run at the origin, which isolates "
        "what "
        "distance does (second figure). Two spheres: summed distance after 3 s; stack: mean over boxes after "
        "10 s; "
        "pile: mean over bodies after 0.5 s of falling, a chaotic scene where small differences grow. "
        "ms_per_frame: Google Benchmark in one process; for lpss-cluster (unpaced, localhost, the built-in "
        "profile, a client reading every body), the coordinator's frame cadence from frame 2 to the last, "
        "one run "
        "each. Distances are offset from round numbers (1e3 + 0.7 ... 1e13 + 37.3) so that no run sits on a "
        "sector multiple; the last is placed by sector position.\n\n" +
        table.markdown({"scene", "distance", "config", "sector_size", "workers", "error_vs_reference",
                        "error", "ms_per_frame", "collided"});
    const std::vector<Row> rows = context.as_twin ? std::vector<Row>{} : rows_of(table);
    const std::string plot = context.as_twin
                                 ? std::string()
                                 : figure_script(rows, kinds, distances, true, "$PNG") +
                                       figure_script(rows, kinds, distances, false,
                                                     (context.out / "pareto_own_origin.png").string());
    publish(context, "pareto", table, "pareto: error against run time", md, plot);
}

}  // namespace lpss::bench
