#include "halo.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <unordered_map>

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

/// The bit of a Halo::near mask for the neighbour at `offset` (each index in -1..1; 13 is the sector).
std::uint32_t near_bit(const SectorKey& offset) {
    return 1u << static_cast<unsigned>(9 * (offset.i + 1) + 3 * (offset.j + 1) + (offset.k + 1));
}

/// Calls `each` with the neighbours a mask of Halo::near names (within the grid).
template <typename Each>
void for_each_near(const SectorKey& key, std::uint32_t near, Each&& each) {
    for (int bit = 0; bit < 27; ++bit) {
        if ((near & (1u << bit)) == 0) continue;
        const SectorKey neighbour{key.i + bit / 9 - 1, key.j + bit / 3 % 3 - 1, key.k + bit % 3 - 1};
        if (in_range(neighbour)) each(neighbour);
    }
}

}  // namespace

void Halo::follow(const SectorAssignment& current, const SectorAssignment& next, double largest_radius) {
    const bool workers_changed = current.workers != current_.workers || next.workers != next_.workers;
    if (current.epoch != current_.epoch || next.epoch != next_.epoch || workers_changed)
        assignment_changed_ = true;
    if (largest_radius != largest_radius_) reach_changed_ = true;
    current_ = current;
    next_ = next;
    largest_radius_ = largest_radius;
    if (!workers_changed) return;
    // A worker in neither assignment is gone: it holds nothing of this worker's any more. A worker that
    // comes back under its id (restarted) is a new recipient, to be sent every sector it needs whole (seen:
    // quiet sectors, never addressed again since the old one went, sent the newcomer partial samples it
    // could not use, and its first frame started without them, a body lost).
    for (auto it = addressed_.begin(); it != addressed_.end();) {
        std::vector<Recipient>& to = it->second;
        to.erase(std::remove_if(to.begin(), to.end(),
                                [&](const Recipient& r) {
                                    return !contains(current_.workers, r.worker) &&
                                           !contains(next_.workers, r.worker);
                                }),
                 to.end());
        it = to.empty() ? addressed_.erase(it) : std::next(it);
    }
}

std::uint32_t Halo::near(const WorldSettings& settings, const BodySnapshot& body, double radius) const {
    std::uint32_t mask = 0;
    const double reach = border_reach(settings, radius, largest_radius_, body.linear_velocity.norm());
    neighbours_within(body.position.local, settings.sector_size, reach,
                      [&](const SectorKey& d) { mask |= near_bit(d); });
    return mask;
}

std::vector<std::uint32_t> Halo::near(const World& world, const std::vector<BodySnapshot>& bodies,
                                      const std::vector<double>& radii) const {
    std::vector<std::uint32_t> out(bodies.size());
    for (std::size_t n = 0; n < bodies.size(); ++n)
        out[n] = near(world.settings(), bodies[n], radii[n]);
    return out;
}

bool Halo::comes_near_own(const SectorKey& key, std::uint32_t near) const {
    bool found = false;
    for_each_near(key, near, [&](const SectorKey& neighbour) { found = found || owns(neighbour); });
    return found;
}

std::uint32_t Halo::own_around(const SectorKey& key) const {
    std::uint32_t mask = 0;
    for_each_near(key, (1u << 27) - 1, [&](const SectorKey& neighbour) {
        if (owns_now_or_next(neighbour))
            mask |= near_bit({neighbour.i - key.i, neighbour.j - key.j, neighbour.k - key.k});
    });
    return mask;
}

std::uint32_t Halo::cached_own_around(const SectorKey& key) {
    auto found = own_around_.find(key);
    if (found == own_around_.end()) found = own_around_.emplace(key, own_around(key)).first;
    return found->second;
}

bool Halo::needs_ghost(const WorldSettings& settings, const SectorKey& key, const BodySnapshot& body,
                       double radius) {
    return comes_near(settings, cached_own_around(key), body, radius);
}

bool Halo::comes_near(const WorldSettings& settings, std::uint32_t own, const BodySnapshot& body,
                      double radius) const {
    if (own & near_bit({0, 0, 0})) return true;  // its own sector
    if (own == 0) return false;
    // The owner's mask came from the double offset; this one may come from its float (4e-6 units at
    // L = 128): a hundredth of a percent of the sector more leaves no body out that the owner counts in.
    return (near(settings, body, radius + 1e-4 * settings.sector_size) & own) != 0;
}

void Halo::forget_dormant(BodyId id) {
    auto at = dormant_sector_.find(id);
    if (at == dormant_sector_.end()) return;
    dormant_.erase({at->second, id});
    dormant_sector_.erase(at);
}

Halo::Addressing Halo::address(const SectorKey& key, std::uint32_t near, bool emptied, std::uint64_t frame) {
    const bool switching = switching_after(frame);
    Addressing out;
    for_each_near(key, near, [&](const SectorKey& neighbour) {
        add(out.recipients, current_.owner_of(neighbour));
        if (switching) add(out.recipients, next_.owner_of(neighbour));
    });
    if (switching) add(out.recipients, next_.owner_of(key));
    out.recipients.erase(std::remove(out.recipients.begin(), out.recipients.end(), self_),
                         out.recipients.end());
    std::sort(out.recipients.begin(), out.recipients.end());

    // A worker no longer needed keeps the sector for a while: a ball rolling along a border would
    // otherwise make its neighbour drop the sector and take it whole again and again.
    std::vector<Recipient>& before = addressed_[key];
    for (std::uint32_t w : out.recipients) {
        auto known =
            std::find_if(before.begin(), before.end(), [w](const Recipient& r) { return r.worker == w; });
        if (known == before.end()) {
            out.gained = true;
            before.push_back({w, frame});
        } else {
            known->needed = frame;
        }
    }
    for (auto it = before.begin(); it != before.end();) {
        if (frame - it->needed > kKeepUnneeded || emptied) {
            out.released.push_back(it->worker);
            it = before.erase(it);
        } else {
            if (!contains(out.recipients, it->worker)) out.recipients.push_back(it->worker);
            ++it;
        }
    }
    if (before.empty()) addressed_.erase(key);
    // Released workers get this sample too, to learn that they hold the sector no more.
    for (std::uint32_t w : out.released)
        add(out.recipients, w);
    std::sort(out.recipients.begin(), out.recipients.end());
    return out;
}

void Halo::addressed(const SectorKey& key, const std::vector<std::uint32_t>& recipients,
                     std::uint64_t frame) {
    std::vector<Recipient>& to = addressed_[key];
    to.clear();
    for (std::uint32_t w : recipients) {
        if (w != self_ && w != 0) to.push_back({w, frame});
    }
    if (to.empty()) addressed_.erase(key);
}

std::vector<double> radii_of(const World& world, const std::vector<BodySnapshot>& bodies) {
    std::vector<double> out;
    out.reserve(bodies.size());
    for (const BodySnapshot& b : bodies)
        out.push_back(world.bounding_radius(b.id));
    return out;
}

void Halo::apply(World& world, const std::vector<const wire::SectorFrame*>& samples,
                 const std::vector<std::pair<std::uint64_t, BodyDesc>>& also) {
    const WorldSettings& settings = world.settings();
    // Bodies that left a sector held here (or all of a sector that releases this worker), with the frame
    // they left in...
    std::unordered_map<BodyId, std::uint64_t> left;
    for (const wire::SectorFrame* sample : samples) {
        const SectorKey key = dds::from_wire(sample->sector());
        const bool released = std::find(sample->released().begin(), sample->released().end(), self_) !=
                              sample->released().end();
        if (released) {
            held_.erase(key);
        } else if (!owns(key)) {
            held_.insert(key);  // (the world's first state holds this worker's own sectors too)
        }
        const auto dormant_from =
            released || sample->complete() ? dormant_.lower_bound({key, 0}) : dormant_.end();
        const bool dormant_here = dormant_from != dormant_.end() && dormant_from->first.first == key;
        if (released || (sample->complete() && (world.has_sector(key) || dormant_here))) {
            // Released: every ghost of the sector goes. Complete: the ghosts it no longer shows left it.
            std::vector<BodyId> shown;
            if (!released) {
                for (const wire::BodyState& b : sample->bodies())
                    shown.push_back(b.id());
                std::sort(shown.begin(), shown.end());
            }
            auto gone = [&](BodyId id) {
                if (!std::binary_search(shown.begin(), shown.end(), id)) left[id] = sample->frame();
            };
            if (world.has_sector(key)) {
                for (const BodySnapshot& b : world.sector_bodies(key))
                    gone(b.id);
            }
            for (auto it = dormant_from; it != dormant_.end() && it->first.first == key; ++it)
                gone(it->first.second);
        }
        for (BodyId id : sample->departed())
            left[id] = std::max(left[id], sample->frame());
    }
    // ...unless a sample of these shows them in a sector held here in that frame or later (they crossed
    // into it). A body one sample moves and a later one takes out of the same sector is gone: these
    // samples may span several frames (a worker that fell behind).
    std::unordered_map<BodyId, std::uint64_t> seen;

    // States follow; bodies new here are built from their kinds, in the scene's order for the world's
    // first state (ranked), as lpss-sim adds them; bodies that need not be ghosts here wait as dormant.
    struct Arrival {
        std::uint64_t rank;
        const wire::SectorFrame* sample;  ///< null: `also[index]`, or `dormant`
        std::uint32_t index;              ///< the body in the sample
        std::uint32_t kind;               ///< its kind in the sample
        bool dormant = false;             ///< a dormant body, built from its record
        BodyId id = 0;                    ///< (the dormant body)
    };
    std::vector<Arrival> arrivals;
    for (std::uint32_t n = 0; n < also.size(); ++n)
        arrivals.push_back({also[n].first, nullptr, n, 0});
    constexpr std::uint64_t kUnranked = ~std::uint64_t{0};
    // The assignment or the reach changed: dormant bodies may come near now. Only those of sectors that
    // gained a neighbour of this worker's, unless every body reaches further: a rebalance need not look
    // at every dormant body of the worker (20,000-30,000 a worker at a million bodies on four).
    if (assignment_changed_ || reach_changed_) {
        auto recheck = [&](const SectorKey& key, std::uint32_t own) {
            for (auto it = dormant_.lower_bound({key, 0}); it != dormant_.end() && it->first.first == key;
                 ++it) {
                BodySnapshot state = dds::from_wire(it->second.state, key);
                state.position.local = it->second.local;
                if (comes_near(settings, own, state, it->second.radius))
                    arrivals.push_back({kUnranked, nullptr, 0, 0, true, it->first.second});
            }
        };
        for (auto& entry : own_around_) {
            const std::uint32_t before = entry.second;
            if (assignment_changed_) entry.second = own_around(entry.first);
            if (reach_changed_ || (entry.second & ~before) != 0) recheck(entry.first, entry.second);
        }
        assignment_changed_ = reach_changed_ = false;
    }
    for (const wire::SectorFrame* sample : samples) {
        const SectorKey key = dds::from_wire(sample->sector());
        if (std::find(sample->released().begin(), sample->released().end(), self_) !=
            sample->released().end())
            continue;
        const bool precise = sample->offsets().size() == sample->bodies().size();
        std::size_t next_kind = 0;
        for (std::uint32_t n = 0; n < sample->bodies().size(); ++n) {
            const BodyId id = sample->bodies()[n].id();
            if (!left.empty() && left.count(id)) seen[id] = std::max(seen[id], sample->frame());
            if (world.contains(id)) {
                if (!world.is_ghost(id)) continue;  // its own: never moved by others
                BodySnapshot snapshot = dds::from_wire(sample->bodies()[n], key);
                if (precise) snapshot.position.local = dds::from_wire(sample->offsets()[n]);
                if (Status st = world.set_state(snapshot); !st)
                    spdlog::warn("ghost {}: {}", id, st.error().message);
                continue;
            }
            BodySnapshot state = dds::from_wire(sample->bodies()[n], key);
            if (precise) state.position.local = dds::from_wire(sample->offsets()[n]);
            if (auto was = dormant_sector_.find(id); was != dormant_sector_.end()) {
                // A dormant body moved (or its sector came whole again): its record follows, in the
                // sector it is in now.
                auto rec = dormant_.find({was->second, id});
                if (was->second != key) {  // moved to another held sector: re-keyed
                    auto node = dormant_.extract(rec);
                    node.key() = {key, id};
                    rec = dormant_.insert(std::move(node)).position;
                    was->second = key;
                }
                rec->second.state = sample->bodies()[n];
                rec->second.local = state.position.local;
                if (needs_ghost(settings, key, state, rec->second.radius))
                    arrivals.push_back({kUnranked, nullptr, 0, 0, true, id});
                continue;
            }
            // A body new to this worker: its kind travels with it (in the sample's order, arrivals only in a
            // partial sample).
            while (next_kind < sample->kinds().size() && sample->kinds()[next_kind].id() != id)
                ++next_kind;
            if (next_kind == sample->kinds().size()) {
                spdlog::error("sector ({}, {}, {}): body {} arrived without its kind", key.i, key.j, key.k,
                              id);
                next_kind = 0;
                continue;
            }
            const std::uint64_t rank = n < sample->ranks().size() ? sample->ranks()[n] : kUnranked;
            const wire::BodyKind& kind = sample->kinds()[next_kind];
            // (Its own or next sector's bodies, the world's first state's most, are all built: no radius.)
            const std::uint32_t own = cached_own_around(key);
            const double radius =
                own & near_bit({0, 0, 0}) ? 0.0 : bounding_radius(dds::from_wire(kind).shape);
            if (comes_near(settings, own, state, radius)) {
                arrivals.push_back({rank, sample, n, static_cast<std::uint32_t>(next_kind)});
            } else {
                dormant_.emplace(DormantKey{key, id},
                                 Dormant{sample->bodies()[n], state.position.local, kind, radius});
                dormant_sector_[id] = key;
            }
        }
    }
    std::stable_sort(arrivals.begin(), arrivals.end(),
                     [](const Arrival& a, const Arrival& b) { return a.rank < b.rank; });
    const bool sleeping = settings.sleeping;
    // Room for the dormant bodies too, so that building them one by one later never moves the engine's
    // tables (seen: a worker of 250,000 bodies stalled 0.3 s in the frame that outgrew them). Room not
    // used is address space, not memory: its pages are never touched.
    const std::size_t room = world.body_count() + arrivals.size() + dormant_.size();
    if (room > reserved_) {
        reserved_ = room + room / 4;  // and handoffs and commands add bodies too
        world.reserve(reserved_);
    }
    for (const Arrival& a : arrivals) {
        if (a.sample == nullptr && !a.dormant) {
            (void)world.add_body(also[a.index].second);
            continue;
        }
        BodySnapshot state;
        BodyDesc body;
        if (a.dormant) {
            auto at = dormant_sector_.find(a.id);
            if (at == dormant_sector_.end()) continue;  // built already, from another arrival
            const Dormant& rec = dormant_.at({at->second, a.id});
            state = dds::from_wire(rec.state, at->second);
            state.position.local = rec.local;
            body = dds::placed(dds::from_wire(rec.kind), state);
            forget_dormant(a.id);
        } else {
            const wire::SectorFrame& sample = *a.sample;
            state = dds::from_wire(sample.bodies()[a.index], dds::from_wire(sample.sector()));
            if (sample.offsets().size() == sample.bodies().size())
                state.position.local = dds::from_wire(sample.offsets()[a.index]);
            body = dds::placed(dds::from_wire(sample.kinds()[a.kind]), state);
        }
        if (world.contains(state.id)) continue;  // arrived twice in these samples
        // At rest as its owner has it: a body that sleeps there starts asleep here (the world's first
        // state); any other arrival takes its owner's state exactly below.
        body.asleep = sleeping && body.mass > 0.0 && !state.awake && state.linear_velocity.isZero() &&
                      state.angular_velocity.isZero();
        if (Status st = world.add_body(body); !st) {
            spdlog::error("cannot hold body {}: {}", body.id, st.error().message);
            continue;
        }
        if (body.mass > 0.0 && a.rank == kUnranked) (void)world.set_state(state);
    }
    for (const auto& [id, frame] : left) {
        auto shown = seen.find(id);
        if (shown != seen.end() && shown->second >= frame) continue;
        if (world.contains(id) && world.is_ghost(id)) (void)world.remove_body(id);
        forget_dormant(id);
    }
}

}  // namespace lpss::worker
