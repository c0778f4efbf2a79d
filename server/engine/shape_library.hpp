// Bullet shapes shared by every body of the same shape value.
#pragma once

#include <BulletCollision/CollisionShapes/btCollisionShape.h>

#include <cstddef>
#include <memory>
#include <unordered_map>

#include "lpss/common/shape.hpp"

namespace lpss::engine {

/// One Bullet shape per distinct shape value, held by the bodies that have it (and lent to their clones),
/// as Jolt's bodies share a reference-counted Shape: a world of a million bodies of a few kinds holds a few
/// shapes, not a million (building them was a fifth of the time a worker spent adding the bodies of its
/// share at start). Bullet only reads a shape while it steps, so sectors stepped on
/// different threads may share one. A shape goes when its last body does.
class ShapeLibrary {
public:
    /// The shape for this value: the one a living body already holds, or a new one.
    std::shared_ptr<btCollisionShape> get(const Shape& shape);
    /// Distinct shapes some body still holds.
    std::size_t live() const;
    /// Entries in the table, gone shapes not yet swept included.
    std::size_t entries() const { return by_hash_.size(); }

private:
    struct Entry {
        Shape value;
        std::weak_ptr<btCollisionShape> bullet;
    };
    /// Forgets entries whose shape has gone, once the table has doubled since the last time (amortized).
    void sweep();

    std::unordered_multimap<std::size_t, Entry> by_hash_;
    std::size_t sweep_at_ = 64;
};

}  // namespace lpss::engine
