// The bodies of each sector as a reader rebuilds them from the samples of lpss/sector_frames: complete
// samples replace a sector, partial ones update it. Apply only samples a SectorChain accepted, in frame
// order. A body the wire shows in two sectors is in both here: the mirror hides no fault of the writers.
#pragma once

#include <map>
#include <unordered_map>
#include <vector>

#include "lpss.h"
#include "lpss/common/body_desc.hpp"
#include "lpss/common/sector_key.hpp"

namespace lpss::dds {

class SectorMirror {
public:
    using Bodies = std::map<BodyId, wire::BodyState>;
    using Sectors = std::unordered_map<SectorKey, Bodies, SectorKeyHash>;

    /// Applies a sample; the bodies that left the sector with it are added to `left` if given.
    void apply(const wire::SectorFrame& sample, std::vector<BodyId>* left = nullptr);
    const Sectors& sectors() const { return sectors_; }

private:
    Sectors sectors_;
};

}  // namespace lpss::dds
