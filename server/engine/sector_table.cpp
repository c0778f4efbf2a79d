#include "sector_table.hpp"

#include <cstdio>
#include <cstdlib>

namespace lpss::engine {

void SectorTable::stale(SectorId id) {
    std::fprintf(stderr, "lpss engine: stale sector id (slot %u, generation %u)\n", id.index, id.generation);
    std::abort();
}

Sector& SectorTable::insert(std::unique_ptr<Sector> sector) {
    std::uint32_t index;
    if (!free_.empty()) {
        index = free_.back();
        free_.pop_back();
    } else {
        index = static_cast<std::uint32_t>(slots_.size());
        slots_.emplace_back();
    }
    Slot& slot = slots_[index];
    ++slot.generation;
    slot.sector = std::move(sector);
    slot.sector->id = SectorId{index, slot.generation};
    index_.emplace(slot.sector->key, index);
    return *slot.sector;
}

void SectorTable::erase(SectorId id) {
    Sector& sector = at(id);
    index_.erase(sector.key);
    Slot& slot = slots_[id.index];
    slot.sector.reset();
    ++slot.generation;
    free_.push_back(id.index);
}

}  // namespace lpss::engine
