// A sector's bound on its fat boxes' overhangs: never below any overhang counted, at most one bucket above
// the largest, and falling when the bodies that raised it go.
#include <gtest/gtest.h>

#include <random>

#include "overhang_bound.hpp"

namespace lpss::engine {
namespace {

TEST(OverhangScale, EveryOverhangFallsInTheLowestBucketThatHoldsIt) {
    const OverhangScale scale(2.0);  // sectors of 8
    std::mt19937_64 random(3);
    std::uniform_real_distribution<double> exponent(-12.0, 2.0);
    for (int n = 0; n < 100000; ++n) {
        const double overhang = std::exp2(exponent(random));
        const std::uint8_t bucket = scale.bucket_of(overhang);
        const std::uint8_t hinted = scale.bucket_of(overhang, static_cast<std::uint8_t>(n % 64));
        ASSERT_EQ(bucket, hinted) << overhang << " with a stale hint";
        if (overhang > 2.0) {
            ASSERT_EQ(bucket, OverhangScale::kBuckets - 1) << overhang;
            continue;
        }
        ASSERT_LT(bucket, OverhangScale::kBuckets - 1) << overhang;
        ASSERT_GE(scale.top(bucket), overhang);
        if (bucket > 0) {
            ASSERT_LT(scale.top(bucket - 1u), overhang);
            ASSERT_LE(scale.top(bucket), overhang * 1.0906) << "a bucket spans an eighth of a doubling";
        }
    }
}

TEST(OverhangBound, FollowsTheBodiesCountedNow) {
    const OverhangScale scale(2.0);
    OverhangBound bound;
    EXPECT_EQ(bound.bound(scale), 0.0);
    const std::uint8_t small = scale.bucket_of(0.6), large = scale.bucket_of(1.7);
    const std::uint8_t beyond = scale.bucket_of(9.0);
    bound.add(small, 0.6);
    bound.add(small, 0.6);
    EXPECT_GE(bound.bound(scale), 0.6);
    EXPECT_LT(bound.bound(scale), 0.66);
    bound.add(large, 1.7);
    EXPECT_GE(bound.bound(scale), 1.7);
    bound.add(beyond, 9.0);
    bound.add_beyond(12.0);
    EXPECT_EQ(bound.bound(scale), 12.0) << "the unbounded bucket keeps its largest";
    bound.remove(beyond);
    EXPECT_GE(bound.bound(scale), 1.7);
    EXPECT_LT(bound.bound(scale), 1.86) << "gone with the body that raised it";
    bound.remove(large);
    bound.remove(small);
    EXPECT_GE(bound.bound(scale), 0.6) << "one body of that bucket is still counted";
    EXPECT_LT(bound.bound(scale), 0.66);
    bound.remove(small);
    EXPECT_EQ(bound.bound(scale), 0.0);
}

}  // namespace
}  // namespace lpss::engine
