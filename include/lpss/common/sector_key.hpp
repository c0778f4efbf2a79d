// The integer address of one sector of the grid. Exact at any distance: arithmetic on keys never
// touches floating point.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

namespace lpss {

/// Sector indices are limited to |index| <= kMaxSectorIndex so that key differences and neighbour
/// arithmetic can never overflow int64.
inline constexpr std::int64_t kMaxSectorIndex = std::int64_t{1} << 62;

/// Three signed 64-bit sector indices; sector (0,0,0) is centred on the origin.
struct SectorKey {
    std::int64_t i = 0;
    std::int64_t j = 0;
    std::int64_t k = 0;

    friend bool operator==(const SectorKey& a, const SectorKey& b) {
        return a.i == b.i && a.j == b.j && a.k == b.k;
    }
    friend bool operator!=(const SectorKey& a, const SectorKey& b) { return !(a == b); }
    /// Lexicographic order, for deterministic iteration over sets of sectors.
    friend bool operator<(const SectorKey& a, const SectorKey& b) {
        if (a.i != b.i) return a.i < b.i;
        if (a.j != b.j) return a.j < b.j;
        return a.k < b.k;
    }
    friend SectorKey operator+(const SectorKey& a, const SectorKey& b) {
        return {a.i + b.i, a.j + b.j, a.k + b.k};
    }
    friend SectorKey operator-(const SectorKey& a, const SectorKey& b) {
        return {a.i - b.i, a.j - b.j, a.k - b.k};
    }
};

/// True when every index lies within +-kMaxSectorIndex.
inline bool in_range(const SectorKey& key) {
    auto ok = [](std::int64_t v) { return v >= -kMaxSectorIndex && v <= kMaxSectorIndex; };
    return ok(key.i) && ok(key.j) && ok(key.k);
}

/// The Chebyshev distance between two sectors: 1 for the 26 neighbours of a sector.
inline std::int64_t sector_distance(const SectorKey& a, const SectorKey& b) {
    auto gap = [](std::int64_t x, std::int64_t y) { return x > y ? x - y : y - x; };
    const std::int64_t di = gap(a.i, b.i), dj = gap(a.j, b.j), dk = gap(a.k, b.k);
    return di > dj ? (di > dk ? di : dk) : (dj > dk ? dj : dk);
}

/// Hash with full avalanche so that neighbouring keys spread over the buckets of a hash map.
struct SectorKeyHash {
    std::size_t operator()(const SectorKey& key) const {
        auto mix = [](std::uint64_t x) {
            x ^= x >> 30;
            x *= 0xbf58476d1ce4e5b9ULL;
            x ^= x >> 27;
            x *= 0x94d049bb133111ebULL;
            x ^= x >> 31;
            return x;
        };
        std::uint64_t h = mix(static_cast<std::uint64_t>(key.i));
        h = mix(h ^ static_cast<std::uint64_t>(key.j));
        h = mix(h ^ static_cast<std::uint64_t>(key.k));
        return static_cast<std::size_t>(h);
    }
};

}  // namespace lpss
