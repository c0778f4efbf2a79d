// Bullet collision shapes made from lpss shape values.
#pragma once

#include <BulletCollision/CollisionShapes/btCollisionShape.h>

#include <memory>

#include "lpss/common/shape.hpp"

namespace lpss::engine {

/// The Bullet shape for a body. A plane is made through the origin (constant 0): each sector places it
/// with the body transform, so that its float constant stays small wherever the sector lies.
std::unique_ptr<btCollisionShape> make_collision_shape(const Shape& shape);

/// Radius of a sphere inside the shape, for Bullet's swept-sphere continuous collision detection.
double inner_radius(const Shape& shape);

}  // namespace lpss::engine
