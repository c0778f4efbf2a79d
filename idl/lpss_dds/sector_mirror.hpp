// The bodies of each sector as a reader rebuilds them from the samples of lpss/sector_frames: complete
// samples replace a sector, partial ones update it; and what each body is (its kind), which travels with
// it. Apply only samples a SectorChain accepted, in frame order. A body the wire shows in two sectors is
// in both here: the mirror hides no fault of the writers.
//
// Compact, for readers that hold a whole world (the coordinator, whole-world clients): a body is its wire
// state as a plain value and the index of its kind among the distinct kinds seen (most bodies share one);
// names, which are the body's own, are kept apart for the bodies that have one. Plain values, because each
// sample's bodies are searched, copied and moved here: with fastddsgen's types (an accessor call for each
// id, a copy through nested members) that was most of what the coordinator did with a sample.
#pragma once

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "lpss.h"
#include "lpss/common/body_desc.hpp"
#include "lpss/common/sector_key.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::dds {

class SectorMirror {
public:
    struct Body {
        PackedBodyState state;
        std::uint32_t kind = 0;  ///< index into the distinct kinds
    };
    using Bodies = std::vector<Body>;  ///< sorted by id
    using Sectors = std::unordered_map<SectorKey, Bodies, SectorKeyHash>;

    /// Applies samples (in frame order) as one batch. Bodies that left their sector in it and arrived in
    /// no other sector of the batch have left what this mirror holds: their names are forgotten, and
    /// their ids added to `left` if given.
    void apply(const std::vector<const wire::SectorFrame*>& samples, std::vector<BodyId>* left = nullptr);
    /// Puts a body in a sector (one that left a sector and was never seen arriving, such as a body handed
    /// to a worker that died before it published it).
    void insert(const SectorKey& sector, const wire::BodyState& state, const wire::BodyKind& kind);
    /// Takes out sectors the reader learned are empty (no inventory lists them, and the samples that
    /// emptied them were lost: see Client). Their bodies have left what this mirror holds unless another
    /// sector holds them too (the sector's state was stale); their ids go to `left` if given. Looks at
    /// every sector: for occasional use.
    void drop(const std::vector<SectorKey>& sectors, std::vector<BodyId>* left = nullptr);

    const Sectors& sectors() const { return sectors_; }
    /// What a body held here is, with its id and name.
    wire::BodyKind kind(const Body& body) const;
    /// What a body is, found by id among every sector (for occasional use), or nothing.
    std::optional<wire::BodyKind> kind(BodyId id) const;
    /// What a body is, found in the sector that holds it, or nothing.
    std::optional<wire::BodyKind> kind(const SectorKey& sector, BodyId id) const;
    /// A body as the sector holds it, or null (valid until the next apply, insert or drop).
    const Body* find(const SectorKey& sector, BodyId id) const;
    std::size_t distinct_kinds() const { return kinds_.size(); }

private:
    std::uint32_t intern(const wire::BodyKind& kind);
    /// Puts a body in a sector's sorted list at `at`, the place of its id (the first body whose id is not
    /// less): in place of the body of that id, or before it.
    static void put(Bodies& bodies, std::size_t at, const Body& body);

    Sectors sectors_;
    std::vector<wire::BodyKind> kinds_;                     ///< distinct, without id and name
    std::unordered_map<std::string, std::uint32_t> index_;  ///< a kind's bytes -> its place in kinds_
    std::unordered_map<BodyId, std::string> names_;         ///< the bodies that have a name
};

}  // namespace lpss::dds
