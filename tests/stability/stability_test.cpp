// The stability suite as tests: every case at the origin and far from it keeps its limits, with no
// NaN, no lost body and no body left in a dead sector. The limits and their reasons are written beside
// each case in tests/support/stability_cases.cpp; lpss-bench stability prints the numbers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "stability_cases.hpp"

namespace lpss::stability {
namespace {

class Stability : public ::testing::TestWithParam<std::pair<std::size_t, std::size_t>> {};

TEST_P(Stability, KeepsItsLimits) {
    const Case c = all_cases()[GetParam().first];
    const Placement where = placements()[GetParam().second];
    Outcome o = c.run(where);
    EXPECT_TRUE(o.health.empty()) << o.health;
    for (const Metric& m : o.metrics) {
        EXPECT_TRUE(m.ok()) << c.name << " at " << o.placement << ": " << m.name << " = " << m.value
                            << (m.at_least ? ", must be >= " : ", must be <= ") << m.limit << " (" << m.basis
                            << ")";
        RecordProperty(m.name, std::to_string(m.value));
    }
}

class FarAsAtTheOrigin : public ::testing::TestWithParam<std::size_t> {};

TEST_P(FarAsAtTheOrigin, KeepsTheOriginsFigures) {
    // The limits above are absolute, set with room for Bullet's own behaviour; "far behaves as at the
    // origin" is the point of lpss. So each far figure is held to the origin's: at most half again the
    // origin's value plus 5% of the limit (for figures near zero) for a "<=" metric, at least two thirds of
    // it less 5% of the limit for a ">=" one.
    const Case c = all_cases()[GetParam()];
    const Outcome origin = c.run(placements()[0]);
    const Outcome far = c.run(placements()[1]);
    // A far run may measure more (its difference from the origin's run): the metrics both have are compared.
    std::size_t compared = 0;
    for (const Metric& o : origin.metrics) {
        auto same = std::find_if(far.metrics.begin(), far.metrics.end(),
                                 [&](const Metric& m) { return m.name == o.name; });
        ASSERT_NE(same, far.metrics.end()) << c.name << ": " << o.name << " not measured far out";
        const Metric& f = *same;
        ++compared;
        const double slack = 0.05 * std::fabs(o.limit);
        if (o.at_least) {
            EXPECT_GE(f.value, o.value / 1.5 - slack)
                << c.name << ": " << o.name << " far " << f.value << ", at the origin " << o.value;
        } else {
            EXPECT_LE(f.value, 1.5 * o.value + slack)
                << c.name << ": " << o.name << " far " << f.value << ", at the origin " << o.value;
        }
    }
}

std::vector<std::pair<std::size_t, std::size_t>> every_case_and_placement() {
    std::vector<std::pair<std::size_t, std::size_t>> out;
    for (std::size_t c = 0; c < all_cases().size(); ++c) {
        for (std::size_t p = 0; p < placements().size(); ++p)
            out.emplace_back(c, p);
    }
    return out;
}

/// A test name from a case's name (gtest allows letters, digits and underscores).
std::string test_name_of(std::string name) {
    for (char& ch : name) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    }
    return name;
}

std::string test_name(const ::testing::TestParamInfo<std::pair<std::size_t, std::size_t>>& info) {
    return test_name_of(all_cases()[info.param.first].name + "_" + placements()[info.param.second].name);
}

INSTANTIATE_TEST_SUITE_P(Suite, Stability, ::testing::ValuesIn(every_case_and_placement()), test_name);
INSTANTIATE_TEST_SUITE_P(Suite, FarAsAtTheOrigin, ::testing::Range<std::size_t>(0, all_cases().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& info) {
                             return test_name_of(all_cases()[info.param].name);
                         });

}  // namespace
}  // namespace lpss::stability
