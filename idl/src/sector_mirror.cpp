#include "lpss_dds/sector_mirror.hpp"

#include "lpss_dds/convert.hpp"

namespace lpss::dds {

void SectorMirror::apply(const wire::SectorFrame& sample) {
    const SectorKey key = from_wire(sample.sector());
    Bodies& bodies = sectors_[key];
    if (sample.complete()) bodies.clear();
    for (std::uint64_t id : sample.departed())
        bodies.erase(id);
    for (const wire::BodyState& b : sample.bodies())
        bodies[b.id()] = b;
    if (bodies.empty()) sectors_.erase(key);
}

}  // namespace lpss::dds
