// The engine's record of one body: its Bullet objects, where it lives, its reach and its clones.
#pragma once

#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "aabb.hpp"
#include "lpss/common/body_desc.hpp"
#include "lpss/common/sector_key.hpp"

namespace lpss::engine {

class Sector;

/// What a Bullet object stands for, stored in its user index 2 (the user index holds the body slot).
enum class Role : int { Original = 0, Clone = 1, PlaneInstance = 2 };

/// A copy of a body inside another sector (or, for a plane, its instance in a sector).
struct Clone {
    Sector* host = nullptr;
    std::unique_ptr<btRigidBody> rb;
    std::uint64_t confirmed_frame = 0;  ///< last frame the cloning stage found it needed
};

struct BodyRecord {
    BodyDesc desc;  ///< as created, for descriptions and messages
    bool alive = false;
    bool dynamic = false;
    bool plane = false;

    std::unique_ptr<btCollisionShape> shape;  ///< shared by the original and every clone
    std::unique_ptr<btRigidBody> rb;          ///< the original, in its owner sector; none for a plane
    btScalar mass = 0;
    btVector3 inertia{0, 0, 0};
    double bound_radius = 0.0;

    Sector* sector = nullptr;  ///< owner sector; none for a plane
    /// Position of the original in its owner sector's frame, in double: the float engine's position is
    /// this rounded (see World::Impl::integrate_positions).
    Eigen::Vector3d local = Eigen::Vector3d::Zero();
    std::uint32_t index_in_sector = 0;

    // A plane exists in every sector near it: dot(normal, p - anchor) = offset.
    SectorPosition plane_anchor;

    // Reach: the box the body may sweep this frame (owner-local) and the foreign sectors it touches.
    Aabb reach;
    std::vector<SectorKey> border_cells;
    std::uint64_t visit_frame = 0;

    std::vector<Clone> clones;
    std::vector<std::unique_ptr<btRigidBody>> spare_clones;

    Clone* clone_in(const Sector* host) {
        for (Clone& c : clones) {
            if (c.host == host) return &c;
        }
        return nullptr;
    }
};

}  // namespace lpss::engine
