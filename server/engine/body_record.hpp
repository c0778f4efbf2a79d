// The engine's record of one body: its Bullet objects, where it lives, its border entry and its clones.
#pragma once

#include <BulletCollision/BroadphaseCollision/btDbvt.h>
#include <BulletCollision/CollisionShapes/btCollisionShape.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "aabb.hpp"
#include "lpss/common/body_desc.hpp"
#include "lpss/common/sector_key.hpp"
#include "overhang_bound.hpp"
#include "sector_id.hpp"

namespace lpss::engine {

/// What a Bullet object stands for, stored in its user index 2 (the user index holds the body slot).
enum class Role : int { Original = 0, Clone = 1, PlaneInstance = 2 };

/// How far (sector_distance) a clone's host may be from its original's sector. A body is at most a sector
/// wide and its centre within the hysteresis band of its sector, so its reach stays within the next sector;
/// two such reaches meet at most two sectors apart. A body that jumps further (set_state, a very fast
/// body) lets go of clones beyond this at once, rather than keep copies far from their host's origin.
inline constexpr std::int64_t kCloneNeighbourhood = 2;

/// Frames an unneeded clone stays in its host before it is released (cloning.cpp says why).
inline constexpr std::uint64_t kCloneLinger = 8;

/// A copy of a body inside another sector (or, for a plane, its instance in a sector).
struct Clone {
    SectorId host;
    std::unique_ptr<btRigidBody> rb;
    std::uint64_t confirmed_frame = 0;  ///< last frame the cloning stage found it needed
};

/// A body's entry in the BorderIndex (border_index.hpp): this frame's tight reach; a fat box, in the
/// owner's frame, that holds every place the body may sweep until it is refreshed; its leaves in the cell
/// trees it enters; and its partners. Only the index writes it.
struct BorderEntry {
    std::vector<std::uint32_t> partners;  ///< bodies of other sectors that may touch it
    Aabb reach;
    std::uint64_t reach_frame = 0;  ///< the frame `reach` was computed in
    Aabb fat;
    /// The sector whose frame `fat` is in (a key: the frame is the sector's centre, whatever becomes of
    /// the sector itself); refreshed when the body changes sector. No fat box yet: has_fat is false.
    SectorKey fat_frame;
    bool has_fat = false;
    /// The fat box was made for a moving body (a slack or a stretch beyond a resting body's).
    bool made_moving = false;
    /// Where its fat box's overhang is counted (Sector::overhangs): the bucket, and the sector.
    std::uint8_t overhang_bucket = OverhangScale::kNoBucket;
    struct Leaf {
        SectorKey cell;
        btDbvtNode* node = nullptr;
    };
    std::vector<Leaf> leaves;
    /// Where the body is listed among its sector's partnered originals (Sector::partnered): the
    /// sector and the place. None while it has no partners; stale for a moment after it changes sector.
    SectorId listed_in;
    std::uint32_t listed_at = 0;
    SectorId overhang_in;  ///< (with overhang_bucket)
};

/// Hot fields first: the stages walk these records every frame.
struct BodyRecord {
    // Read by every stage, every frame.
    BodyId id = 0;
    bool alive = false;
    bool dynamic = false;
    bool plane = false;
    std::uint32_t index_in_sector = 0;
    SectorId sector;                  ///< owner sector; none for a plane
    std::unique_ptr<btRigidBody> rb;  ///< the original, in its owner sector; none for a plane
    /// Position of the original in its owner sector's frame, in double: the float engine's position is
    /// this rounded (see World::Impl::track_position).
    Eigen::Vector3d local = Eigen::Vector3d::Zero();
    std::uint64_t visit_frame = 0;
    bool departing = false;         ///< listed in World::Impl::departing
    std::uint64_t moved_frame = 0;  ///< the frame the step found it active (recorded in the change log once)

    BorderEntry border;  ///< kept by the BorderIndex

    std::vector<Clone> clones;
    std::vector<std::unique_ptr<btRigidBody>> spare_clones;

    // Read when bodies and clones are made.
    /// Shared by the original, every clone, and every body of the same shape value (ShapeLibrary).
    std::shared_ptr<btCollisionShape> shape;
    btScalar mass = 0;
    btVector3 inertia{0, 0, 0};
    double bound_radius = 0.0;
    SectorPosition
        plane_anchor;  ///< a plane exists in every sector near it: dot(normal, p - anchor) = offset
    std::unique_ptr<BodyDesc> desc;  ///< as created: cold, for descriptions and messages

    Clone* clone_in(SectorId host) {
        for (Clone& c : clones) {
            if (c.host == host) return &c;
        }
        return nullptr;
    }
};

}  // namespace lpss::engine
