// Conversions between the wire types (lpss::wire, generated from idl/lpss.idl) and lpss's own values.
#pragma once

#include <array>
#include <cstdint>

#include "lpss.h"
#include "lpss/common/assignment.hpp"
#include "lpss/common/body_desc.hpp"
#include "lpss/common/body_snapshot.hpp"
#include "lpss/common/sector_key.hpp"
#include "lpss/common/world_settings.hpp"

namespace lpss::dds {

wire::SectorKey to_wire(const SectorKey& key);
SectorKey from_wire(const wire::SectorKey& key);
wire::Vec3d to_wire(const Eigen::Vector3d& v);
Eigen::Vector3d from_wire(const wire::Vec3d& v);

/// A body's state as it goes on the wire (position as a float offset from its sector's centre), as a plain
/// value: what a writer keeps of many bodies, copied and compared without fastddsgen's accessor calls.
struct PackedBodyState {
    BodyId id = 0;
    std::array<float, 3> position{};
    std::array<float, 4> orientation{};  ///< x, y, z, w
    std::array<float, 3> linear_velocity{};
    std::array<float, 3> angular_velocity{};
    std::uint32_t flags = 0;  ///< bit 0: awake
    bool awake() const { return (flags & 1u) != 0; }
    /// The same state for readers (ids aside): each float compared as a float.
    bool same_motion(const PackedBodyState& other) const {
        return position == other.position && orientation == other.orientation &&
               linear_velocity == other.linear_velocity && angular_velocity == other.angular_velocity &&
               flags == other.flags;
    }
};
PackedBodyState pack(const BodySnapshot& body);
PackedBodyState pack(const wire::BodyState& state);
wire::BodyState to_wire(const PackedBodyState& state);
/// The state read back, placed in `sector`.
BodySnapshot unpack(const PackedBodyState& state, const SectorKey& sector);
/// A body's state with its position as a float offset from its sector's centre: to_wire(pack(body)).
wire::BodyState to_wire(const BodySnapshot& body);
/// The state read back, placed in `sector`: unpack(pack(state), sector).
BodySnapshot from_wire(const wire::BodyState& state, const SectorKey& sector);

/// What a body is (shape, mass, material, name), without where it is.
wire::BodyKind kind_of(const BodyDesc& body);
/// The kind read back as a BodyDesc at rest at the origin (not validated: validate before use).
BodyDesc from_wire(const wire::BodyKind& kind);
/// A body placed with the given state, what it is included (a plane: at its anchor).
BodyDesc placed(BodyDesc body, const BodySnapshot& state);

/// A body's whole description, placed at `state` (a plane: its anchor).
wire::BodyDescription describe(const BodyDesc& body, const BodySnapshot& state);
/// The description read back as a BodyDesc placed by sector (not validated: validate before use).
BodyDesc from_wire(const wire::BodyDescription& description);

wire::WorldSettings to_wire(const WorldSettings& settings);
WorldSettings from_wire(const wire::WorldSettings& settings);
wire::MortonCode to_wire(const MortonCode& code);
MortonCode from_wire(const wire::MortonCode& code);
/// The assignment with the world's settings it applies to and the largest bounding radius of its bodies.
wire::Assignment to_wire(const SectorAssignment& assignment, const WorldSettings& settings,
                         double largest_radius);
SectorAssignment from_wire(const wire::Assignment& assignment);

}  // namespace lpss::dds
