// The float64 build of the engine: plain double Bullet (monolithic) holds the experiments far out, as
// the baselines say, so lpss-sim-f64 --monolithic is a fair comparison.
#include <gtest/gtest.h>

#include <cstring>

#include "engine_test_support.hpp"

namespace lpss {
namespace {

using testing::make_world;
using testing::relative_positions;
using testing::run;
using testing::summed_error;

TEST(DoubleEngine, IsBuiltAgainstDoubleBullet) { EXPECT_STREQ(World::physics_precision(), "double"); }

TEST(DoubleEngine, MonolithicSpheresCollideAt1e9) {
    EngineOptions monolithic;
    monolithic.monolithic = true;
    const Eigen::Vector3d far(1e9, 0, 0);
    World origin = make_world(scenes::sphere_pair(Eigen::Vector3d::Zero().eval(), 128.0), monolithic);
    World moved = make_world(scenes::sphere_pair(far, 128.0), monolithic);
    run(origin, 180);
    run(moved, 180);
    EXPECT_LT(moved.body(1)->linear_velocity.x(), 0.0);
    EXPECT_LT(summed_error(relative_positions(moved, far),
                           relative_positions(origin, Eigen::Vector3d::Zero().eval())),
              1e-3);
}

TEST(DoubleEngine, MonolithicStackStandsAt2Pow24) {
    EngineOptions monolithic;
    monolithic.monolithic = true;
    const Eigen::Vector3d far = Eigen::Vector3d::Constant(16777216.0);
    World world = make_world(scenes::box_stack(far, 10, 1000.0), monolithic);
    run(world, 600);
    Eigen::Vector3d top = scenes::relative_position(world.grid(), *world.body(10), far);
    EXPECT_GT(top.y(), 9.0);
}

TEST(DoubleEngine, SectorizedDoubleMatchesTheOriginAt1e13Sectors) {
    // A sector position: a global double at this distance would round the start positions by 1e-3.
    const SectorPosition far{{10'000'000'000'000, 0, 0}, {333.25, 0, 0}};
    World origin = make_world(scenes::sphere_pair(Eigen::Vector3d::Zero().eval(), 1024.0));
    World moved = make_world(scenes::sphere_pair(far, 1024.0));
    run(origin, 180);
    run(moved, 180);
    EXPECT_LT(summed_error(relative_positions(moved, far),
                           relative_positions(origin, Eigen::Vector3d::Zero().eval())),
              1e-6);
}

}  // namespace
}  // namespace lpss
