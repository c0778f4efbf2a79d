// The sectors of a world, addressed by generation-checked handles. Anything that outlives one engine call
// (a body's owner, a clone's host, the sectors queued for stepping or destruction) holds a SectorId, never
// a pointer: a sector destroyed and its slot reused bumps the slot's generation, so a stale id resolves to
// nothing instead of to freed or foreign memory (Jolt's BodyID, Box2D's ids with a revision).
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "lpss/common/sector_key.hpp"
#include "sector.hpp"

namespace lpss::engine {

class SectorTable {
public:
    /// The live sector of a key, or nothing.
    Sector* find(const SectorKey& key) const {
        auto it = index_.find(key);
        return it == index_.end() ? nullptr : slots_[it->second].sector.get();
    }
    /// The sector an id names if it is still alive, or nothing for a stale or empty id.
    Sector* get(SectorId id) const {
        if (id.index >= slots_.size()) return nullptr;
        const Slot& slot = slots_[id.index];
        return slot.generation == id.generation ? slot.sector.get() : nullptr;
    }
    /// The sector an id names; the id must be alive (the engine's invariants say it is). A stale id is a
    /// bug in the engine: it stops the process rather than read freed memory.
    Sector& at(SectorId id) const {
        Sector* sector = get(id);
        if (sector == nullptr) stale(id);
        return *sector;
    }

    /// Takes a new sector (its key not in the table yet) and gives it its id.
    Sector& insert(std::unique_ptr<Sector> sector);
    /// Destroys a sector; its id and every copy of it go stale.
    void erase(SectorId id);

    std::size_t size() const { return index_.size(); }
    bool empty() const { return index_.empty(); }
    /// Calls each(Sector&) for every live sector, in slot order.
    template <class F>
    void for_each(F&& each) const {
        for (const Slot& slot : slots_) {
            if (slot.sector) each(*slot.sector);
        }
    }

private:
    /// Inline, as the stages look sectors up for every body they touch; the failure is out of line.
    [[noreturn]] static void stale(SectorId id);

    struct Slot {
        std::unique_ptr<Sector> sector;
        std::uint32_t generation = 0;  ///< odd while a sector lives in the slot, even while it is free
    };
    std::vector<Slot> slots_;
    std::vector<std::uint32_t> free_;
    std::unordered_map<SectorKey, std::uint32_t, SectorKeyHash> index_;
};

}  // namespace lpss::engine
