#include "lpss_dds/sector_mirror.hpp"

#include <algorithm>
#include <cstring>
#include <unordered_set>

namespace lpss::dds {
namespace {

auto by_id = [](const SectorMirror::Body& b, BodyId id) { return b.state.id < id; };

/// Where `id` is, or would go, in a sector's bodies, searched onwards from `from` (where the id looked up
/// before it was) when ids come in order, as a sample's do: steps of 1, 2, 4... then a binary search within
/// the last step. A binary search from the middle of a sector of hundreds of bodies missed the cache at
/// each of its first steps, for every body of every sample: most of what the mirror cost its reader.
std::size_t seek(const SectorMirror::Bodies& bodies, std::size_t from, BodyId id) {
    if (from > bodies.size() || (from > 0 && bodies[from - 1].state.id >= id)) from = 0;
    std::size_t step = 1;
    while (bodies.size() - from > step && bodies[from + step - 1].state.id < id) {
        from += step;
        step *= 2;
    }
    const auto first = bodies.begin() + static_cast<std::ptrdiff_t>(from);
    const auto last = bodies.begin() + static_cast<std::ptrdiff_t>(std::min(bodies.size(), from + step));
    return static_cast<std::size_t>(std::lower_bound(first, last, id, by_id) - bodies.begin());
}

/// The bytes that tell kinds apart (everything but id and name).
std::string key_of(const wire::BodyKind& k) {
    std::string key;
    auto add = [&key](const void* data, std::size_t size) {
        key.append(static_cast<const char*>(data), size);
    };
    const std::uint8_t shape = k.shape();
    const double values[] = {k.size().x(), k.size().y(), k.size().z(),   k.plane_offset(),
                             k.mass(),     k.friction(), k.restitution()};
    add(&shape, sizeof shape);
    add(values, sizeof values);
    const bool ccd = k.ccd();
    add(&ccd, sizeof ccd);
    for (const wire::Vec3d& p : k.hull_points()) {
        const double xyz[] = {p.x(), p.y(), p.z()};
        add(xyz, sizeof xyz);
    }
    return key;
}

}  // namespace

std::uint32_t SectorMirror::intern(const wire::BodyKind& kind) {
    std::string key = key_of(kind);
    auto it = index_.find(key);
    if (it != index_.end()) return it->second;
    wire::BodyKind shared = kind;
    shared.id(0);
    shared.name("");
    kinds_.push_back(std::move(shared));
    const auto n = static_cast<std::uint32_t>(kinds_.size() - 1);
    index_.emplace(std::move(key), n);
    return n;
}

void SectorMirror::put(Bodies& bodies, std::size_t at, const Body& body) {
    if (at != bodies.size() && bodies[at].state.id == body.state.id) {
        bodies[at] = body;
    } else {
        bodies.insert(bodies.begin() + static_cast<std::ptrdiff_t>(at), body);
    }
}

void SectorMirror::apply(const std::vector<const wire::SectorFrame*>& samples, std::vector<BodyId>* left) {
    std::vector<BodyId> gone;
    for (const wire::SectorFrame* sample : samples) {
        const SectorKey key = from_wire(sample->sector());
        Bodies& bodies = sectors_[key];
        // Kinds come for every body of a complete sample and for the arrivals of a partial one, in the
        // order of the bodies.
        std::unordered_map<BodyId, const wire::BodyKind*> kinds;
        for (const wire::BodyKind& k : sample->kinds())
            kinds[k.id()] = &k;
        if (sample->complete()) {
            Bodies fresh;
            fresh.reserve(sample->bodies().size());
            for (const wire::BodyState& wired : sample->bodies()) {
                const PackedBodyState b = pack(wired);
                auto kind = kinds.find(b.id);
                std::uint32_t index = 0;
                if (kind != kinds.end()) {
                    index = intern(*kind->second);
                    if (!kind->second->name().empty()) names_[b.id] = kind->second->name();
                } else {
                    auto old = std::lower_bound(bodies.begin(), bodies.end(), b.id, by_id);
                    if (old != bodies.end() && old->state.id == b.id) index = old->kind;
                }
                fresh.push_back(Body{b, index});
            }
            std::sort(fresh.begin(), fresh.end(),
                      [](const Body& x, const Body& y) { return x.state.id < y.state.id; });
            for (const Body& b : bodies) {
                auto at = std::lower_bound(fresh.begin(), fresh.end(), b.state.id, by_id);
                if (at == fresh.end() || at->state.id != b.state.id) gone.push_back(b.state.id);
            }
            bodies.swap(fresh);
        } else {
            std::size_t at = 0;
            for (std::uint64_t id : sample->departed()) {
                at = seek(bodies, at, id);
                if (at == bodies.size() || bodies[at].state.id != id) continue;
                bodies.erase(bodies.begin() + static_cast<std::ptrdiff_t>(at));
                gone.push_back(id);
            }
            at = 0;
            for (const wire::BodyState& wired : sample->bodies()) {
                const PackedBodyState b = pack(wired);
                at = seek(bodies, at, b.id);
                const bool held = at != bodies.size() && bodies[at].state.id == b.id;
                auto kind = kinds.find(b.id);
                if (kind != kinds.end()) {
                    if (!kind->second->name().empty()) names_[b.id] = kind->second->name();
                    put(bodies, at, Body{b, intern(*kind->second)});
                } else if (held) {
                    bodies[at].state = b;
                }
                // (neither: a body changed that this mirror does not hold, its base missed; not shown)
            }
        }
        if (bodies.empty()) sectors_.erase(key);
    }
    if (gone.empty()) return;  // most batches: nothing left a sector
    // Where the samples put each body that left a sector last: it is gone unless it is there at the end (it
    // crossed into another sector of the batch); a body changed by one sample and taken out by a later one
    // of the same sector is gone. Looked up for those bodies only: a map of every body the batch carries
    // was most of what a reader of a thousand moving bodies spent here a frame.
    std::sort(gone.begin(), gone.end());
    gone.erase(std::unique(gone.begin(), gone.end()), gone.end());
    std::unordered_map<BodyId, SectorKey> arrived;
    auto note = [&](BodyId id, const SectorKey& key) {
        if (std::binary_search(gone.begin(), gone.end(), id)) arrived[id] = key;
    };
    for (const wire::SectorFrame* sample : samples) {
        const SectorKey key = from_wire(sample->sector());
        for (const wire::BodyState& b : sample->bodies())
            note(b.id(), key);
    }
    for (BodyId id : gone) {
        if (auto at = arrived.find(id); at != arrived.end() && find(at->second, id)) continue;
        names_.erase(id);
        if (left) left->push_back(id);
    }
}

void SectorMirror::insert(const SectorKey& sector, const wire::BodyState& state, const wire::BodyKind& kind) {
    if (!kind.name().empty()) names_[state.id()] = kind.name();
    Bodies& bodies = sectors_[sector];
    const auto at = std::lower_bound(bodies.begin(), bodies.end(), state.id(), by_id);
    put(bodies, static_cast<std::size_t>(at - bodies.begin()), Body{pack(state), intern(kind)});
}

void SectorMirror::drop(const std::vector<SectorKey>& sectors, std::vector<BodyId>* left) {
    std::unordered_set<BodyId> gone;
    for (const SectorKey& key : sectors) {
        auto it = sectors_.find(key);
        if (it == sectors_.end()) continue;
        for (const Body& b : it->second)
            gone.insert(b.state.id);
        sectors_.erase(it);
    }
    if (gone.empty()) return;
    for (const auto& [key, bodies] : sectors_) {
        for (const Body& b : bodies)
            gone.erase(b.state.id);
    }
    std::vector<BodyId> ids(gone.begin(), gone.end());
    std::sort(ids.begin(), ids.end());
    for (BodyId id : ids) {
        names_.erase(id);
        if (left) left->push_back(id);
    }
}

wire::BodyKind SectorMirror::kind(const Body& body) const {
    wire::BodyKind out = kinds_.at(body.kind);
    out.id(body.state.id);
    if (auto name = names_.find(body.state.id); name != names_.end()) out.name(name->second);
    return out;
}

std::optional<wire::BodyKind> SectorMirror::kind(BodyId id) const {
    for (const auto& [key, bodies] : sectors_) {
        auto at = std::lower_bound(bodies.begin(), bodies.end(), id, by_id);
        if (at != bodies.end() && at->state.id == id) return kind(*at);
    }
    return std::nullopt;
}

std::optional<wire::BodyKind> SectorMirror::kind(const SectorKey& sector, BodyId id) const {
    const Body* body = find(sector, id);
    if (body == nullptr) return std::nullopt;
    return kind(*body);
}

const SectorMirror::Body* SectorMirror::find(const SectorKey& sector, BodyId id) const {
    auto bodies = sectors_.find(sector);
    if (bodies == sectors_.end()) return nullptr;
    auto at = std::lower_bound(bodies->second.begin(), bodies->second.end(), id, by_id);
    return at != bodies->second.end() && at->state.id == id ? &*at : nullptr;
}

}  // namespace lpss::dds
