// Accuracy: cases with an analytic answer (an elastic collision, bounces, a box sliding to rest, free
// fall, a stack at rest), each measured against that answer with a two-sided limit. Shared by the tests
// (tests/engine/accuracy_test.cpp, which assert the limits at the origin and 10^12 out) and lpss-bench
// `accuracy` (which sweeps the accuracy knobs, substeps and solver iterations, against cost).
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "lpss/engine/world.hpp"
#include "scenes.hpp"

namespace lpss::accuracy {

/// The settings swept against cost; the scene's own otherwise.
struct Knobs {
    int substeps = 0;  ///< 0: the engine's default (enough for steps of at most 1/60 s)
    int solver_iterations = 10;
    bool bullet_bounces = false;  ///< EngineOptions::bullet_bounces: Bullet's own push on bounces, to compare
};

/// One measured quantity against its analytic value.
struct Measure {
    std::string quantity;
    double measured = 0.0;
    double analytic = 0.0;
    double limit = 0.0;      ///< |measured - analytic| allowed, either way
    double same_far = 1e-4;  ///< how far the run 10^12 out may differ from the origin's
    std::string basis;       ///< where the limit comes from

    double error() const { return std::fabs(measured - analytic); }
    bool ok() const { return error() <= limit; }  // NaN fails
};

struct Case {
    std::string name;
    std::string description;
    /// The case's scene placed at `centre` with `knobs` (for timing it alone).
    std::function<Scene(const scenes::Centre& centre, const Knobs& knobs)> scene;
    int frames = 0;  ///< frames the case runs
    /// Runs the case and measures it.
    std::function<std::vector<Measure>(const scenes::Centre& centre, const Knobs& knobs)> run;
};

/// Every case, in a stable order.
std::vector<Case> all_cases();

/// Where the cases run: the origin, and a sector position 10^12 units out (exact, off sector multiples).
struct Placement {
    std::string name;
    scenes::Centre centre;
};
std::vector<Placement> placements();

}  // namespace lpss::accuracy
