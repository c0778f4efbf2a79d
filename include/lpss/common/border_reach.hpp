// Which of the sectors next to its own a body may touch something in, before the next frame's samples
// come. A worker sends each sector's samples to the owners of the neighbouring sectors its bodies come this
// near (and only to them): they hold those bodies as ghosts and clone them across the border, as one
// process would. Nothing here knows Bullet: positions are sector-local offsets, sizes bounding radii.
#pragma once

#include <Eigen/Core>

#include "lpss/common/sector_key.hpp"
#include "lpss/common/world_settings.hpp"

namespace lpss {

/// How far beyond its centre a body must be looked at for neighbours it may touch: past the border by up
/// to the hysteresis band (its own centre, or a neighbour's, may lie that far in the other's cell), its
/// radius, the largest radius of anything it may meet, and three frames of its motion (a sample reaches
/// the neighbour's worker one frame after it is written), with a little slack for contact distance.
inline double border_reach(const WorldSettings& settings, double radius, double largest_radius,
                           double speed) {
    return settings.hysteresis * settings.sector_size + radius + largest_radius + 3.0 * speed * settings.dt +
           0.1;
}

/// Calls each(offset) for each of the 26 neighbours of a sector (offset in {-1, 0, 1}^3, not all 0) whose
/// cell comes within `reach` of a point `local` (its offset from the sector's centre).
template <class F>
void neighbours_within(const Eigen::Vector3d& local, double sector_size, double reach, F&& each) {
    const double half = 0.5 * sector_size;
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = local[a] - reach <= -half ? -1 : 0;
        hi[a] = local[a] + reach >= half ? 1 : 0;
    }
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
            for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
                if (i != 0 || j != 0 || k != 0) each(SectorKey{i, j, k});
}

}  // namespace lpss
