// Stage 1, sectorization: a body whose centre has left its sector by more than the hysteresis band
// moves to the sector that now contains it, in that sector's local coordinates.
#include <cmath>

#include "bullet_convert.hpp"
#include "world_impl.hpp"

namespace lpss {

void World::Impl::sectorize(const std::vector<std::uint32_t>& candidates) {
    for (std::uint32_t slot : candidates) {
        engine::BodyRecord& rec = record(slot);
        if (!rec.dynamic || sector_of(rec).remote) continue;  // ghosts move by set_state only
        const Eigen::Vector3d& local = rec.local;
        if (std::fabs(local.x()) < band && std::fabs(local.y()) < band && std::fabs(local.z()) < band)
            continue;
        // Any distance: a fast body may cross several sectors in one frame.
        Expected<SectorPosition> to = grid.canonical(SectorPosition{sector_of(rec).key, local});
        if (!to.ok()) continue;   // past the edge of the grid (index 2^62): it stays where it is
        if (!owns(to->sector)) {  // handed off by its process: World::departures()
            if (!rec.departing) departing.push_back(slot);
            rec.departing = true;
            continue;
        }
        move_body(slot, to.value());
        ++stats.sector_changes;
    }
}

}  // namespace lpss
