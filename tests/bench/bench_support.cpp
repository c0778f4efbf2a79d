#include "bench_support.hpp"

#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <malloc.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "scenes.hpp"

namespace lpss::bench {

std::string Config::label() const {
    if (sector_size > 0.0) return fmt::format("{} L={:g}", name, sector_size);
    return name;
}

EngineOptions Config::options(int threads) const {
    EngineOptions o;
    o.threads = threads;
    o.monolithic = monolithic;
    if (naive) {
        o.naive_sector_worlds = true;
        o.double_positions = false;
        o.floating_origins = false;
    }
    return o;
}

bool Config::runs_here() const { return precision == World::physics_precision(); }

std::vector<Config> comparison_configs() {
    std::vector<Config> out;
    out.push_back({"bullet-float", 0.0, true, false, "float"});
    out.push_back({"bullet-double", 0.0, true, false, "double"});
    for (double size : {64.0, 128.0, 1024.0, 4096.0})
        out.push_back({"lpss-float", size, false, false, "float"});
    out.push_back({"lpss-double", 1024.0, false, false, "double"});
    return out;
}

// ---- tables

Table::Table(std::vector<std::string> columns) : columns_(std::move(columns)) {}

void Table::add(std::vector<std::string> cells) {
    if (cells.size() != columns_.size()) throw std::logic_error("table row has the wrong number of cells");
    rows_.push_back(std::move(cells));
}

std::size_t Table::column(const std::string& name) const {
    for (std::size_t n = 0; n < columns_.size(); ++n) {
        if (columns_[n] == name) return n;
    }
    throw std::logic_error("no column " + name);
}

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
        if (c == '"') {
            quoted = !quoted;
        } else if (c == ',' && !quoted) {
            cells.push_back(cell);
            cell.clear();
        } else {
            cell += c;
        }
    }
    cells.push_back(cell);
    return cells;
}

std::string csv_cell(const std::string& cell) {
    if (cell.find_first_of(",\"") == std::string::npos) return cell;
    return "\"" + cell + "\"";
}

}  // namespace

void Table::add_csv(const std::string& csv) {
    std::istringstream in(csv);
    std::string line;
    if (!std::getline(in, line)) throw std::runtime_error("twin printed nothing");
    if (split_csv_line(line) != columns_) throw std::runtime_error("twin printed another header: " + line);
    while (std::getline(in, line)) {
        if (!line.empty()) add(split_csv_line(line));
    }
}

std::string Table::csv() const {
    std::string out;
    for (std::size_t n = 0; n < columns_.size(); ++n)
        out += (n ? "," : "") + csv_cell(columns_[n]);
    out += "\n";
    for (const auto& row : rows_) {
        for (std::size_t n = 0; n < row.size(); ++n)
            out += (n ? "," : "") + csv_cell(row[n]);
        out += "\n";
    }
    return out;
}

std::string Table::markdown(const std::vector<std::string>& wanted,
                            const std::function<bool(const std::vector<std::string>&)>& keep) const {
    std::vector<std::size_t> cols;
    if (wanted.empty()) {
        for (std::size_t n = 0; n < columns_.size(); ++n)
            cols.push_back(n);
    } else {
        for (const std::string& name : wanted)
            cols.push_back(column(name));
    }
    std::string out = "|";
    for (std::size_t c : cols)
        out += " " + columns_[c] + " |";
    out += "\n|";
    for (std::size_t n = 0; n < cols.size(); ++n)
        out += "---|";
    out += "\n";
    for (const auto& row : rows_) {
        if (keep && !keep(row)) continue;
        out += "|";
        for (std::size_t c : cols)
            out += " " + row[c] + " |";
        out += "\n";
    }
    return out;
}

std::string num(double value, int digits) { return fmt::format("{:.{}g}", value, digits); }

// ---- machine and outputs

std::string machine() {
    std::string cpu = "unknown CPU";
    std::ifstream info("/proc/cpuinfo");
    for (std::string line; std::getline(info, line);) {
        if (line.rfind("model name", 0) == 0) {
            cpu = line.substr(line.find(':') + 2);
            break;
        }
    }
    utsname u{};
    uname(&u);
    return fmt::format("{} x {}, {} {}, g++ {}, Bullet 3.24 (Debian), {} build",
                       std::thread::hardware_concurrency(), cpu, u.sysname, u.release, __VERSION__,
                       World::physics_precision());
}

namespace {

std::string today() {
    std::time_t t = std::time(nullptr);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%d", std::gmtime(&t));
    return buf;
}

void replace_all(std::string& text, const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
        text.replace(at, from.size(), to);
    }
}

}  // namespace

void publish(const Context& context, const std::string& name, const Table& table, const std::string& title,
             const std::string& markdown_body, const std::string& plot) {
    if (context.as_twin) {
        std::cout << table.csv();
        return;
    }
    std::filesystem::create_directories(context.out);
    const std::filesystem::path csv = context.out / (name + ".csv");
    const std::filesystem::path png = context.out / (name + ".png");
    const std::filesystem::path md = context.out / (name + ".md");
    const std::filesystem::path gp = context.out / (name + ".gp");
    std::ofstream(csv) << table.csv();
    std::string doc =
        fmt::format("## {}\n\nCommand: `{}`  \nMachine: {}  \nDate: {}\n\n{}\n\n![{}]({}.png)\n", title,
                    context.command, machine(), today(), markdown_body, name, name);
    std::ofstream(md) << doc;
    std::string script = plot;
    replace_all(script, "$CSV", csv.string());
    replace_all(script, "$PNG", png.string());
    std::ofstream(gp)
        << "set datafile separator ','\nset terminal pngcairo size 1400,900 font 'Sans,11'\nset output '"
        << png.string() << "'\n"
        << script;
    const std::string run =
        "gnuplot '" + gp.string() + "' 2>'" + (context.out / (name + ".gnuplot.log")).string() + "'";
    if (std::system(run.c_str()) != 0) {
        std::cerr << "lpss-bench: gnuplot failed for " << name << ": see "
                  << (context.out / (name + ".gnuplot.log")) << "\n";
    }
    std::cout << doc << "\n(written: " << csv.string() << ", " << md.string() << ", " << png.string()
              << ")\n";
}

void merge_twin(const Context& context, const std::string& subcommand, Table& table) {
    if (context.as_twin) return;
    std::string command = "'" + context.twin + "' --out '" + context.out.parent_path().string() + "' " +
                          subcommand + " --as-twin" + (context.quick ? " --quick" : "");
    progress("running the float64 twin: " + command);
    std::FILE* pipe = popen(command.c_str(), "r");
    if (pipe == nullptr) throw std::runtime_error("cannot start " + context.twin);
    std::string out;
    std::array<char, 4096> buffer{};
    while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe))
        out.append(buffer.data(), n);
    int status = pclose(pipe);
    if (status != 0) throw std::runtime_error("the float64 twin failed (" + command + ")");
    table.add_csv(out);
}

void progress(const std::string& what) { std::cerr << "lpss-bench: " << what << std::endl; }

double median(std::vector<double> values) {
    if (values.empty()) return std::nan("");
    std::sort(values.begin(), values.end());
    const std::size_t half = values.size() / 2;
    return values.size() % 2 ? values[half] : 0.5 * (values[half - 1] + values[half]);
}

// ---- timing with Google Benchmark

namespace {

/// Keeps the real time per iteration of the runs Google Benchmark reports, and prints nothing.
class Capture : public benchmark::BenchmarkReporter {
public:
    bool ReportContext(const Context&) override { return true; }
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            if (run.error_occurred) throw std::runtime_error("benchmark failed: " + run.error_message);
            seconds_per_iteration = run.real_accumulated_time / static_cast<double>(run.iterations);
        }
    }
    double seconds_per_iteration = 0.0;
};

/// Google Benchmark's mean real time per iteration; `iterations` > 0 fixes their number (a world's frames
/// cannot be run twice), else it runs for at least `min_seconds`.
double run_benchmark(const std::string& name, const std::function<void(benchmark::State&)>& body,
                     double min_seconds, benchmark::IterationCount iterations = 0) {
    static bool initialised = [] {
        int argc = 1;
        char arg0[] = "lpss-bench";
        char* argv[] = {arg0, nullptr};
        benchmark::Initialize(&argc, argv);
        return true;
    }();
    (void)initialised;
    benchmark::internal::Benchmark* registered =
        benchmark::RegisterBenchmark(name.c_str(), body)->UseRealTime();
    if (iterations > 0) {
        registered->Iterations(iterations);
    } else {
        registered->MinTime(min_seconds);
    }
    Capture capture;
    benchmark::RunSpecifiedBenchmarks(&capture);
    benchmark::ClearRegisteredBenchmarks();
    return capture.seconds_per_iteration;
}

}  // namespace

namespace {

/// A benchmark body whose every iteration steps `world` `frames` times.
std::function<void(benchmark::State&)> stepping(World& world, int frames,
                                                const std::function<void(const FrameStats&)>& each_frame) {
    return [&world, frames, &each_frame](benchmark::State& state) {
        for (auto _ : state) {
            for (int f = 0; f < frames; ++f) {
                world.step();
                if (each_frame) each_frame(world.last_frame_stats());
            }
        }
    };
}

}  // namespace

double ms_per_frame(const std::string& name, World& world, int frames, double min_seconds,
                    const std::function<void(const FrameStats&)>& each_frame) {
    return 1e3 * run_benchmark(name, stepping(world, frames, each_frame), min_seconds) / frames;
}

double ms_over_frames(const std::string& name, World& world, int frames,
                      const std::function<void(const FrameStats&)>& each_frame) {
    return 1e3 * run_benchmark(name, stepping(world, frames, each_frame), 0.0, 1) / frames;
}

double ms_per_frame_fresh(const std::string& name, const std::function<World()>& make, int frames,
                          double min_seconds) {
    double seconds = run_benchmark(
        name,
        [&](benchmark::State& state) {
            for (auto _ : state) {
                state.PauseTiming();
                World world = make();
                state.ResumeTiming();
                for (int f = 0; f < frames; ++f)
                    world.step();
                state.PauseTiming();
                { World gone = std::move(world); }
                state.ResumeTiming();
            }
        },
        min_seconds);
    return 1e3 * seconds / frames;
}

double us_per_call(const std::string& name, const std::function<void()>& call, double min_seconds) {
    return 1e6 * run_benchmark(
                     name,
                     [&](benchmark::State& state) {
                         for (auto _ : state)
                             call();
                     },
                     min_seconds);
}

double us_to_create(const std::string& name, const std::function<World()>& make, double min_seconds) {
    return 1e6 * run_benchmark(
                     name,
                     [&](benchmark::State& state) {
                         for (auto _ : state) {
                             World world = make();
                             state.PauseTiming();
                             { World gone = std::move(world); }
                             state.ResumeTiming();
                         }
                     },
                     min_seconds);
}

std::size_t heap_bytes() {
    struct mallinfo2 m = mallinfo2();
    return m.uordblks + m.hblkhd;
}

World make_world(const Scene& scene, const EngineOptions& options) {
    Expected<World> world = World::create(scene, options);
    if (!world) throw std::runtime_error("scene refused: " + world.error().message);
    return std::move(world).value();
}

Scene drifting(int count, int every) {
    Scene s;
    s.settings.sector_size = 8;
    s.settings.sleeping = false;
    std::mt19937_64 random(99);
    std::uniform_real_distribution<double> speed(-2.0, 2.0);
    const int side = static_cast<int>(std::ceil(std::cbrt(count)));
    for (int n = 0; n < count; ++n) {
        // Centred on the origin, so that the lattice spans several sectors and blocks of sectors.
        Eigen::Vector3d p(1.5 * (n % side - side / 2), 1.5 * (n / side % side - side / 2),
                          1.5 * (n / (side * side) - side / 2));
        BodyDesc b = n % 2 ? scenes::sphere_body(n + 1, 0.45, 1.0, p)
                           : scenes::box_body(n + 1, Eigen::Vector3d::Constant(0.4), 1.0, p);
        const Eigen::Vector3d v(speed(random), speed(random), speed(random));
        if (n % every == 0) b.linear_velocity = v;
        s.bodies.push_back(b);
    }
    return s;
}

}  // namespace lpss::bench
