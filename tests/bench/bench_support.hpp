// What every lpss-bench sub-command shares: configurations, result tables and their outputs (CSV,
// markdown, gnuplot PNG), the machine description, timing with Google Benchmark, and the float64 twin.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "lpss/engine/world.hpp"

namespace lpss::bench {

/// One way of simulating a scene. The double configurations run in the float64 twin.
struct Config {
    std::string name;          ///< bullet-float, bullet-double, lpss-float, lpss-double, naive-bullet
    double sector_size = 0.0;  ///< 0 for the monolithic configurations
    bool monolithic = false;
    bool naive = false;
    std::string precision;  ///< "float" or "double": the Bullet build it needs

    std::string label() const;  ///< "lpss-float L=128"
    EngineOptions options(int threads = 1) const;
    bool runs_here() const;  ///< built against the Bullet this program links
};

/// The standard comparison: monolithic float and double Bullet, lpss on float at several sector sizes,
/// lpss on double at one.
std::vector<Config> comparison_configs();

/// A table of strings with named columns; numbers are formatted by the caller.
class Table {
public:
    explicit Table(std::vector<std::string> columns);
    void add(std::vector<std::string> cells);
    /// Appends the rows of a CSV text with the same header (the twin's output).
    void add_csv(const std::string& csv);
    const std::vector<std::string>& columns() const { return columns_; }
    const std::vector<std::vector<std::string>>& rows() const { return rows_; }
    std::size_t column(const std::string& name) const;
    std::string csv() const;
    /// A markdown table of the named columns (all when empty), rows filtered by `keep`.
    std::string markdown(const std::vector<std::string>& columns = {},
                         const std::function<bool(const std::vector<std::string>&)>& keep = {}) const;

private:
    std::vector<std::string> columns_;
    std::vector<std::vector<std::string>> rows_;
};

std::string num(double value, int digits = 4);

/// Where a sub-command writes and how it was invoked.
struct Context {
    std::filesystem::path out;       ///< output folder of this sub-command
    std::string command;             ///< the command line that produced the results
    std::string twin;                ///< path of lpss-bench-f64
    bool quick = false;              ///< smaller sizes, for a smoke run
    bool as_twin = false;            ///< running inside the twin: print the table as CSV, nothing else
    bool keep = false;               ///< keep the scenes and logs a sub-command writes to a temporary folder
    bool security = false;           ///< cluster: with and without DDS Security, side by side
    std::vector<std::size_t> sizes;  ///< world sizes instead of the sub-command's own (when not empty)
    unsigned rounds = 0;             ///< times a sub-command repeats its runs (0: its own default)
};

/// "2 x Intel(R) Xeon(R) ..., Linux 6.1, g++ 12.2.0, Bullet 3.24": the machine a result came from.
std::string machine();

/// Writes <name>.csv, <name>.md (table, command, machine, reading) and <name>.png (from a gnuplot
/// script reading <name>.csv), and prints the markdown. `plot` is the gnuplot script's body: it may use
/// the file names "$CSV" and "$PNG", replaced before running.
void publish(const Context& context, const std::string& name, const Table& table, const std::string& title,
             const std::string& markdown_body, const std::string& plot);

/// Runs the twin with the same sub-command and appends its rows. Fails loudly if the twin fails.
void merge_twin(const Context& context, const std::string& subcommand, Table& table);

/// Progress on stderr, so long runs show where they are.
void progress(const std::string& what);

/// Mean real time per frame, measured by Google Benchmark: each iteration steps `world` `frames` times;
/// `each_frame` (not timed separately) may read the frame's statistics.
double ms_per_frame(const std::string& name, World& world, int frames, double min_seconds = 0.2,
                    const std::function<void(const FrameStats&)>& each_frame = {});
/// Mean real time per frame over exactly the next `frames` frames of `world` (one Google Benchmark
/// iteration): a fixed window of a world's history, the same for every size.
double ms_over_frames(const std::string& name, World& world, int frames,
                      const std::function<void(const FrameStats&)>& each_frame = {});
/// Each iteration builds a world (not timed) and steps it `frames` times (timed).
double ms_per_frame_fresh(const std::string& name, const std::function<World()>& make, int frames,
                          double min_seconds = 0.2);
/// Mean real time of one call, in microseconds, measured by Google Benchmark.
double us_per_call(const std::string& name, const std::function<void()>& call, double min_seconds = 0.2);
/// Mean real time to build a world with `make`, in microseconds; its destruction is not timed.
double us_to_create(const std::string& name, const std::function<World()>& make, double min_seconds = 0.2);

/// The middle value (the mean of the two middle ones for an even count); NaN for none.
double median(std::vector<double> values);

/// Bytes the process has allocated from the heap right now (glibc mallinfo2).
std::size_t heap_bytes();

/// A world for a scene, or an exit with the reason.
World make_world(const Scene& scene, const EngineOptions& options);

/// `count` bodies in a lattice 1.5 apart around the origin, without gravity, in sectors of 8; one in
/// `every` drifting at up to 2 units/s, the others at rest until something hits them.
Scene drifting(int count, int every);

}  // namespace lpss::bench
