// stability: the numbers of the stability suite (tests/support/stability_cases.cpp), every case at the
// origin and far from it, beside the limit each must keep.
#include <fmt/format.h>

#include "subcommands.hpp"
#if LPSS_BENCH_DRIVER
#include "stability_cases.hpp"
#endif

namespace lpss::bench {

void run_stability(const Context& context) {
#if LPSS_BENCH_DRIVER
    Table table({"case", "placement", "metric", "value", "limit", "kind", "ok", "ms_per_frame", "basis"});
    for (const stability::Case& c : stability::all_cases()) {
        for (const stability::Placement& where : stability::placements()) {
            progress("stability: " + c.name + " at " + where.name);
            const stability::Outcome o = c.run(where);
            if (!o.health.empty()) {
                table.add(
                    {c.name, o.placement, "health", "0", "0", "==", "0", num(o.ms_per_frame, 4), o.health});
            }
            for (const stability::Metric& m : o.metrics) {
                table.add({c.name, o.placement, m.name, num(m.value, 4), num(m.limit, 4),
                           m.at_least ? ">=" : "<=", m.ok() ? "1" : "0", num(o.ms_per_frame, 4), m.basis});
            }
        }
    }
    std::string md =
        "Every case of the stability suite, at the origin and at 1e12 (sector index 2^62 for the grid-edge "
        "case). ok: the value keeps its limit (the tests assert the same). ms_per_frame: the engine's "
        "own clock over the case's main run, for scale only.\n\n" +
        table.markdown({"case", "placement", "metric", "value", "kind", "limit", "ok", "ms_per_frame"});
    std::string plot =
        R"(set title 'Stability suite: each metric as a fraction of its limit (<= limits: below 1 passes; >= limits shown inverted; 1e-4: zero, or a limit of 0 kept)'
set termoption noenhanced
set style data histogram
set style fill solid 0.6
set logscale y
set yrange [1e-4:10]
set ylabel 'value / limit'
set xtics rotate by 60 right font ',7'
set arrow from graph 0, first 1 to graph 1, first 1 nohead lc rgb 'red'
unset key
r(v,l,k) = strcol(6) eq '<=' ? (l == 0 ? (v == 0 ? 1e-4 : 10) : (v/l > 1e-4 ? v/l : 1e-4)) : (l == 0 ? (v >= 0 ? 1e-4 : 10) : (v > 0 ? (l/v > 1e-4 ? l/v : 1e-4) : 10))
plot '$CSV' every ::1 using (r($4,$5,0)):xtic(sprintf('%s %s', strcol(1), strcol(2)[1:3]))
)";
    publish(context, "stability", table, "stability: the hard cases", md, plot);
#else
    (void)context;
    throw std::runtime_error("stability runs in the float build only");
#endif
}

}  // namespace lpss::bench
