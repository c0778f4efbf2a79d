// The bodies of each sector as a reader rebuilds them from the samples of lpss/sector_frames: complete
// samples replace a sector, partial ones update it; and what each body is (its kind), which travels with
// it. Apply only samples a SectorChain accepted, in frame order. A body the wire shows in two sectors is
// in both here: the mirror hides no fault of the writers.
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

    /// Applies samples (in frame order) as one batch. Bodies that left their sector in it and arrived in
    /// no other sector of the batch have left what this mirror holds: their kinds are forgotten, and
    /// their ids added to `left` if given.
    void apply(const std::vector<const wire::SectorFrame*>& samples, std::vector<BodyId>* left = nullptr);
    /// Puts a body in a sector (one that left a sector and was never seen arriving, such as a body handed
    /// to a worker that died before it published it).
    void insert(const SectorKey& sector, const wire::BodyState& state, const wire::BodyKind& kind);

    const Sectors& sectors() const { return sectors_; }
    /// What a body held here is, or nothing.
    const wire::BodyKind* kind(BodyId id) const;

private:
    Sectors sectors_;
    std::unordered_map<BodyId, wire::BodyKind> kinds_;
};

}  // namespace lpss::dds
