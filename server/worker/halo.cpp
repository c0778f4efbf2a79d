#include "halo.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <unordered_set>

#include "lpss_dds/convert.hpp"

namespace lpss::worker {
namespace {

bool contains(const std::vector<std::uint32_t>& workers, std::uint32_t worker) {
    return std::binary_search(workers.begin(), workers.end(), worker);
}

}  // namespace

void Halo::follow(const SectorAssignment& current, const SectorAssignment& next) {
    if (current.epoch != current_.epoch) current_holders_.clear();
    if (next.epoch != next_.epoch) next_holders_.clear();
    current_ = current;
    next_ = next;
}

const std::vector<std::uint32_t>& Halo::holders(
    const SectorAssignment& assignment, const SectorKey& key,
    std::unordered_map<SectorKey, std::vector<std::uint32_t>, SectorKeyHash>& cache) {
    auto it = cache.find(key);
    if (it == cache.end()) it = cache.emplace(key, assignment.holders(key)).first;
    return it->second;
}

bool Halo::holds(const SectorKey& key) {
    if (contains(holders(current_, key, current_holders_), self_)) return true;
    return next_.epoch != current_.epoch && contains(holders(next_, key, next_holders_), self_);
}

std::vector<std::uint32_t> Halo::recipients(const SectorKey& key, std::uint64_t frame) {
    std::vector<std::uint32_t> out = holders(current_, key, current_holders_);
    if (switching_after(frame)) {
        for (std::uint32_t w : holders(next_, key, next_holders_)) {
            if (!contains(out, w)) out.push_back(w);
        }
        std::sort(out.begin(), out.end());
    }
    return out;
}

bool Halo::gains_holders(const SectorKey& key) {
    const std::vector<std::uint32_t>& now = holders(current_, key, current_holders_);
    for (std::uint32_t w : holders(next_, key, next_holders_)) {
        if (!contains(now, w)) return true;
    }
    return false;
}

void Halo::apply(World& world, const std::vector<const wire::SectorFrame*>& samples,
                 const std::vector<std::pair<std::uint64_t, BodyDesc>>& also) {
    std::vector<BodyId> left;
    std::unordered_set<BodyId> seen;
    struct Arrival {
        std::uint64_t rank;
        BodyDesc body;
        BodySnapshot state;
    };
    std::vector<Arrival> arrivals;
    for (const auto& [rank, body] : also)
        arrivals.push_back({rank, body, BodySnapshot{}});
    for (const wire::SectorFrame* sample : samples) {
        const SectorKey key = dds::from_wire(sample->sector());
        if (!holds(key)) continue;  // addressed to this worker under an assignment no longer in force
        if (sample->complete()) {
            // A complete sample replaces the sector: the ghosts it no longer shows left it.
            std::vector<BodyId> shown;
            for (const wire::BodyState& b : sample->bodies())
                shown.push_back(b.id());
            std::sort(shown.begin(), shown.end());
            for (const BodySnapshot& b : world.sector_bodies(key)) {
                if (!std::binary_search(shown.begin(), shown.end(), b.id)) left.push_back(b.id);
            }
        }
        for (std::uint64_t id : sample->departed())
            left.push_back(id);
        const bool precise = sample->offsets().size() == sample->bodies().size();
        std::size_t next_kind = 0;
        for (std::size_t n = 0; n < sample->bodies().size(); ++n) {
            const wire::BodyState& state = sample->bodies()[n];
            BodySnapshot snapshot = dds::from_wire(state, key);
            if (precise) snapshot.position.local = dds::from_wire(sample->offsets()[n]);
            seen.insert(snapshot.id);
            if (world.contains(snapshot.id)) {
                if (!world.is_ghost(snapshot.id)) continue;  // its own: never moved by others
                if (Status st = world.set_state(snapshot); !st)
                    spdlog::warn("ghost {}: {}", snapshot.id, st.error().message);
                continue;
            }
            // A body new to this worker: its kind travels with it (in the sample's order, arrivals only
            // in a partial sample).
            while (next_kind < sample->kinds().size() && sample->kinds()[next_kind].id() != snapshot.id)
                ++next_kind;
            if (next_kind == sample->kinds().size()) {
                spdlog::error("sector ({}, {}, {}): body {} arrived without its kind", key.i, key.j, key.k,
                              snapshot.id);
                next_kind = 0;
                continue;
            }
            const std::uint64_t rank = n < sample->ranks().size() ? sample->ranks()[n] : ~std::uint64_t{0};
            arrivals.push_back(
                {rank, dds::placed(dds::from_wire(sample->kinds()[next_kind]), snapshot), snapshot});
        }
    }
    // The world's first state comes ranked: bodies are added in the scene's order, as lpss-sim adds them.
    std::stable_sort(arrivals.begin(), arrivals.end(),
                     [](const Arrival& a, const Arrival& b) { return a.rank < b.rank; });
    for (const Arrival& a : arrivals) {
        if (world.contains(a.body.id)) continue;  // arrived twice in these samples
        if (Status st = world.add_body(a.body); !st) {
            spdlog::error("cannot hold body {}: {}", a.body.id, st.error().message);
            continue;
        }
        if (a.body.mass > 0.0 && a.state.id != 0)
            (void)world.set_state(a.state);  // asleep or awake, as its owner has it
    }
    for (BodyId id : left) {
        if (!seen.count(id) && world.contains(id) && world.is_ghost(id)) (void)world.remove_body(id);
    }
}

void Halo::drop_unheld(World& world) {
    for (const SectorKey& key : world.sectors()) {
        if (owns(key) || holds(key)) continue;
        for (const BodySnapshot& b : world.sector_bodies(key))
            (void)world.remove_body(b.id);
    }
}

}  // namespace lpss::worker
