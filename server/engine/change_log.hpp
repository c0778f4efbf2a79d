// What changed where, for publishers (World::changed_sectors, World::sector_changes): per sector, the
// bodies that may have moved or arrived (by slot: read back without looking ids up; a slot freed and
// reused since holds another body, which the reader checks is there) and the ids of those that left. Gathered
// from calls and sectorization since the last frame and from the frame's step, then kept as the last frame's,
// so that a publisher looks at what moved and nothing else: a sector of a thousand resting bodies and one
// rolling ball costs one body.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "lpss/common/body_desc.hpp"
#include "lpss/common/sector_key.hpp"

namespace lpss::engine {

class ChangeLog {
public:
    struct Entry {
        std::vector<std::uint32_t> touched;  ///< slots that may have moved or arrived (may repeat)
        std::vector<BodyId> left;            ///< moved out or removed (may repeat, or have come back)
        bool empty() const { return touched.empty() && left.empty(); }
    };

    void touched(const SectorKey& sector, std::uint32_t slot) { gathering_[sector].touched.push_back(slot); }
    void left(const SectorKey& sector, BodyId id) { gathering_[sector].left.push_back(id); }
    /// The frame ended: what was gathered since the last frame is this frame's.
    void end_frame();

    /// Sectors where something changed in the last frame, in key order.
    const std::vector<SectorKey>& sectors() const { return sectors_; }
    /// What changed in one of them, or nothing.
    const Entry* find(const SectorKey& sector) const {
        auto it = last_.find(sector);
        return it == last_.end() || it->second.empty() ? nullptr : &it->second;
    }

private:
    std::unordered_map<SectorKey, Entry, SectorKeyHash> gathering_;
    std::unordered_map<SectorKey, Entry, SectorKeyHash> last_;
    std::vector<SectorKey> sectors_;
};

}  // namespace lpss::engine
