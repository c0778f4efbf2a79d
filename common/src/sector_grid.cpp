#include "lpss/common/sector_grid.hpp"

#include <cmath>
#include <sstream>

namespace lpss {
namespace {

// Sign of x - (index + shift) * L, exact for |index| < 2^52 (index + 1/2 is then a double and the
// fused multiply-add rounds once, which keeps the sign).
double border_side(double x, std::int64_t index, double shift, double size) {
    return std::fma(-(static_cast<double>(index) + shift), size, x);
}

// Index and offset along one axis. The candidate from floor(x / L + 1/2) can be off by one where the
// division or the addition rounds. The fused multiply-add gives x - index * L with a single rounding,
// whose comparison with +-L/2 is exact except when it rounds onto the border itself: then the side of
// the border is decided on x - (index +- 1/2) * L directly.
bool split_axis(double x, double size, double half, std::int64_t& index, double& local) {
    double q = std::floor(x / size + 0.5);
    if (!std::isfinite(q) || std::fabs(q) > static_cast<double>(kMaxSectorIndex)) {
        return false;
    }
    index = static_cast<std::int64_t>(q);
    local = std::fma(-static_cast<double>(index), size, x);
    if (local > half || (local == half && border_side(x, index, 0.5, size) >= 0.0)) {
        ++index;
        local = std::fma(-static_cast<double>(index), size, x);
    } else if (local < -half || (local == -half && border_side(x, index, -0.5, size) < 0.0)) {
        --index;
        local = std::fma(-static_cast<double>(index), size, x);
    }
    return index >= -kMaxSectorIndex && index <= kMaxSectorIndex;
}

std::string format_vector(const Eigen::Vector3d& v) {
    std::ostringstream out;
    out.precision(17);
    out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
    return out.str();
}

}  // namespace

double max_sector_size(double precision_radius) { return 2.0 * precision_radius / (3.0 * std::sqrt(3.0)); }

Status check_sector_size(double sector_size, double precision_radius) {
    double largest = max_sector_size(precision_radius);
    if (sector_size > largest) {
        std::ostringstream out;
        out.precision(10);
        out << "sector_size " << sector_size << " breaks the precision bound L <= 2r/(3*sqrt(3)) for "
            << "precision_radius " << precision_radius << ": the largest sector_size allowed is " << largest;
        return Error{out.str()};
    }
    return {};
}

SectorGrid::SectorGrid(double sector_size) : size_(sector_size), half_(0.5 * sector_size) {}

Expected<SectorPosition> SectorGrid::from_global(const Eigen::Vector3d& global) const {
    if (!global.allFinite()) {
        return Error{"position " + format_vector(global) + " is not finite"};
    }
    SectorPosition out;
    if (!split_axis(global.x(), size_, half_, out.sector.i, out.local.x()) ||
        !split_axis(global.y(), size_, half_, out.sector.j, out.local.y()) ||
        !split_axis(global.z(), size_, half_, out.sector.k, out.local.z())) {
        return Error{"position " + format_vector(global) + " lies beyond sector index 2^62"};
    }
    return out;
}

Eigen::Vector3d SectorGrid::to_global(const SectorPosition& p) const {
    return {std::fma(static_cast<double>(p.sector.i), size_, p.local.x()),
            std::fma(static_cast<double>(p.sector.j), size_, p.local.y()),
            std::fma(static_cast<double>(p.sector.k), size_, p.local.z())};
}

Expected<SectorPosition> SectorGrid::canonical(const SectorPosition& p) const {
    if (!p.local.allFinite()) {
        return Error{"local offset " + format_vector(p.local) + " is not finite"};
    }
    if (!in_range(p.sector)) {
        return Error{"sector index beyond 2^62"};
    }
    SectorPosition shift;
    if (!split_axis(p.local.x(), size_, half_, shift.sector.i, shift.local.x()) ||
        !split_axis(p.local.y(), size_, half_, shift.sector.j, shift.local.y()) ||
        !split_axis(p.local.z(), size_, half_, shift.sector.k, shift.local.z())) {
        return Error{"local offset " + format_vector(p.local) + " is too large"};
    }
    // Both terms are within 2^62, so the sum fits in int64; in_range then checks the result.
    SectorPosition out{p.sector + shift.sector, shift.local};
    if (!in_range(out.sector)) {
        return Error{"sector index beyond 2^62"};
    }
    return out;
}

double SectorGrid::wide_key_difference(std::int64_t a, std::int64_t b) {
    // Converting a 128-bit integer is a library call: only where 64 bits overflow. Both conversions round
    // the same value the same way.
    return static_cast<double>(static_cast<__int128>(a) - static_cast<__int128>(b));
}

SectorPosition SectorGrid::relocate(const SectorKey& frame, const Eigen::Vector3d& offset) const {
    SectorPosition shifted{frame, offset};
    Expected<SectorPosition> out = canonical(shifted);
    return out.ok() ? out.value() : shifted;
}

}  // namespace lpss
