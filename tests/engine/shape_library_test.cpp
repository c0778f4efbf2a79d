// The engine's shape library: one Bullet shape per distinct shape value, living while a body holds it.
#include <gtest/gtest.h>

#include "shape_library.hpp"

namespace lpss::engine {
namespace {

ConvexHull pyramid(double apex) {
    ConvexHull hull;
    for (double x : {-0.5, 0.5})
        for (double z : {-0.5, 0.5})
            hull.points.push_back(Eigen::Vector3d(x, -0.2, z));
    hull.points.push_back(Eigen::Vector3d(0, apex, 0));
    return hull;
}

TEST(ShapeLibrary, BodiesOfTheSameShapeValueShareOneBulletShape) {
    ShapeLibrary library;
    const auto box = library.get(Box{Eigen::Vector3d(0.8, 0.3, 0.4)});
    EXPECT_EQ(library.get(Box{Eigen::Vector3d(0.8, 0.3, 0.4)}), box);
    EXPECT_EQ(library.get(pyramid(0.6)), library.get(pyramid(0.6)));
    EXPECT_EQ(library.get(Sphere{0.5}), library.get(Sphere{0.5}));
    EXPECT_EQ(library.get(Capsule{0.4, 0.6}), library.get(Capsule{0.4, 0.6}));
}

TEST(ShapeLibrary, DifferentValuesGetDifferentShapes) {
    ShapeLibrary library;
    const auto a = library.get(Box{Eigen::Vector3d(0.8, 0.3, 0.4)});
    EXPECT_NE(library.get(Box{Eigen::Vector3d(0.8, 0.3, 0.41)}), a);
    EXPECT_NE(library.get(pyramid(0.6)), library.get(pyramid(0.7)));
    EXPECT_NE(library.get(Sphere{0.5}), library.get(Sphere{0.25}));
    // Same numbers, other kinds.
    EXPECT_NE(library.get(Capsule{0.5, 1.0}), library.get(Sphere{0.5}));
    const auto cube = library.get(Box{Eigen::Vector3d::Constant(0.5)});
    EXPECT_EQ(cube->getShapeType(), BOX_SHAPE_PROXYTYPE);
    EXPECT_EQ(library.get(Sphere{0.5})->getShapeType(), SPHERE_SHAPE_PROXYTYPE);
}

TEST(ShapeLibrary, AShapeGoesWithItsLastHolderAndIsMadeAgainWhenNeeded) {
    ShapeLibrary library;
    std::weak_ptr<btCollisionShape> first;
    {
        auto held = library.get(pyramid(0.6));
        auto also = library.get(pyramid(0.6));
        first = held;
        EXPECT_EQ(library.live(), 1u);
    }
    EXPECT_TRUE(first.expired());
    EXPECT_EQ(library.live(), 0u);
    const auto again = library.get(pyramid(0.6));
    EXPECT_EQ(library.live(), 1u);
    EXPECT_EQ(again->getShapeType(), CONVEX_HULL_SHAPE_PROXYTYPE);
}

TEST(ShapeLibrary, ManyShortLivedValuesDoNotPileUp) {
    ShapeLibrary library;
    const auto kept = library.get(Sphere{1.0});
    for (int n = 0; n < 10000; ++n)
        (void)library.get(Sphere{2.0 + n});  // each released at once
    EXPECT_EQ(library.get(Sphere{1.0}), kept);
    EXPECT_EQ(library.live(), 1u);
    EXPECT_LT(library.entries(), 200u) << "entries of gone shapes are swept";
}

}  // namespace
}  // namespace lpss::engine
