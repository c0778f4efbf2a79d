// What a worker holds: its own sectors, and the sectors next to them (its halo), whose bodies it keeps as
// ghosts in its engine so that they are cloned across its borders exactly as in one process. A sector is
// held by its owner and by the owners of its 26 neighbours: the holders, whom its samples are addressed
// to. While an assignment change is announced for the next frame, a worker holds what it holds under
// either, so that the samples written at the switch reach the new holders.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "lpss.h"
#include "lpss/common/assignment.hpp"
#include "lpss/engine/world.hpp"

namespace lpss::worker {

class Halo {
public:
    explicit Halo(std::uint32_t self) : self_(self) {}

    /// The assignment in force and the one announced (the same one when none is announced).
    void follow(const SectorAssignment& current, const SectorAssignment& next);
    const SectorAssignment& current() const { return current_; }
    const SectorAssignment& next() const { return next_; }
    /// Whether `next` takes effect with the frame after `frame`.
    bool switching_after(std::uint64_t frame) const {
        return next_.epoch != current_.epoch && next_.from_frame == frame + 1;
    }

    bool owns(const SectorKey& key) const { return current_.owner_of(key) == self_; }
    /// Own or halo, under the current assignment or the one announced.
    bool holds(const SectorKey& key);
    /// The workers a sample of `key` written at `frame` goes to: its holders now, and from the next frame.
    std::vector<std::uint32_t> recipients(const SectorKey& key, std::uint64_t frame);
    /// Whether the sector gains holders with the assignment announced (they need it whole).
    bool gains_holders(const SectorKey& key);

    /// Applies other workers' samples (in frame order) to the engine's ghosts: states follow, bodies that
    /// arrive are built from their kinds, and those that left what this worker holds are dropped. Its own
    /// bodies are never touched. The coordinator's samples of the world's first state rank their bodies:
    /// those are added in the scene's order, together with `also` (ranked bodies, the world's planes).
    void apply(World& world, const std::vector<const wire::SectorFrame*>& samples,
               const std::vector<std::pair<std::uint64_t, BodyDesc>>& also = {});
    /// Drops the ghosts of sectors no longer held (after an assignment change).
    void drop_unheld(World& world);

private:
    const std::vector<std::uint32_t>& holders(
        const SectorAssignment& assignment, const SectorKey& key,
        std::unordered_map<SectorKey, std::vector<std::uint32_t>, SectorKeyHash>& cache);

    std::uint32_t self_;
    SectorAssignment current_;
    SectorAssignment next_;
    std::unordered_map<SectorKey, std::vector<std::uint32_t>, SectorKeyHash> current_holders_;
    std::unordered_map<SectorKey, std::vector<std::uint32_t>, SectorKeyHash> next_holders_;
};

}  // namespace lpss::worker
