#include "lpss_dds/sector_mirror.hpp"

#include <algorithm>
#include <unordered_set>

#include "lpss_dds/convert.hpp"

namespace lpss::dds {

void SectorMirror::apply(const std::vector<const wire::SectorFrame*>& samples, std::vector<BodyId>* left) {
    std::vector<BodyId> gone;
    std::unordered_set<BodyId> arrived;
    for (const wire::SectorFrame* sample : samples) {
        const SectorKey key = from_wire(sample->sector());
        Bodies& bodies = sectors_[key];
        if (sample->complete()) {
            std::vector<BodyId> kept;
            for (const wire::BodyState& b : sample->bodies())
                kept.push_back(b.id());
            std::sort(kept.begin(), kept.end());
            for (const auto& [id, state] : bodies) {
                if (!std::binary_search(kept.begin(), kept.end(), id)) gone.push_back(id);
            }
            bodies.clear();
        }
        for (std::uint64_t id : sample->departed()) {
            if (bodies.erase(id)) gone.push_back(id);
        }
        for (const wire::BodyState& b : sample->bodies()) {
            bodies[b.id()] = b;
            arrived.insert(b.id());
        }
        for (const wire::BodyKind& k : sample->kinds())
            kinds_[k.id()] = k;
        if (bodies.empty()) sectors_.erase(key);
    }
    for (BodyId id : gone) {
        if (arrived.count(id)) continue;
        kinds_.erase(id);
        if (left) left->push_back(id);
    }
}

void SectorMirror::insert(const SectorKey& sector, const wire::BodyState& state, const wire::BodyKind& kind) {
    sectors_[sector][state.id()] = state;
    kinds_[state.id()] = kind;
}

const wire::BodyKind* SectorMirror::kind(BodyId id) const {
    auto it = kinds_.find(id);
    return it == kinds_.end() ? nullptr : &it->second;
}

}  // namespace lpss::dds
