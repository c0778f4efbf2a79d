// How far a sector's fat reach boxes reach beyond its bodies' broadphase boxes: a bound that follows the
// bodies there now, not every body that ever was.
//
// The border index finds a sector's bodies by fat box through the sector's Bullet broadphase, which holds
// their broadphase boxes; a query grown by the most any fat box there overhangs its body's box finds every
// fat box it overlaps. Kept as the running maximum, that growth only ever rose: one fast body once in a
// sector (a fat box stretched by half a second's travel) widened every later query there for good, long after
// it had gone (seen: 2.3 units in a million-body cluster world whose mean was 0.21). Here each body is
// counted in one bucket of a geometric scale (eight per doubling, so the bound is at most 9% over the
// largest overhang counted), and the bound is the top of the highest bucket that holds a body: it falls
// as soon as the bodies that raised it are gone or have new fat boxes.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace lpss::engine {

/// The buckets' scale: bucket b < 63 holds overhangs up to top(b) = unit * 2^((b - 62) / 8), bucket 63 the
/// larger ones. `unit`: a quarter sector serves (a fat box's slack and lookahead are at most an eighth each).
class OverhangScale {
public:
    static constexpr int kBuckets = 64;
    static constexpr std::uint8_t kNoBucket = 0xff;

    explicit OverhangScale(double unit) {
        for (int b = 0; b < kBuckets - 1; ++b)
            tops_[static_cast<std::size_t>(b)] = unit * std::exp2((b - (kBuckets - 2)) / 8.0);
    }
    /// The bucket of an overhang; `was`, its bucket before, is checked first (an overhang noted again mostly
    /// stays in it).
    std::uint8_t bucket_of(double overhang, std::uint8_t was = kNoBucket) const {
        if (was < kBuckets - 1 && overhang <= tops_[was] && (was == 0 || overhang > tops_[was - 1u]))
            return was;
        return static_cast<std::uint8_t>(std::lower_bound(tops_.begin(), tops_.end(), overhang) -
                                         tops_.begin());
    }
    double top(std::uint8_t bucket) const { return tops_[bucket]; }

private:
    std::array<double, kBuckets - 1> tops_{};
};

/// The bodies of one sector, counted by bucket.
class OverhangBound {
public:
    static constexpr int kBuckets = OverhangScale::kBuckets;

    void add(std::uint8_t bucket, double overhang) {
        if (counts_[bucket]++ == 0) occupied_ |= std::uint64_t{1} << bucket;
        if (bucket == kBuckets - 1) beyond_ = std::max(beyond_, overhang);
    }
    /// A body of the unbounded bucket, counted there already, whose overhang changed.
    void add_beyond(double overhang) { beyond_ = std::max(beyond_, overhang); }
    void remove(std::uint8_t bucket) {
        if (--counts_[bucket] != 0) return;
        occupied_ &= ~(std::uint64_t{1} << bucket);
        if (bucket == kBuckets - 1) beyond_ = 0.0;
    }
    /// At least the overhang of every body counted (0 with none).
    double bound(const OverhangScale& scale) const {
        if (occupied_ == 0) return 0.0;
        const auto highest = static_cast<std::uint8_t>(63 - __builtin_clzll(occupied_));
        return highest == kBuckets - 1 ? beyond_ : scale.top(highest);
    }

private:
    std::array<std::uint32_t, kBuckets> counts_{};
    std::uint64_t occupied_ = 0;  ///< bit b: counts_[b] > 0
    /// The largest overhang in the unbounded bucket since it was last empty (it rises, and falls only when
    /// the bucket empties: such fat boxes are rare, and short-lived).
    double beyond_ = 0.0;
};

}  // namespace lpss::engine
