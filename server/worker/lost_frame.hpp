// The frame a worker that is gone did not finish, stepped again by someone else (the coordinator) as the
// worker would have stepped it, so that its bodies lose no motion: its sectors and the sectors around them
// as last published (the frame before), the handoffs granted and the commands of the frame, stepped once
// in an engine world of their own. What comes out is what the worker would have published: its sectors
// whole, the bodies it would hand over, and the answers to commands it owed.
//
// Not bit for bit the worker's step: a world built afresh has no contact history (Bullet's warm start),
// as a body handed between workers has none either.
#pragma once

#include <cstdint>
#include <vector>

#include "lpss.h"
#include "lpss/common/assignment.hpp"
#include "lpss/common/expected.hpp"
#include "lpss/common/scene.hpp"

namespace lpss::worker {

struct LostFrameInput {
    WorldSettings settings;
    SectorAssignment assignment;  ///< in force at `frame`
    double largest_radius = 0.0;
    std::uint32_t worker = 0;  ///< the worker that is gone
    std::uint64_t frame = 0;   ///< the frame it did not finish
    /// Complete samples of its sectors and of the sectors around them, as of frame - 1.
    std::vector<wire::SectorFrame> sectors;
    std::vector<BodyDesc> planes;         ///< the world's planes
    std::vector<wire::Handoff> handoffs;  ///< granted at `frame`
    std::vector<wire::Command> commands;  ///< of `frame`, in the coordinator's order
    std::vector<std::uint64_t> command_order;
};

struct LostFrame {
    std::vector<wire::SectorFrame> sectors;    ///< its sectors at `frame`, complete; recipients not set
    std::vector<wire::Handoff> leaving;        ///< its bodies that crossed into sectors it does not own
    std::vector<wire::CommandResult> results;  ///< the answers it owed, at `frame`
    std::size_t bodies = 0;                    ///< its own bodies, stepped
};

/// Steps the lost frame; refused with the reason if the world cannot be built.
Expected<LostFrame> step_lost_frame(const LostFrameInput& input);

}  // namespace lpss::worker
