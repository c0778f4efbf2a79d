// The writing half of the delta encoding of sector frames (SectorChain and SectorMirror are the reading
// half): what readers hold of each sector a worker owns, and the sample that brings them to the sector's
// state now. A sector's first sample, and any sample asked for whole, is complete: every body with what it
// is (its kind) and its offset in double. The others hold the bodies that changed or arrived (with the
// arrivals' kinds) and the ids of those that left, on the sector's previous sample; they are made from what
// changed alone, so that a sector of resting bodies with one rolling ball costs one body. A sector that
// empties says so in a complete sample (empty), and is forgotten: if bodies come back, its next sample is
// complete again.
//
// Each body also carries a 27-bit mask of the neighbouring sectors it comes near (bit 13 is the sector
// itself), set by the caller; the publisher keeps, per sector, which neighbours some body comes near.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <unordered_map>
#include <vector>

#include "lpss.h"
#include "lpss/common/body_snapshot.hpp"
#include "lpss/common/sector_key.hpp"
#include "lpss_dds/convert.hpp"

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

    /// A complete sample of `key` holding `bodies` (every body of the sector, sorted by id, with their
    /// near masks), even if there is none: readers then learn that the sector emptied. Fills the body
    /// fields, frame, base and complete; the caller fills recipients, worker and epoch.
    wire::SectorFrame whole(const SectorKey& key, const std::vector<BodySnapshot>& bodies,
                            const std::vector<std::uint32_t>& near, std::uint64_t frame,
                            const Describe& describe);
    /// A sector readers already hold whole as of `frame` from another writer (the coordinator's samples of
    /// the world's first state): the same as whole() without the sample. Its next sample is partial.
    void adopt(const SectorKey& key, const std::vector<BodySnapshot>& bodies,
               const std::vector<std::uint32_t>& near, std::uint64_t frame);
    /// The partial sample that brings readers of a sector published before to its state now, from the
    /// bodies that may have changed or arrived (sorted by id, with their near masks) and the ids of those
    /// that left (sorted); nothing if nothing changed for readers.
    std::optional<wire::SectorFrame> update(const SectorKey& key, const std::vector<BodySnapshot>& changed,
                                            const std::vector<std::uint32_t>& near,
                                            const std::vector<BodyId>& left, std::uint64_t frame,
                                            const Describe& describe);
    /// An empty partial sample of a sector published before, for readers that must hear from it this
    /// frame (to learn they no longer hold it).
    wire::SectorFrame nothing_new(const SectorKey& key, std::uint64_t frame);
    /// Sets the near masks of a sector's bodies (every body, sorted by id, as the sector holds them).
    void set_near(const SectorKey& key, const std::vector<BodySnapshot>& bodies,
                  const std::vector<std::uint32_t>& near);
    /// Forgets a sector given away: if it comes back, its first sample is complete again.
    void forget(const SectorKey& key);

    bool publishes(const SectorKey& key) const { return sectors_.count(key) != 0; }
    /// The frame of the sector's latest sample (0: none).
    std::uint64_t stamp(const SectorKey& key) const;
    Counts counts(const SectorKey& key) const;
    /// The neighbours some body of the sector comes near (bit 9i + 3j + k for offset (i-1, j-1, k-1)).
    std::uint32_t near(const SectorKey& key) const;
    /// Bodies and awake bodies over every sector published.
    Counts totals() const { return totals_; }
    std::size_t sector_count() const { return sectors_.size(); }
    /// Calls each(key, stamp, counts) for every sector published (one that holds bodies).
    template <class F>
    void for_each(F&& each) const {
        for (const auto& [key, sector] : sectors_)
            each(key, sector.stamp, sector.counts);
    }

private:
    // Plain values, so that a sector's sorted bodies move by memmove and are searched and compared inline
    // (with fastddsgen's types, its accessor and copy calls were most of the publisher's time).
    struct Body {
        PackedBodyState state;  ///< as readers hold it
        std::uint32_t near = 0;
    };
    struct Sector {
        std::vector<Body> bodies;  ///< sorted by id
        std::uint64_t stamp = 0;
        Counts counts;
        std::array<std::uint32_t, 27> near{};  ///< bodies coming near each neighbour
    };
    void count(Sector& sector, const Body& body, int sign);

    std::unordered_map<SectorKey, Sector, SectorKeyHash> sectors_;
    Counts totals_;
};

}  // namespace lpss::dds
