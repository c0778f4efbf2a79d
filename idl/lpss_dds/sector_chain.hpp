// Which sector samples a reader can use. A sample holds its whole sector, or only what changed since the
// sector's last complete sample (its base, see SectorFrame in idl/lpss.idl): a reader that missed that base
// (it joined late, or a slow reader lost samples to newer ones in the writer's history) cannot use a
// partial sample, and waits for the next complete one rather than show a sector with stale bodies.
#pragma once

#include <cstdint>
#include <set>
#include <unordered_map>
#include <vector>

#include "lpss.h"
#include "lpss/common/sector_key.hpp"

namespace lpss::dds {

class SectorChain {
public:
    /// Whether `sample` can be applied on the samples accepted before it (applied in frame order); if so,
    /// its frame is remembered as one the reader will hold the sector at.
    bool accept(const wire::SectorFrame& sample);
    /// Whether `sample` comes after the reader applied a state of its sector as new or newer: from another
    /// writer's history that reached the reader late (the coordinator's first state, a sector's previous
    /// owner). accept() refuses it; applying it would take the sector back in time.
    bool stale(const wire::SectorFrame& sample) const;
    /// Whether an accepted sample of `sector` has a frame in [from, to]: the sector as of `to` is known.
    bool holds(const SectorKey& sector, std::uint64_t from, std::uint64_t to) const;
    /// The frame of the newest accepted sample of `sector` (0: none).
    std::uint64_t newest(const SectorKey& sector) const;
    /// Samples up to `frame` are applied: of those, only the newest of each sector still matters.
    void forget_applied(std::uint64_t frame);
    /// Partial samples refused so far (each costs the reader that sector until a complete sample).
    std::uint64_t refused() const { return refused_; }

private:
    std::unordered_map<SectorKey, std::set<std::uint64_t>, SectorKeyHash> accepted_;
    /// Sectors holding more than one accepted frame: forget_applied looks at these alone (a reader of a
    /// large world holds thousands of sectors, and a few change in a frame).
    std::vector<SectorKey> several_;
    std::uint64_t refused_ = 0;
    std::uint64_t applied_ = 0;  ///< forget_applied's latest frame
};

}  // namespace lpss::dds
