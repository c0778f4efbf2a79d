// When a liveliness lapse DDS reports counts: not before its grace has passed without the writer coming
// back, and a lapse reported right after another (what Fast DDS 2.9's false reports look like) is given
// longer.
#include "lpss_dds/confirmed_lapses.hpp"

#include <gtest/gtest.h>

namespace lpss::dds {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

TEST(ConfirmedLapses, ALapseCountsOnlyOnceItsGraceHasPassedWithoutTheWriterComingBack) {
    ConfirmedLapses<int> lapses(milliseconds(150), milliseconds(450), milliseconds(25));
    const Clock::time_point t0 = Clock::now();
    lapses.reported(1, false, t0);
    lapses.reported(2, false, t0 + milliseconds(30));
    EXPECT_TRUE(lapses.confirmed(t0 + milliseconds(149)).empty());
    lapses.reported(2, true, t0 + milliseconds(90));  // its next beat: a false report
    EXPECT_EQ(lapses.confirmed(t0 + milliseconds(150)), std::vector<int>{1});
    EXPECT_TRUE(lapses.confirmed(t0 + milliseconds(1000)).empty()) << "each counted once, and 2 came back";
}

TEST(ConfirmedLapses, ALapseReportedRightAfterAnotherIsGivenTheLongerGrace) {
    ConfirmedLapses<int> lapses(milliseconds(150), milliseconds(450), milliseconds(25));
    const Clock::time_point t0 = Clock::now();
    lapses.reported(1, false, t0);
    lapses.reported(2, false, t0 + milliseconds(3));
    EXPECT_EQ(lapses.confirmed(t0 + milliseconds(200)), std::vector<int>{1});
    EXPECT_TRUE(lapses.confirmed(t0 + milliseconds(452)).empty());
    EXPECT_EQ(lapses.confirmed(t0 + milliseconds(453)), std::vector<int>{2})
        << "a real second death is found";
    lapses.reported(3, false, t0 + milliseconds(2000));
    lapses.forget(3);
    EXPECT_TRUE(lapses.confirmed(t0 + milliseconds(3000)).empty()) << "a forgotten writer never counts";
}

TEST(ConfirmedLapses, DataWrittenAfterTheReportShowsTheWriterAlive) {
    ConfirmedLapses<int> lapses(milliseconds(150), milliseconds(450), milliseconds(25));
    const Clock::time_point t0 = Clock::now();
    const std::int64_t before = wall_clock_ns() - 1'000'000;
    lapses.reported(1, false, t0);
    lapses.reported(2, false, t0 + milliseconds(100));
    lapses.heard(1, before);  // written before the lapse: says nothing
    lapses.heard(2, wall_clock_ns() + 1'000'000);
    EXPECT_EQ(lapses.confirmed(t0 + milliseconds(1000)), std::vector<int>{1});
}

}  // namespace
}  // namespace lpss::dds
