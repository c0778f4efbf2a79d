// Clients' commands as a worker applies them at the start of a frame, in the coordinator's order: a spawn
// is added by its sector's owner and by the workers holding that sector; a removal by every worker that
// holds the body; impulses and velocities by the body's owner. The owner answers.
#pragma once

#include <functional>
#include <optional>
#include <set>

#include "lpss.h"
#include "lpss/common/sector_key.hpp"
#include "lpss/engine/world.hpp"

namespace lpss::worker {

/// Which sectors a worker owns, and which others it holds (their bodies are its ghosts).
struct Holding {
    std::function<bool(const SectorKey&)> owns;
    std::function<bool(const SectorKey&)> holds;
};

/// Applies one command to `world`; `planes` (the world's planes, every worker holds them as its own) follows
/// spawns and removals of planes. Returns how it went when this worker is the one to answer, else nothing.
std::optional<Status> apply_command(World& world, const wire::Command& command, const Holding& holding,
                                    std::set<BodyId>& planes);

/// The answer to a command: applied, or refused with the reason, at `frame` and in the global `order`.
wire::CommandResult answer(const wire::Command& command, std::uint64_t order, std::uint64_t frame,
                           const Status& outcome);

}  // namespace lpss::worker
