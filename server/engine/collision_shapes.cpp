#include "collision_shapes.hpp"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionShapes/btStaticPlaneShape.h>

#include <algorithm>

#include "bullet_convert.hpp"

namespace lpss::engine {

std::unique_ptr<btCollisionShape> make_collision_shape(const Shape& shape) {
    struct Visitor {
        std::unique_ptr<btCollisionShape> operator()(const Sphere& s) const {
            return std::make_unique<btSphereShape>(static_cast<btScalar>(s.radius));
        }
        std::unique_ptr<btCollisionShape> operator()(const Box& b) const {
            return std::make_unique<btBoxShape>(to_bt(b.half_extents));
        }
        std::unique_ptr<btCollisionShape> operator()(const Capsule& c) const {
            return std::make_unique<btCapsuleShape>(static_cast<btScalar>(c.radius),
                                                    static_cast<btScalar>(c.height));
        }
        std::unique_ptr<btCollisionShape> operator()(const ConvexHull& h) const {
            auto hull = std::make_unique<btConvexHullShape>();
            for (const Eigen::Vector3d& p : h.points)
                hull->addPoint(to_bt(p), false);
            hull->recalcLocalAabb();
            hull->optimizeConvexHull();
            return hull;
        }
        std::unique_ptr<btCollisionShape> operator()(const Plane& p) const {
            return std::make_unique<btStaticPlaneShape>(to_bt(p.normal), btScalar(0));
        }
    };
    return std::visit(Visitor{}, shape);
}

double inner_radius(const Shape& shape) {
    struct Visitor {
        double operator()(const Sphere& s) const { return s.radius; }
        double operator()(const Box& b) const { return b.half_extents.minCoeff(); }
        double operator()(const Capsule& c) const { return c.radius; }
        double operator()(const ConvexHull& h) const { return 0.25 * bounding_radius(h); }
        double operator()(const Plane&) const { return 0.0; }
    };
    return std::visit(Visitor{}, shape);
}

}  // namespace lpss::engine
