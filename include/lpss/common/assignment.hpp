// Which worker simulates which sectors. Sectors are grouped in cubic blocks; blocks are ordered along the
// Morton (Z-order) curve, and each worker owns one contiguous range of it: spatially coherent pieces of
// the world, every sector owned by exactly one worker, including sectors nobody has used yet.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "lpss/common/sector_key.hpp"

namespace lpss {

/// A block's position on the Morton curve: its three indices (offset by 2^63) interleaved bit by bit
/// into 192 bits, most significant word first.
struct MortonCode {
    std::uint64_t high = 0;
    std::uint64_t middle = 0;
    std::uint64_t low = 0;

    friend bool operator<(const MortonCode& a, const MortonCode& b) {
        if (a.high != b.high) return a.high < b.high;
        if (a.middle != b.middle) return a.middle < b.middle;
        return a.low < b.low;
    }
    friend bool operator==(const MortonCode& a, const MortonCode& b) {
        return a.high == b.high && a.middle == b.middle && a.low == b.low;
    }
};

MortonCode morton_code(const SectorKey& block);

/// The block holding a sector (floor division of each index by the block size).
SectorKey block_of(const SectorKey& sector, std::int64_t block_size);

struct SectorAssignment {
    std::uint32_t epoch = 0;
    std::uint64_t from_frame = 0;
    std::int64_t block_size = 4;
    std::vector<std::uint32_t> workers;  ///< workers[n] owns [starts[n], starts[n + 1])
    std::vector<MortonCode> starts;      ///< starts[0] is the start of the curve

    /// The worker simulating a sector (0 when the assignment is empty).
    std::uint32_t owner_of(const SectorKey& sector) const;

    /// Cuts the Morton curve into one range per worker so that each holds about the same load; `loads`
    /// gives the load (bodies, step time) of the sectors that have any. Workers in the order given.
    static SectorAssignment balanced(const std::vector<std::pair<SectorKey, double>>& loads,
                                     const std::vector<std::uint32_t>& workers, std::int64_t block_size);

    /// The same cut without one worker: its range goes to its neighbours on the curve, split where its load
    /// (`loads`, as for balanced) halves; every other worker keeps every sector it owns. What a cluster
    /// needs when a worker is gone: its other workers cannot hand a sector over in the frame that follows.
    /// Unchanged if `worker` has no range or is the only worker.
    SectorAssignment without(std::uint32_t worker,
                             const std::vector<std::pair<SectorKey, double>>& loads) const;
};

}  // namespace lpss
