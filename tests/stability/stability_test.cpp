// The stability suite as tests: every case at the origin and far from it keeps its limits, with no
// NaN, no lost body and no body left in a dead sector. The limits and their reasons are written beside
// each case in tests/support/stability_cases.cpp; lpss-bench stability prints the numbers.
#include <gtest/gtest.h>

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

std::vector<std::pair<std::size_t, std::size_t>> every_case_and_placement() {
    std::vector<std::pair<std::size_t, std::size_t>> out;
    for (std::size_t c = 0; c < all_cases().size(); ++c) {
        for (std::size_t p = 0; p < placements().size(); ++p)
            out.emplace_back(c, p);
    }
    return out;
}

std::string test_name(const ::testing::TestParamInfo<std::pair<std::size_t, std::size_t>>& info) {
    std::string name = all_cases()[info.param.first].name + "_" + placements()[info.param.second].name;
    for (char& ch : name) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    }
    return name;
}

INSTANTIATE_TEST_SUITE_P(Suite, Stability, ::testing::ValuesIn(every_case_and_placement()), test_name);

}  // namespace
}  // namespace lpss::stability
