// The lpss-bench sub-commands. Each runs its configurations (the double ones in the float64 twin),
// then publishes <name>.csv, <name>.md and <name>.png into its output folder.
#pragma once

#include "bench_support.hpp"

namespace lpss::bench {

void run_precision(const Context& context);
void run_pareto(const Context& context);
void run_instances(const Context& context);
void run_overhead(const Context& context);
void run_stacks(const Context& context);
void run_scaling(const Context& context);
void run_stability(const Context& context);
void run_accuracy(const Context& context);
void run_cluster(const Context& context);
void run_cluster_scale(const Context& context);
void run_late_join(const Context& context);
void run_dis(const Context& context);

}  // namespace lpss::bench
