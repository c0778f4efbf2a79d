// Bodies changing owner between workers. A body whose centre crosses into a sector another worker owns
// stays with its owner, past the border, until the coordinator grants the handoff; the grant comes with
// the next frame's start, and every worker holding the body then moves it to the state handed over,
// exactly: the receiver's copy becomes its own body (its sector is the receiver's), the sender's a ghost.
#pragma once

#include <cstdint>
#include <vector>

#include "lpss.h"
#include "lpss/common/assignment.hpp"
#include "lpss/engine/world.hpp"

namespace lpss::worker {

/// This worker's requests at the end of a frame: its bodies that crossed into sectors it does not own,
/// each with its exact state and what it is, for the owner of that sector under `after` (the assignment
/// in force at the next frame).
std::vector<wire::Handoff> handoff_requests(const World& world, std::uint32_t self,
                                            const SectorAssignment& after);

/// Applies the handoffs granted for this frame to this worker's copies of those bodies; a receiver that
/// holds no copy (a body that crossed more than a sector in one frame) builds one.
void apply_handoffs(World& world, const std::vector<wire::Handoff>& granted, std::uint32_t self);

}  // namespace lpss::worker
