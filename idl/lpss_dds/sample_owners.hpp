// Whose sample a sector sample may be: the worker that owns the sector under the assignment in force at
// the sample's frame, writing under that assignment's epoch. Without it a reader took any well-formed
// sample in: a peer's sample of a sector it does not own put its bodies into workers' worlds (as ghosts)
// and into clients' frames, and a worker left behind by a newer assignment (cut off, taken as gone) could
// write over its sectors' new owner. Each reader (worker, client, coordinator) learns the assignments as
// they come and asks here before a sample reaches its chain.
//
// What it cannot tell: a writer that names the owner and the epoch in force is believed. Telling a worker
// from a peer that claims to be it takes DDS Security (docs/security.md). The coordinator's samples (worker
// 0: the world's first state, the sectors of a worker that is gone) are its own to write. A sample that
// comes before the reader knows any assignment, or of a frame before every assignment it knows (a late
// joiner reading a writer's history), is let through unjudged: the reader cannot know who owned the sector
// then.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "lpss.h"
#include "lpss/common/assignment.hpp"
#include "lpss_dds/sample_check.hpp"

namespace lpss::dds {

class SampleOwners {
public:
    /// How many samples it holds at most while their epochs are unknown; beyond, the oldest is refused.
    static constexpr std::size_t kMostHeld = 4096;

    /// An assignment, in force from its from_frame; it replaces what was known from that frame on.
    /// Returns the held samples, to be offered again: their epoch may be known now.
    std::vector<wire::SectorFrame> learn(const SectorAssignment& assignment);

    /// Whether `sample` may be taken in now. false: refused (with its reason, to `refused`), or held, when
    /// its epoch is newer than every assignment known (a sample can come before the word of its epoch).
    bool admit(const wire::SectorFrame& sample, RefusedSamples& refused);

    /// The frames up to `frame` are applied: a sample of one still held never had its epoch come. Refused.
    void applied(std::uint64_t frame, RefusedSamples& refused);

    /// The assignment in force at `frame`; null before every assignment known.
    const SectorAssignment* in_force(std::uint64_t frame) const;

    std::size_t held() const { return held_.size(); }

private:
    std::map<std::uint64_t, SectorAssignment> by_from_frame_;
    std::uint32_t newest_epoch_ = 0;
    std::vector<wire::SectorFrame> held_;
};

}  // namespace lpss::dds
