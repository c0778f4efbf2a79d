// Conversions between the wire types (lpss::wire, generated from idl/lpss.idl) and lpss's own values.
#pragma once

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

/// A body's state with its position as a float offset from its sector's centre.
wire::BodyState to_wire(const BodySnapshot& body);
/// The state read back, placed in `sector`.
BodySnapshot from_wire(const wire::BodyState& state, const SectorKey& sector);

/// A body's description, placed at `where` with the given state (a plane: its anchor).
wire::BodyDescription describe(const BodyDesc& body, const BodySnapshot& state, std::uint32_t owner);
/// The description read back as a BodyDesc placed by sector (not validated: validate before use).
BodyDesc from_wire(const wire::BodyDescription& description);

wire::WorldSettings to_wire(const WorldSettings& settings);
WorldSettings from_wire(const wire::WorldSettings& settings);
wire::MortonCode to_wire(const MortonCode& code);
MortonCode from_wire(const wire::MortonCode& code);
/// The assignment with the world's settings it applies to.
wire::Assignment to_wire(const SectorAssignment& assignment, const WorldSettings& settings);
SectorAssignment from_wire(const wire::Assignment& assignment);

}  // namespace lpss::dds
