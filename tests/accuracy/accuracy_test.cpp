// Accuracy: the engine against analytic truth, not against Bullet's own output. Every case of
// tests/support/accuracy_cases.cpp runs with the engine's defaults at the origin and 10^12 units out, and
// keeps its two-sided limits in both places; the far run also matches the origin's (within each
// quantity's stated margin). lpss-bench accuracy sweeps the same cases against substeps and solver
// iterations.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdio>

#include "accuracy_cases.hpp"

namespace lpss::accuracy {
namespace {

class Accuracy : public ::testing::TestWithParam<std::size_t> {};

TEST_P(Accuracy, KeepsItsAnalyticLimitsAtTheOriginAndFarAway) {
    const Case c = all_cases()[GetParam()];
    std::vector<std::vector<Measure>> runs;
    for (const Placement& where : placements()) {
        runs.push_back(c.run(where.centre, Knobs{}));
        for (const Measure& m : runs.back()) {
            std::printf("%s at %s: %s = %.6g (analytic %.6g, limit +-%.3g)\n", c.name.c_str(),
                        where.name.c_str(), m.quantity.c_str(), m.measured, m.analytic, m.limit);
            EXPECT_TRUE(m.ok()) << c.name << " at " << where.name << ": " << m.quantity << " = " << m.measured
                                << ", analytic " << m.analytic << ", limit +-" << m.limit << " (" << m.basis
                                << ")";
        }
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    for (std::size_t n = 0; n < runs[0].size(); ++n) {
        EXPECT_NEAR(runs[1][n].measured, runs[0][n].measured, runs[0][n].same_far)
            << c.name << ": " << runs[0][n].quantity << " far as at the origin";
    }
}

std::string case_name(const ::testing::TestParamInfo<std::size_t>& info) {
    std::string name = all_cases()[info.param].name;
    for (char& ch : name) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    }
    return name;
}

INSTANTIATE_TEST_SUITE_P(Cases, Accuracy, ::testing::Range<std::size_t>(0, all_cases().size()), case_name);

}  // namespace
}  // namespace lpss::accuracy
