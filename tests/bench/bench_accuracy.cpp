// accuracy: the analytic cases (tests/support/accuracy_cases.cpp) against the accuracy knobs, substeps
// and solver iterations, each setting's worst error against its cost, with the cheapest setting that
// keeps every limit marked.
#include <fmt/format.h>

#include <limits>

#include "subcommands.hpp"
#if LPSS_BENCH_DRIVER
#include "accuracy_cases.hpp"
#endif

namespace lpss::bench {

void run_accuracy(const Context& context) {
#if LPSS_BENCH_DRIVER
    struct Setting {
        std::string knob;
        int value;
        accuracy::Knobs knobs;
    };
    std::vector<Setting> settings;
    for (int s : {1, 2, 4, 8, 16})
        settings.push_back({"substeps", s, accuracy::Knobs{s, 10}});
    for (int i : {2, 4, 10, 20, 50})
        settings.push_back({"iterations", i, accuracy::Knobs{1, i}});
    // The defaults with Bullet's own penetration push on bouncing contacts: what lpss's change buys, and
    // what it costs.
    settings.push_back({"bullet-bounces", 1, accuracy::Knobs{1, 10, true}});
    const double min_seconds = context.quick ? 0.02 : 0.2;

    Table table({"case", "knob", "value", "ms_per_frame", "worst_error_over_limit", "worst_quantity",
                 "worst_measured", "analytic", "limit", "keeps_limits", "cheapest"});
    const scenes::Centre origin = Eigen::Vector3d::Zero().eval();
    for (const accuracy::Case& c : accuracy::all_cases()) {
        std::vector<std::vector<std::string>> rows;
        double cheapest_ms = std::numeric_limits<double>::infinity();
        std::size_t cheapest = rows.size();
        for (const Setting& s : settings) {
            progress(fmt::format("accuracy: {}, {} {}", c.name, s.knob, s.value));
            const std::vector<accuracy::Measure> measures = c.run(origin, s.knobs);
            const accuracy::Measure* worst = &measures.front();
            bool keeps = true;
            for (const accuracy::Measure& m : measures) {
                keeps = keeps && m.ok();
                if (!(m.error() / m.limit <= worst->error() / worst->limit)) worst = &m;
            }
            const Scene scene = c.scene(origin, s.knobs);
            EngineOptions options;
            options.bullet_bounces = s.knobs.bullet_bounces;
            const double ms = ms_per_frame_fresh(
                fmt::format("accuracy/{}/{}={}", c.name, s.knob, s.value),
                [&] { return make_world(scene, options); }, c.frames, min_seconds);
            if (keeps && ms < cheapest_ms && !s.knobs.bullet_bounces) {
                cheapest_ms = ms;
                cheapest = rows.size();
            }
            rows.push_back({c.name, s.knob, std::to_string(s.value), num(ms, 4),
                            num(worst->error() / worst->limit, 4), worst->quantity, num(worst->measured, 6),
                            num(worst->analytic, 6), num(worst->limit, 4), keeps ? "1" : "0", "0"});
        }
        if (cheapest < rows.size()) rows[cheapest].back() = "1";
        for (auto& row : rows)
            table.add(std::move(row));
    }

    std::string md =
        "Each case of the accuracy suite (analytic answers: tests/support/accuracy_cases.cpp), at the "
        "origin, with one knob changed from the defaults (1 step a frame at 1/60 s, 10 solver iterations); "
        "bullet-bounces: the defaults with Bullet's own penetration push on bouncing contacts, which lpss "
        "turns off (docs/design.md). "
        "worst_error_over_limit: the case's worst quantity's distance from its analytic value, as a "
        "fraction of the limit the tests hold it to (two-sided; 1 or less keeps it). keeps_limits: every "
        "quantity within its limit. cheapest: the cheapest setting that keeps them all. ms_per_frame: "
        "Google Benchmark, the case's world built and run for its frames (a few bodies: microseconds "
        "a frame).\n\n" +
        table.markdown({"case", "knob", "value", "ms_per_frame", "worst_error_over_limit", "worst_quantity",
                        "worst_measured", "analytic", "keeps_limits", "cheapest"});
    std::string plot =
        "set multiplot layout 2,4 title 'Accuracy against cost: worst error / its limit (below the red "
        "line keeps every limit; ringed: the cheapest setting that does; 1e-3: no error)'\n"
        "set logscale xy\nset xlabel 'ms per frame' font ',9'\nset ylabel 'worst error / limit' font ',9'\n"
        "set xrange [5e-4:2]\nset yrange [5e-4:2e3]\nset format y '10^{%L}'\n"
        "set key top right font ',7' samplen 1 spacing 0.8 width -4\n"
        "set arrow 1 from graph 0, first 1 to graph 1, first 1 nohead lc rgb 'red'\n"
        "v(c,k) = (strcol(1) eq c && strcol(2) eq k) ? ($5 > 1e-3 ? $5 : 1e-3) : 1/0\n"
        "best(c) = (strcol(1) eq c && strcol(11) eq '1') ? ($5 > 1e-3 ? $5 : 1e-3) : 1/0\n";
    for (const accuracy::Case& c : accuracy::all_cases()) {
        plot += fmt::format(
            "set title '{0}' font ',10'\n"
            "plot '$CSV' every ::1 using 4:(v('{0}','substeps')) with linespoints lc 1 pt 7 title 'substeps "
            "1-16', "
            "'' every ::1 using 4:(v('{0}','substeps')):3 with labels offset 0,0.8 font ',7' notitle, "
            "'' every ::1 using 4:(v('{0}','iterations')) with linespoints lc 2 pt 5 title 'iterations "
            "2-50', "
            "'' every ::1 using 4:(v('{0}','iterations')):3 with labels offset 0,-0.8 font ',7' tc lt 2 "
            "notitle, "
            "'' every ::1 using 4:(v('{0}','bullet-bounces')) with points lc 4 pt 9 ps 2 title 'defaults "
            "with Bullet''s bounce push', "
            "'' every ::1 using 4:(best('{0}')) with points lc 7 pt 6 ps 3 lw 2 title 'cheapest keeping "
            "all'\n",
            c.name);
    }
    plot += "unset multiplot\n";
    publish(context, "accuracy", table, "accuracy: analytic cases against the accuracy knobs", md, plot);
#else
    (void)context;
    throw std::runtime_error("accuracy runs in the float build only");
#endif
}

}  // namespace lpss::bench
