// The handle by which the engine names a sector across calls (see sector_table.hpp).
#pragma once

#include <cstdint>

namespace lpss::engine {

/// A sector's handle: its slot in the world's SectorTable and the slot's generation when it was made.
/// Ids outlive sectors harmlessly: a stale id resolves to nothing (sector_table.hpp).
struct SectorId {
    static constexpr std::uint32_t kNone = ~std::uint32_t{0};
    std::uint32_t index = kNone;
    std::uint32_t generation = 0;

    bool valid() const { return index != kNone; }
    friend bool operator==(SectorId a, SectorId b) {
        return a.index == b.index && a.generation == b.generation;
    }
    friend bool operator!=(SectorId a, SectorId b) { return !(a == b); }
    friend bool operator<(SectorId a, SectorId b) {
        return a.index != b.index ? a.index < b.index : a.generation < b.generation;
    }
};

}  // namespace lpss::engine
