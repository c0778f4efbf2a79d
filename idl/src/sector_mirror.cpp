#include "lpss_dds/sector_mirror.hpp"

#include <algorithm>

#include "lpss_dds/convert.hpp"

namespace lpss::dds {

void SectorMirror::apply(const wire::SectorFrame& sample, std::vector<BodyId>* left) {
    const SectorKey key = from_wire(sample.sector());
    Bodies& bodies = sectors_[key];
    if (sample.complete()) {
        if (left) {
            std::vector<BodyId> kept;
            for (const wire::BodyState& b : sample.bodies())
                kept.push_back(b.id());
            std::sort(kept.begin(), kept.end());
            for (const auto& [id, state] : bodies) {
                if (!std::binary_search(kept.begin(), kept.end(), id)) left->push_back(id);
            }
        }
        bodies.clear();
    }
    for (std::uint64_t id : sample.departed()) {
        if (bodies.erase(id) && left) left->push_back(id);
    }
    for (const wire::BodyState& b : sample.bodies())
        bodies[b.id()] = b;
    if (bodies.empty()) sectors_.erase(key);
}

}  // namespace lpss::dds
