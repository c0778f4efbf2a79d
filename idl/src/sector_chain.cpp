#include "lpss_dds/sector_chain.hpp"

#include <algorithm>
#include <iterator>

#include "lpss_dds/convert.hpp"

namespace lpss::dds {

bool SectorChain::stale(const wire::SectorFrame& sample) const {
    if (sample.frame() > applied_) return false;
    auto it = accepted_.find(from_wire(sample.sector()));
    return it != accepted_.end() && !it->second.empty() && *it->second.rbegin() >= sample.frame();
}

bool SectorChain::accept(const wire::SectorFrame& sample) {
    if (stale(sample)) return false;
    std::set<std::uint64_t>& frames = accepted_[from_wire(sample.sector())];
    // A partial sample holds every change since its base: any sector state the reader holds from the base
    // on, and before the sample, becomes the sample's state once the sample is applied on it.
    const auto held = frames.lower_bound(sample.base());
    const bool usable = sample.complete() || (held != frames.end() && *held < sample.frame());
    if (!usable) {
        ++refused_;
        return false;
    }
    if (frames.insert(sample.frame()).second && frames.size() == 2)
        several_.push_back(from_wire(sample.sector()));
    return true;
}

bool SectorChain::holds(const SectorKey& sector, std::uint64_t from, std::uint64_t to) const {
    auto it = accepted_.find(sector);
    if (it == accepted_.end()) return false;
    const auto at = it->second.lower_bound(from);
    return at != it->second.end() && *at <= to;
}

std::uint64_t SectorChain::newest(const SectorKey& sector) const {
    auto it = accepted_.find(sector);
    return it == accepted_.end() || it->second.empty() ? 0 : *it->second.rbegin();
}

void SectorChain::forget_applied(std::uint64_t frame) {
    applied_ = std::max(applied_, frame);
    std::vector<SectorKey> still;
    for (const SectorKey& key : several_) {
        std::set<std::uint64_t>& frames = accepted_.at(key);
        const auto later = frames.upper_bound(frame);
        if (later != frames.begin()) frames.erase(frames.begin(), std::prev(later));
        if (frames.size() > 1) still.push_back(key);
    }
    several_ = std::move(still);
}

}  // namespace lpss::dds
