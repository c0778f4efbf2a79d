#include "lpss_dds/sector_chain.hpp"

#include <iterator>

#include "lpss_dds/convert.hpp"

namespace lpss::dds {

bool SectorChain::accept(const wire::SectorFrame& sample) {
    std::set<std::uint64_t>& frames = accepted_[from_wire(sample.sector())];
    // A partial sample holds every change since its base: any sector state the reader holds from the base
    // on, and before the sample, becomes the sample's state once the sample is applied on it.
    const auto held = frames.lower_bound(sample.base());
    const bool usable = sample.complete() || (held != frames.end() && *held < sample.frame());
    if (!usable) {
        ++refused_;
        return false;
    }
    frames.insert(sample.frame());
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
    for (auto& [key, frames] : accepted_) {
        const auto later = frames.upper_bound(frame);
        if (later != frames.begin()) frames.erase(frames.begin(), std::prev(later));
    }
}

}  // namespace lpss::dds
