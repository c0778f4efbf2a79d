// lpss-bench: the measurements behind docs/results.md. Each sub-command runs the same scenes through
// the configurations it compares (monolithic float and double Bullet, lpss at several sector sizes,
// lpss on double Bullet), measuring time with Google Benchmark, and writes CSV, a markdown table and a
// gnuplot PNG. Built twice: lpss-bench (float Bullet, the driver) runs lpss-bench-f64 (float64 Bullet)
// as a child process for the double configurations, so that one command gives the whole comparison.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>

#include "subcommands.hpp"

int main(int argc, char** argv) {
    using namespace lpss::bench;
    CLI::App app{"lpss-bench: error against run time, side by side (see docs/results.md)"};
    app.require_subcommand(1);
    app.fallthrough();
    std::string out = "bench-results";
    std::string twin;
    bool quick = false;
    bool as_twin = false;
    bool keep = false;
    bool security = false;
    std::vector<std::size_t> sizes;
    unsigned rounds = 0;
    app.add_option("--out", out, "output folder (a sub-folder per sub-command)");
    app.add_option("--twin", twin, "the float64 twin (default: lpss-bench-f64 beside this program)");
    app.add_flag("--quick", quick, "smaller sizes and fewer points: a smoke run");
    app.add_option("--bodies", sizes,
                   "world sizes to run instead of the default ones (cluster-scale, overhead)");
    app.add_option(
           "--rounds", rounds,
           "times each size is run over, lpss-sim and every cluster in turn (cluster-scale; default 3, "
           "1 with --quick)")
        ->check(CLI::Range(1u, 100u));
    app.add_flag("--keep", keep,
                 "keep the scenes and logs of the runs (cluster-scale), to rerun one by hand");
    app.add_flag("--as-twin", as_twin, "internal: run the double configurations and print CSV");
    app.add_flag("--security", security,
                 "cluster: each run with and without DDS Security, side by side (into cluster-security/)");

    struct Sub {
        const char* name;
        const char* help;
        void (*run)(const Context&);
    };
    const Sub subs[] = {
        {"precision", "two spheres at distances 0..1e15 (paper Figure 5)", run_precision},
        {"pareto", "error against milliseconds per frame for several scenes and distances", run_pareto},
        {"instances", "128 bodies over 1..128 sectors: time, memory, creation (paper Figure 6)",
         run_instances},
        {"overhead", "sectorization and cloning time against body count (paper Figure 7)", run_overhead},
        {"stacks", "box stacks of 10 and 30 at 0, 2^24, 2^40, 1e15 (paper Figure 8)", run_stacks},
        {"scaling", "frame time against body count and threads", run_scaling},
        {"stability", "the stability suite's numbers", run_stability},
        {"accuracy", "analytic cases against substeps and solver iterations, with cost", run_accuracy},
        {"cluster", "lpss-cluster with 2 workers against one process", run_cluster},
        {"cluster-scale",
         "a world at rest from 10^4 to 10^6 bodies: lpss-cluster (1, 2, 4 workers) and lpss-sim",
         run_cluster_scale},
        {"late-join", "clients joining a running cluster: time to match and to the first frame",
         run_late_join},
        {"dis", "lpss-dis's Entity State PDUs against one per body per frame, at rest and moving", run_dis},
    };
    std::vector<std::pair<CLI::App*, const Sub*>> commands;
    for (const Sub& sub : subs)
        commands.emplace_back(app.add_subcommand(sub.name, sub.help), &sub);
    CLI11_PARSE(app, argc, argv);

    Context context;
    context.quick = quick;
    context.as_twin = as_twin;
    context.keep = keep;
    context.security = security;
    context.sizes = sizes;
    context.rounds = rounds;
    context.twin =
        twin.empty() ? (std::filesystem::path(argv[0]).parent_path() / "lpss-bench-f64").string() : twin;
    context.command = "lpss-bench";
    for (int n = 1; n < argc; ++n)
        context.command += std::string(" ") + argv[n];
    try {
        for (const auto& [command, sub] : commands) {
            if (!command->parsed()) continue;
            context.out = std::filesystem::path(out) /
                          (security && std::string(sub->name) == "cluster" ? "cluster-security" : sub->name);
            sub->run(context);
        }
    } catch (const std::exception& e) {
        std::cerr << "lpss-bench: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
