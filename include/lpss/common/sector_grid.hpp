// The sector grid: conversions between double global positions and the canonical (sector key, local
// offset) form. The grid is centred on the origin: sector 0 spans [-L/2, L/2) on each axis,
// index = floor(x / L + 1/2), local = x - index * L.
#pragma once

#include <Eigen/Core>

#include "lpss/common/expected.hpp"
#include "lpss/common/sector_key.hpp"

namespace lpss {

/// A position as the sector it lies in and the offset from that sector's centre. This pair is exact at
/// any distance; a double global position is only made at the edges (scene input, client output).
/// The float engine's offsets are floats; doubles hold them exactly, and the float64 engine fills them.
struct SectorPosition {
    SectorKey sector;
    Eigen::Vector3d local = Eigen::Vector3d::Zero();
};

/// The largest sector edge for a precision radius r (paper section 4): a sector and all its
/// neighbours, where clones live, must fit inside the sphere of radius r: L <= 2r / (3 sqrt 3).
double max_sector_size(double precision_radius);

/// Refuses a sector size that breaks the bound for its precision radius, naming the largest allowed.
Status check_sector_size(double sector_size, double precision_radius);

/// Conversions for one sector size. A cheap value type: copy it where it is needed.
class SectorGrid {
public:
    /// sector_size must be finite and > 0 (validated where settings are loaded).
    explicit SectorGrid(double sector_size);

    double sector_size() const { return size_; }

    /// The sector containing a global position and the offset from its centre. The offset is exact
    /// (one rounding of x - index * L); refused for non-finite input or |index| > 2^62.
    Expected<SectorPosition> from_global(const Eigen::Vector3d& global) const;

    /// The double global position; good to about 1e15 units, the reach of a double.
    Eigen::Vector3d to_global(const SectorPosition& position) const;

    /// The same point with its offset brought inside [-L/2, L/2) by exact key arithmetic, for offsets
    /// that lie outside their sector (as hand-written scenes may give). Refused like from_global.
    Expected<SectorPosition> canonical(const SectorPosition& position) const;

    /// The vector from the centre of sector `from` to the centre of sector `to`, (to - from) * L.
    /// Exact key difference even for keys at opposite ends of the grid. Inline: the border index asks for
    /// it for every pair of partners every frame (16% of the cloning stage's instructions as a call).
    Eigen::Vector3d centre_offset(const SectorKey& from, const SectorKey& to) const {
        return {key_difference(to.i, from.i) * size_, key_difference(to.j, from.j) * size_,
                key_difference(to.k, from.k) * size_};
    }

    /// A position expressed as an offset from the centre of sector `frame`.
    Eigen::Vector3d offset_in(const SectorPosition& position, const SectorKey& frame) const {
        return centre_offset(frame, position.sector) + position.local;
    }

    /// The sector whose cell contains an offset given relative to the centre of `frame`.
    SectorPosition relocate(const SectorKey& frame, const Eigen::Vector3d& offset) const;

private:
    /// a - b as a double. Keys reach +-2^62, so a - b can need 64 bits plus a sign.
    static double key_difference(std::int64_t a, std::int64_t b) {
        std::int64_t difference = 0;
        if (!__builtin_sub_overflow(a, b, &difference)) return static_cast<double>(difference);
        return wide_key_difference(a, b);
    }
    static double wide_key_difference(std::int64_t a, std::int64_t b);

    double size_;
    double half_;
};

}  // namespace lpss
