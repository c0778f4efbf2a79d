// The stability suite: hard cases for a physics engine (stiff stacks, fast bodies, borders, extremes,
// conservation), each run at the origin and far from it. Shared by the tests (which assert the limits)
// and lpss-bench `stability` (which tabulates the numbers).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "lpss/engine/world.hpp"
#include "scenes.hpp"

namespace lpss::stability {

/// One measured number and the limit it must keep, with the reason for that limit.
struct Metric {
    std::string name;
    double value = 0.0;
    double limit = 0.0;
    bool at_least = false;  ///< pass when value >= limit; otherwise when value <= limit
    std::string basis;      ///< where the limit comes from

    bool ok() const { return at_least ? value >= limit : value <= limit; }  // NaN fails either way
};

struct Outcome {
    std::string case_name;
    std::string placement;
    std::vector<Metric> metrics;
    /// Empty when every run kept every body finite, owned by a live sector, none lost; else what broke.
    std::string health;
    double ms_per_frame = 0.0;  ///< mean engine time per frame of the case's main run (not a benchmark)

    bool ok() const;
};

/// Where a case runs: "origin" or "far" (at least 1e12 from the origin, not on a sector multiple).
struct Placement {
    std::string name;
    scenes::Centre centre;
};
std::vector<Placement> placements();

struct Case {
    std::string name;
    std::string description;
    std::function<Outcome(const Placement&)> run;
};

/// Every case of the suite, in a stable order.
std::vector<Case> all_cases();

}  // namespace lpss::stability
