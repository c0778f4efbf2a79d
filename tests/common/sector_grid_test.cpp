#include "lpss/common/sector_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>

namespace lpss {
namespace {

TEST(SectorGrid, OriginAndCentredCells) {
    SectorGrid grid(128.0);
    auto p = grid.from_global({0, 0, 0}).value();
    EXPECT_EQ(p.sector, (SectorKey{0, 0, 0}));
    EXPECT_EQ(p.local, Eigen::Vector3d::Zero());
    p = grid.from_global({63.9, -63.9, 100}).value();
    EXPECT_EQ(p.sector, (SectorKey{0, 0, 1}));
    EXPECT_DOUBLE_EQ(p.local.x(), 63.9);
    EXPECT_DOUBLE_EQ(p.local.y(), -63.9);
    EXPECT_DOUBLE_EQ(p.local.z(), 100 - 128);
}

TEST(SectorGrid, BordersAreHalfOpen) {
    SectorGrid grid(128.0);
    // [-L/2, L/2): the lower border belongs to the cell, the upper border to the next one.
    auto p = grid.from_global({64, -64, 192}).value();
    EXPECT_EQ(p.sector, (SectorKey{1, 0, 2}));
    EXPECT_EQ(p.local, Eigen::Vector3d(-64, -64, -64));
    p = grid.from_global({std::nextafter(64.0, 0.0), std::nextafter(-64.0, -100.0), -192}).value();
    EXPECT_EQ(p.sector, (SectorKey{0, -1, -1}));
    EXPECT_EQ(p.local.x(), std::nextafter(64.0, 0.0));
    EXPECT_EQ(p.local.y(), std::nextafter(-64.0, -100.0) + 128.0);
    EXPECT_EQ(p.local.z(), -64.0);
}

TEST(SectorGrid, NegativeCoordinates) {
    SectorGrid grid(100.0);
    auto p = grid.from_global({-50.0, -150.0, -1234.5}).value();
    EXPECT_EQ(p.sector, (SectorKey{0, -1, -12}));
    EXPECT_DOUBLE_EQ(p.local.x(), -50.0);
    EXPECT_DOUBLE_EQ(p.local.y(), -50.0);
    EXPECT_DOUBLE_EQ(p.local.z(), -34.5);
}

TEST(SectorGrid, CornerWhereEightSectorsMeet) {
    SectorGrid grid(128.0);
    const double e = 1e-9;
    int seen = 0;
    for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) {
            for (int k = 0; k < 2; ++k) {
                Eigen::Vector3d x(64 + (i ? e : -e), 64 + (j ? e : -e), 64 + (k ? e : -e));
                auto p = grid.from_global(x).value();
                EXPECT_EQ(p.sector, (SectorKey{i, j, k}));
                EXPECT_LE(p.local.cwiseAbs().maxCoeff(), 64.0);
                EXPECT_EQ(grid.to_global(p), x) << "round trip at the corner";
                ++seen;
            }
        }
    }
    EXPECT_EQ(seen, 8);
}

TEST(SectorGrid, RoundTripIsExactWhereDoublesCanHoldThePosition) {
    for (double size : {1.0, 64.0, 128.0, 1000.0, 1024.0, 0.1}) {
        SectorGrid grid(size);
        for (double x :
             {0.0, 1e-7, -3.75, 1e3, -1e6, 16777216.0, 1e9 + 0.25, -1e12 - 0.5, 1e15, 123456789.123}) {
            // Where x / L passes 2^52 a double cannot tell one sector from the next: beyond the reach of
            // global positions (scenes give sector positions there).
            if (std::fabs(x) / size > std::ldexp(1.0, 52)) continue;
            auto p = grid.from_global({x, -x, x * 0.5}).value();
            EXPECT_EQ(grid.to_global(p), Eigen::Vector3d(x, -x, x * 0.5)) << "size " << size << " x " << x;
            EXPECT_LT(p.local.x(), size / 2);
            EXPECT_GE(p.local.x(), -size / 2);
        }
    }
}

TEST(SectorGrid, IndexComputedDespiteRoundingOfTheDivision) {
    // x / L + 1/2 rounds up to an integer for the largest double below the border: the index must
    // still be the lower one, with the local offset just below L/2.
    SectorGrid grid(0.1);
    double x = std::nextafter(0.05, 0.0);
    auto p = grid.from_global({x, 0, 0}).value();
    EXPECT_EQ(p.sector.i, 0);
    EXPECT_EQ(p.local.x(), x);
    EXPECT_LT(p.local.x(), 0.05);
}

TEST(SectorGrid, IndicesNear2Pow62) {
    SectorGrid grid(128.0);
    const std::int64_t big = kMaxSectorIndex - 3;
    SectorPosition p{{big, -big, big}, {63.5, -64.0, 10.25}};
    auto c = grid.canonical(p).value();
    EXPECT_EQ(c.sector, p.sector);
    EXPECT_EQ(c.local, p.local);

    // Offsets outside the cell move to the neighbour by exact key arithmetic.
    auto moved = grid.canonical({{big, -big, big}, {64.0 + 128.0 * 2, -64.5, 0}}).value();
    EXPECT_EQ(moved.sector, (SectorKey{big + 3, -big - 1, big}));
    EXPECT_EQ(moved.local, Eigen::Vector3d(-64.0, 63.5, 0));

    // Past the edge of the grid: refused.
    EXPECT_FALSE(grid.canonical({{kMaxSectorIndex, 0, 0}, {64.0, 0, 0}}).ok());
    EXPECT_FALSE(grid.canonical({{kMaxSectorIndex + 1, 0, 0}, {0, 0, 0}}).ok());

    // Differences between keys at opposite ends of the grid do not overflow.
    Eigen::Vector3d d = grid.centre_offset({-kMaxSectorIndex, 0, 0}, {kMaxSectorIndex, 0, 0});
    EXPECT_EQ(d.x(), std::ldexp(1.0, 63) * 128.0);
    // Neighbouring sectors far out are exactly L apart.
    EXPECT_EQ(grid.centre_offset({big, big, big}, {big + 1, big - 1, big}), Eigen::Vector3d(128, -128, 0));
    // A sector position near 2^62 seen from its neighbour's frame.
    EXPECT_EQ(grid.offset_in({{big + 1, big, big}, {-60, 1, 2}}, {big, big, big}), Eigen::Vector3d(68, 1, 2));
}

TEST(SectorGrid, GlobalPositionsBeyondTheGridAreRefused) {
    SectorGrid grid(1.0);
    EXPECT_TRUE(grid.from_global({4e18, 0, 0}).ok());
    auto far = grid.from_global({1e19, 0, 0});
    ASSERT_FALSE(far.ok());
    EXPECT_NE(far.error().message.find("2^62"), std::string::npos);
}

TEST(SectorGrid, NonFiniteIsRefusedWithANamedError) {
    SectorGrid grid(128.0);
    for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
        auto p = grid.from_global({1, bad, 2});
        ASSERT_FALSE(p.ok());
        EXPECT_NE(p.error().message.find("not finite"), std::string::npos);
        EXPECT_FALSE(grid.canonical({{0, 0, 0}, {bad, 0, 0}}).ok());
    }
}

TEST(PrecisionBound, LargestSectorForARadius) {
    EXPECT_NEAR(max_sector_size(1000.0), 2000.0 / (3.0 * std::sqrt(3.0)), 1e-12);
    EXPECT_TRUE(check_sector_size(384.0, 1000.0).ok());
    Status refused = check_sector_size(400.0, 1000.0);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("384.9"), std::string::npos) << refused.error().message;
}

}  // namespace
}  // namespace lpss

#include <algorithm>
#include <set>

#include "lpss/common/assignment.hpp"

namespace lpss {
namespace {

TEST(Assignment, EverySectorHasOneOwnerAndRangesAreBalanced) {
    std::vector<std::pair<SectorKey, double>> loads;
    for (int i = -20; i < 20; ++i)
        loads.push_back({{i, 0, 3}, 10.0});
    SectorAssignment a = SectorAssignment::balanced(loads, {1, 2, 3}, 4);
    std::map<std::uint32_t, double> load;
    for (const auto& [sector, l] : loads)
        load[a.owner_of(sector)] += l;
    ASSERT_EQ(load.size(), 3u);
    for (const auto& [worker, l] : load)
        EXPECT_NEAR(l, 400.0 / 3.0, 45.0) << "worker " << worker;
    // Sectors nobody uses, anywhere on the grid, still have an owner among the workers.
    for (SectorKey s : {SectorKey{kMaxSectorIndex, -kMaxSectorIndex, 0}, SectorKey{-5, 99, 1000000}}) {
        std::uint32_t w = a.owner_of(s);
        EXPECT_TRUE(w >= 1 && w <= 3);
    }
    // Neighbouring sectors of one block share an owner.
    EXPECT_EQ(a.owner_of({4, 1, 2}), a.owner_of({7, 3, 3}));
    EXPECT_EQ(block_of({-1, -4, -5}, 4), (SectorKey{-1, -1, -2}));
}

TEST(Assignment, AWorkerTakenOutLeavesItsRangeToItsNeighboursAndNoOtherSectorMoves) {
    // The cluster's answer to a worker that is gone: the others cannot hand sectors over in time, so only
    // the gone worker's sectors may change owner, and they go to the workers beside it on the curve.
    std::vector<std::pair<SectorKey, double>> loads;
    for (int i = -20; i < 20; ++i)
        for (int k = 0; k < 4; ++k)
            loads.push_back({{i, 0, k}, 1.0 + (i + 20) % 3});
    const SectorAssignment a = SectorAssignment::balanced(loads, {1, 2, 3, 4}, 2);
    std::vector<SectorKey> probes;
    for (const auto& [sector, l] : loads)
        probes.push_back(sector);
    for (SectorKey s : {SectorKey{kMaxSectorIndex, -kMaxSectorIndex, 0}, SectorKey{-kMaxSectorIndex, 0, 0},
                        SectorKey{-5, 99, 1000000}, SectorKey{0, 0, 0}})
        probes.push_back(s);
    for (std::uint32_t gone : {1u, 2u, 3u, 4u}) {
        const SectorAssignment b = a.without(gone, loads);
        ASSERT_EQ(b.workers.size(), 3u);
        EXPECT_EQ(std::count(b.workers.begin(), b.workers.end(), gone), 0);
        const std::size_t n =
            static_cast<std::size_t>(std::find(a.workers.begin(), a.workers.end(), gone) - a.workers.begin());
        std::set<std::uint32_t> heirs;
        double before = 0.0, after = 0.0;  // the gone worker's load taken by the one before and the one after
        for (const SectorKey& s : probes) {
            const std::uint32_t was = a.owner_of(s), now = b.owner_of(s);
            if (was != gone) {
                EXPECT_EQ(now, was) << "a sector of worker " << was << " moved when worker " << gone
                                    << " went";
                continue;
            }
            heirs.insert(now);
            for (const auto& [sector, l] : loads) {
                if (sector == s) (n > 0 && now == a.workers[n - 1] ? before : after) += l;
            }
        }
        std::set<std::uint32_t> neighbours;
        if (n > 0) neighbours.insert(a.workers[n - 1]);
        if (n + 1 < a.workers.size()) neighbours.insert(a.workers[n + 1]);
        EXPECT_EQ(heirs, neighbours) << "worker " << gone;
        if (neighbours.size() == 2) {
            EXPECT_NEAR(before, after, 0.25 * (before + after)) << "worker " << gone;
        }
    }
    // The last worker of the cluster, or one it does not have: nothing changes.
    const SectorAssignment one = SectorAssignment::balanced(loads, {7}, 2);
    EXPECT_EQ(one.without(7, loads).workers, std::vector<std::uint32_t>{7});
    EXPECT_EQ(a.without(9, loads).workers, a.workers);
}

TEST(Assignment, MortonOrderFollowsSpace) {
    EXPECT_LT(morton_code({0, 0, 0}), morton_code({1, 0, 0}));
    EXPECT_LT(morton_code({-1, 0, 0}), morton_code({0, 0, 0}));
    EXPECT_LT(morton_code({1, 1, 1}), morton_code({2, 0, 0}));
}

}  // namespace
}  // namespace lpss
