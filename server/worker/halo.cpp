#include "halo.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <unordered_set>

#include "lpss/common/border_reach.hpp"
#include "lpss_dds/convert.hpp"

namespace lpss::worker {
namespace {

bool contains(const std::vector<std::uint32_t>& workers, std::uint32_t worker) {
    return std::find(workers.begin(), workers.end(), worker) != workers.end();
}

void add(std::vector<std::uint32_t>& workers, std::uint32_t worker) {
    if (worker != 0 && !contains(workers, worker)) workers.push_back(worker);
}

}  // namespace

void Halo::follow(const SectorAssignment& current, const SectorAssignment& next, double largest_radius) {
    current_ = current;
    next_ = next;
    largest_radius_ = largest_radius;
}

std::uint32_t Halo::near(const WorldSettings& settings, const BodySnapshot& body, double radius) const {
    std::uint32_t mask = 0;
    const double reach = border_reach(settings, radius, largest_radius_, body.linear_velocity.norm());
    neighbours_within(body.position.local, settings.sector_size, reach, [&](const SectorKey& d) {
        mask |= 1u << static_cast<unsigned>(9 * (d.i + 1) + 3 * (d.j + 1) + (d.k + 1));
    });
    return mask;
}

std::vector<std::uint32_t> Halo::near(const World& world, const std::vector<BodySnapshot>& bodies,
                                      const std::vector<double>& radii) const {
    std::vector<std::uint32_t> out(bodies.size());
    for (std::size_t n = 0; n < bodies.size(); ++n)
        out[n] = near(world.settings(), bodies[n], radii[n]);
    return out;
}

Halo::Addressing Halo::address(const SectorKey& key, std::uint32_t near, std::uint64_t frame) {
    const bool switching = switching_after(frame);
    Addressing out;
    for (int bit = 0; bit < 27; ++bit) {
        if ((near & (1u << bit)) == 0) continue;
        const SectorKey neighbour{key.i + bit / 9 - 1, key.j + bit / 3 % 3 - 1, key.k + bit % 3 - 1};
        if (!in_range(neighbour)) continue;
        add(out.recipients, current_.owner_of(neighbour));
        if (switching) add(out.recipients, next_.owner_of(neighbour));
    }
    if (switching) add(out.recipients, next_.owner_of(key));
    out.recipients.erase(std::remove(out.recipients.begin(), out.recipients.end(), self_),
                         out.recipients.end());
    std::sort(out.recipients.begin(), out.recipients.end());

    std::vector<std::uint32_t>& before = addressed_[key];
    for (std::uint32_t w : out.recipients)
        out.gained = out.gained || !contains(before, w);
    for (std::uint32_t w : before) {
        if (!contains(out.recipients, w)) out.released.push_back(w);
    }
    before = out.recipients;
    if (before.empty()) addressed_.erase(key);
    // Released workers get this sample too, to learn that they hold the sector no more.
    for (std::uint32_t w : out.released)
        add(out.recipients, w);
    std::sort(out.recipients.begin(), out.recipients.end());
    return out;
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
        const bool released = std::find(sample->released().begin(), sample->released().end(), self_) !=
                              sample->released().end();
        if (released || sample->complete()) {
            // Released: every ghost of the sector goes. Complete: the ghosts it no longer shows left it.
            std::vector<BodyId> shown;
            if (!released) {
                for (const wire::BodyState& b : sample->bodies())
                    shown.push_back(b.id());
                std::sort(shown.begin(), shown.end());
            }
            for (const BodySnapshot& b : world.sector_bodies(key)) {
                if (!std::binary_search(shown.begin(), shown.end(), b.id)) left.push_back(b.id);
            }
        }
        if (released) {
            held_.erase(key);
            continue;
        }
        if (!owns(key)) held_.insert(key);  // the world's first state holds this worker's own sectors too
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

}  // namespace lpss::worker
