// The writing half of the delta encoding of sector frames (SectorChain and SectorMirror are the reading
// half): what readers hold of each sector a worker owns, and the sample that brings them to the sector's
// state now. A sector's first sample, and any sample asked for whole, is complete: every body with what it
// is (its kind) and its offset in double; the others hold the bodies that changed or arrived (with the
// arrivals' kinds) and the ids of those that left, on the sector's previous sample. A sector that empties
// gets an empty complete sample and is forgotten. Costs what the sectors it is given hold, nothing else.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <unordered_map>
#include <vector>

#include "lpss.h"
#include "lpss/common/body_snapshot.hpp"
#include "lpss/common/sector_key.hpp"

namespace lpss::dds {

class SectorPublisher {
public:
    /// What a body is, for readers that see it for the first time.
    using Describe = std::function<wire::BodyKind(BodyId)>;

    /// Bodies, and awake bodies, of one sector as last published.
    struct Counts {
        std::uint32_t bodies = 0;
        std::uint32_t awake = 0;
    };

    /// The sample that brings readers of `key` to `bodies` (the sector's bodies now, sorted by id), or
    /// nothing when nothing changed and `whole` is false. Whole, it is complete even if the sector is
    /// empty: a sector taken over from another writer must be sent whole, empty or not, since its readers
    /// hold what that writer sent. Fills the body fields, frame, base and complete; the caller fills
    /// recipients, worker and epoch.
    std::optional<wire::SectorFrame> update(const SectorKey& key, const std::vector<BodySnapshot>& bodies,
                                            std::uint64_t frame, bool whole, const Describe& describe);
    /// Forgets a sector given away: if it comes back, its first sample is complete again.
    void forget(const SectorKey& key);

    bool publishes(const SectorKey& key) const { return sectors_.count(key) != 0; }
    /// The frame of the sector's latest sample (0: none).
    std::uint64_t stamp(const SectorKey& key) const;
    Counts counts(const SectorKey& key) const;
    /// Bodies and awake bodies over every sector published.
    Counts totals() const { return totals_; }
    std::size_t sector_count() const { return sectors_.size(); }
    /// Sectors whose last sample was partial: a reader that joins finds in DDS's history only partial
    /// samples of them, of no use without what came before.
    std::vector<SectorKey> last_partial() const;
    /// Calls each(key, stamp, counts) for every sector published (one that holds bodies).
    template <class F>
    void for_each(F&& each) const {
        for (const auto& [key, sector] : sectors_)
            each(key, sector.stamp, sector.counts);
    }

private:
    struct Sector {
        std::vector<wire::BodyState> states;  ///< as readers hold them, sorted by id
        std::uint64_t stamp = 0;
        bool complete = false;  ///< its last sample was complete
        Counts counts;
    };
    void count(const Counts& counts, int sign);

    std::unordered_map<SectorKey, Sector, SectorKeyHash> sectors_;
    Counts totals_;
};

}  // namespace lpss::dds
