// Stage 2, cloning (paper section 3.2). The border index (border_index.hpp) keeps, for every body, its
// *partners*: the bodies of
// other sectors whose fat reach boxes overlap its own. For every sector about to be stepped, each of its
// dynamic bodies needs, in that sector, a clone of each partner whose reach (its box swept by this
// frame's motion) meets its own. This covers the paper's three cases:
// - static across borders and dynamic-static: a static body is cloned into the sector of a dynamic body
//   that reaches it (while it does: a static clone in a sector with nothing moving near it is useless);
// - dynamic-dynamic: each body is cloned into the other's sector.
// A clone takes its original's pose and velocity before every step; what happens to it during the step
// is discarded. Clones come from per-body pools, and a clone no longer needed in a stepped sector goes
// back to its pool. Bodies far from borders have no partners and cost nothing here.
#include <algorithm>

#include <sstream>
#include "bullet_convert.hpp"

#include "prefetch.hpp"
#include "world_impl.hpp"

namespace lpss {

using engine::BodyRecord;
using engine::Clone;
using engine::kCloneLinger;
using engine::prefetch;
using engine::Role;
using engine::Sector;
using engine::SectorId;

void World::Impl::clone_stage(const std::vector<std::uint32_t>& candidates) {
    if (!options.monolithic) {
        for (std::uint32_t slot : candidates)
            border.update(slot, frame);
    }

    // Sectors to step: those holding awake originals...
    step_set.clear();
    for (SectorId id : awake_list) {
        Sector& s = sectors.at(id);
        s.in_awake_list = false;
        if (s.awake) {
            s.stepping = true;
            step_set.push_back(id);
        }
    }
    awake_list.clear();
    if (options.naive_sector_worlds) {
        sectors.for_each([&](Sector& s) {
            if (!s.stepping) {
                s.stepping = true;
                step_set.push_back(s.id);
            }
        });
    }
    if (options.monolithic) return;
    if (step_set.empty()) {
        bool awake_ghost = false;
        for (std::uint32_t slot : candidates) {
            const BodyRecord& rec = record(slot);
            awake_ghost =
                awake_ghost || (rec.alive && rec.dynamic && sector_of(rec).remote && rec.rb->isActive());
        }
        if (!awake_ghost) return;
    }

    // ...and those that receive a clone of an awake body: the sectors of its dynamic partners. Awake
    // ghosts (moved by set_state this frame) count too: their copies may push this process's bodies.
    // Every dynamic body of a stepped sector needs, there, a clone of each partner its reach meets; for
    // the awake sectors that is found in the same pass over their pairs (`host`: the sector the body is
    // stepped in, none for a ghost).
    // A clone required in a stepped sector: confirmed if it is there, else created below. Confirming twice
    // is harmless, so pairs are not sorted and made unique first (a sort of every pair met was a tenth of
    // the stage with half the bodies on borders); only the missing ones are.
    missing_scratch.clear();
    auto require = [&](SectorId host, std::uint32_t other) {
        if (Clone* clone = record(other).clone_in(host)) {
            clone->confirmed_frame = frame;
        } else {
            missing_scratch.emplace_back(host, other);
        }
    };
    // A pair of dynamic bodies of two awake sectors is met from both sides: it is checked once, from the
    // lower slot, for both (half the reach checks where everything moves).
    auto visited_from_both_sides = [&](const BodyRecord& partner) {
        return partner.dynamic && partner.border.listed_in == partner.sector && sector_of(partner).awake;
    };
    auto visit_pairs = [&](std::uint32_t slot, SectorId host) {
        const BodyRecord& rec = record(slot);
        if (!rec.dynamic) return;
        // Whether it pushes is read only where needed: the rigid body is a cache miss of its own (a third
        // of this loop's time at L = 32 when it was read for every body).
        int pushes = -1;
        const std::vector<std::uint32_t>& partners = border.partners(slot);
        for (std::size_t n = 0; n < partners.size(); ++n) {
            const std::uint32_t other = partners[n];
            if (n + 1 < partners.size()) {
                const BodyRecord& next = record(partners[n + 1]);
                prefetch(&next);
                prefetch(&next.border.reach);
                prefetch(&next.border.listed_in);
            }
            const BodyRecord& partner = record(other);
            if (host.valid() && visited_from_both_sides(partner)) {
                if (other < slot || !border.reaches_meet(slot, other, frame)) continue;
                require(host, other);
                require(partner.sector, slot);
                continue;
            }
            if (!border.reaches_meet(slot, other, frame)) continue;
            if (host.valid()) require(host, other);
            if (!partner.dynamic) continue;
            if (pushes < 0) pushes = rec.rb->isActive() ? 1 : 0;
            if (pushes == 0) continue;
            Sector& target = sector_of(partner);
            if (!target.stepping && !target.remote) {
                target.stepping = true;
                step_set.push_back(target.id);
            }
        }
    };
    // The walks below go from records to partner and clone lists to Bullet objects, each its own heap
    // block: they ask for what they will read a few steps ahead (perf, 10,000 drifting bodies at L = 8:
    // a third of the stage was this loop's own time, most of it waiting for those; asking ahead took the
    // stage's share of a running frame from 0.114-0.118 to 0.099-0.107, 0.054-0.055 to 0.046-0.049 at
    // L = 32, `lpss-bench --quick overhead` alternated three times).
    auto prefetch_record = [&](const std::vector<std::uint32_t>& slots, std::size_t at) {
        if (at >= slots.size()) return;
        const BodyRecord& rec = record(slots[at]);
        prefetch(&rec);
        prefetch(&rec.border.partners);
        prefetch(&rec.border.listed_in);
    };
    auto prefetch_lists = [&](const std::vector<std::uint32_t>& slots, std::size_t at) {
        if (at >= slots.size()) return;
        const BodyRecord& rec = record(slots[at]);
        prefetch(rec.border.partners.data());
        prefetch(rec.clones.data());
    };
    const std::size_t awake_sectors = step_set.size();
    for (std::size_t n = 0; n < awake_sectors; ++n) {
        const SectorId id = step_set[n];
        const std::vector<std::uint32_t>& partnered = border.partnered(sectors.at(id));
        for (std::size_t k = 0; k < partnered.size(); ++k) {
            prefetch_record(partnered, k + 4);
            prefetch_lists(partnered, k + 2);
            visit_pairs(partnered[k], id);
        }
    }
    for (std::uint32_t slot : candidates) {
        const BodyRecord& rec = record(slot);
        if (rec.alive && !rec.plane && sector_of(rec).remote) visit_pairs(slot, SectorId{});
    }
    // In key order: the partnered lists' order depends on history, and merge_contacts follows this one.
    std::sort(step_set.begin() + static_cast<std::ptrdiff_t>(awake_sectors), step_set.end(),
              [&](SectorId a, SectorId b) { return sectors.at(a).key < sectors.at(b).key; });
    for (std::size_t n = awake_sectors; n < step_set.size(); ++n) {
        const SectorId id = step_set[n];
        for (std::uint32_t slot : border.partnered(sectors.at(id))) {
            if (!record(slot).dynamic) continue;
            for (std::uint32_t other : border.partners(slot)) {
                if (border.reaches_meet(slot, other, frame)) require(id, other);
            }
        }
    }

    // Bring each stepped sector's clones to what is required: the existing ones were confirmed above;
    // create the missing ones (once each, in sector key and slot order, so that runs are reproducible), and
    // release the clones nobody needs any more.
    std::sort(missing_scratch.begin(), missing_scratch.end(), [&](const auto& a, const auto& b) {
        if (a.first != b.first) return sectors.at(a.first).key < sectors.at(b.first).key;
        return a.second < b.second;
    });
    missing_scratch.erase(std::unique(missing_scratch.begin(), missing_scratch.end()), missing_scratch.end());
    for (auto [target, slot] : missing_scratch)
        create_clone(slot, sectors.at(target));
    for (SectorId id : step_set) {
        Sector& s = sectors.at(id);
        for (std::size_t n = s.hosted.size(); n-- > 0;) {
            if (n >= 4) prefetch(&record(s.hosted[n - 4]));
            if (n >= 2) {
                const BodyRecord& next = record(s.hosted[n - 2]);
                prefetch(next.clones.data());
                prefetch(next.rb.get());
            }
            std::uint32_t slot = s.hosted[n];
            BodyRecord& rec = record(slot);
            if (rec.plane) continue;
            Clone* clone = rec.clone_in(id);
            // A clone is let go only after it has gone unneeded for a few frames: taking an object out of a
            // Bullet world scans the world's whole pair cache, and pairs near the edge of reach flicker.
            // A lingering clone is a true copy of its original, so it changes nothing but the cost.
            if (frame - clone->confirmed_frame > kCloneLinger) {
                release_clone(slot, s);
            } else if (rec.dynamic) {
                sync_clone(rec, *clone);
            }
        }
    }
    if (options.check_clones) check_clones();
}

void World::Impl::check_clones() {
    // Every pair, not only partners: a pair the border index failed to make partners is what this must
    // find (O(bodies^2): for tests). Two bodies of different sectors whose fat boxes overlap must be
    // partners (the index's own invariant), and where their reaches meet a stepped one needs a clone of
    // the other.
    auto describe = [&](std::uint32_t slot) {
        const BodyRecord& r = record(slot);
        const engine::Aabb& fat = r.border.fat;
        const engine::Aabb& reach = border.reach(slot, frame);
        const SectorKey& key = sectors.at(r.sector).key;
        std::ostringstream out;
        out << "body " << r.id << " in sector (" << key.i << "," << key.j << "," << key.k << "): fat box ("
            << fat.min.transpose() << ")-(" << fat.max.transpose() << ") in sector (" << r.border.fat_frame.i
            << "," << r.border.fat_frame.j << "," << r.border.fat_frame.k << "), reach ("
            << reach.min.transpose() << ")-(" << reach.max.transpose() << "), its sector's query growth "
            << border.query_growth(sectors.at(r.sector));
        return out.str();
    };
    for (SectorId id : step_set) {
        const Sector& s = sectors.at(id);
        for (std::uint32_t slot : s.originals) {
            const BodyRecord& rec = record(slot);
            if (!rec.dynamic || !rec.border.has_fat) continue;
            const std::vector<std::uint32_t>& partners = border.partners(slot);
            for (std::uint32_t other = 0; other < bodies.size() && clone_check_failure.empty(); ++other) {
                BodyRecord& them = record(other);
                if (!them.alive || them.plane || them.sector == id || !them.border.has_fat) continue;
                const bool partnered = std::find(partners.begin(), partners.end(), other) != partners.end();
                std::string missed;
                if (!partnered && border.fat_boxes_overlap(slot, other)) {
                    missed = "their fat boxes overlap, yet they are not partners";
                } else if (border.reaches_meet(slot, other, frame) && them.clone_in(id) == nullptr) {
                    missed = std::string("their reaches meet, yet the first has no clone of the other") +
                             (partnered ? "" : " (they are not partners)");
                }
                if (!missed.empty()) {
                    clone_check_failure = "frame " + std::to_string(frame) + ": " + missed + ": " +
                                          describe(slot) + "; " + describe(other);
                }
            }
        }
    }
}

Clone& World::Impl::create_clone(std::uint32_t slot, Sector& host) {
    BodyRecord& rec = record(slot);
    std::unique_ptr<btRigidBody> rb;
    if (!rec.spare_clones.empty()) {
        rb = std::move(rec.spare_clones.back());
        rec.spare_clones.pop_back();
        --spare_count;
    } else {
        btRigidBody::btRigidBodyConstructionInfo info(rec.mass, nullptr, rec.shape.get(), rec.inertia);
        info.m_friction = rec.rb->getFriction();
        info.m_restitution = rec.rb->getRestitution();
        rb = std::make_unique<btRigidBody>(info);
        rb->setUserIndex(static_cast<int>(slot));
        rb->setUserIndex2(static_cast<int>(Role::Clone));
        rb->setCcdMotionThreshold(rec.rb->getCcdMotionThreshold());
        rb->setCcdSweptSphereRadius(rec.rb->getCcdSweptSphereRadius());
    }
    rec.clones.push_back(Clone{host.id, std::move(rb), frame});
    Clone& clone = rec.clones.back();
    sync_clone(rec, clone);
    host.world.addRigidBody(clone.rb.get());
    host.hosted.push_back(slot);
    ++clone_count;
    ++clones_made;
    return clone;
}

void World::Impl::release_clone(std::uint32_t slot, Sector& host) {
    BodyRecord& rec = record(slot);
    auto it =
        std::find_if(rec.clones.begin(), rec.clones.end(), [&](const Clone& c) { return c.host == host.id; });
    std::unique_ptr<btRigidBody> rb = std::move(it->rb);
    *it = std::move(rec.clones.back());
    rec.clones.pop_back();
    host.world.removeRigidBody(rb.get());
    auto pos = std::find(host.hosted.begin(), host.hosted.end(), slot);
    *pos = host.hosted.back();
    host.hosted.pop_back();
    forget_contacts(host, rec.id);
    --clone_count;
    ++clones_released;
    if (rec.spare_clones.size() < options.max_spare_clones) {
        rec.spare_clones.push_back(std::move(rb));
        ++spare_count;
    }
}

void World::Impl::sync_clone(const BodyRecord& rec, Clone& clone) const {
    const btRigidBody& original = *rec.rb;
    btRigidBody& copy = *clone.rb;
    const Sector& host = sectors.at(clone.host);
    btTransform transform = original.getWorldTransform();
    transform.setOrigin(host.to_physics(rec.local + grid.centre_offset(host.key, sector_of(rec).key)));
    copy.setWorldTransform(transform);
    copy.setInterpolationWorldTransform(transform);
    copy.setLinearVelocity(original.getLinearVelocity());
    copy.setAngularVelocity(original.getAngularVelocity());
    copy.setInterpolationLinearVelocity(original.getLinearVelocity());
    copy.setInterpolationAngularVelocity(original.getAngularVelocity());
    copy.forceActivationState(original.getActivationState());
    copy.setDeactivationTime(original.getDeactivationTime());
    // The step refreshes only moving objects' broadphase boxes: a resting clone's box is refreshed here.
    if (!copy.isActive() && copy.getBroadphaseHandle() != nullptr) {
        // Bullet's world is not const-correct; the table hands out its sectors mutable.
        sectors.at(clone.host).world.updateSingleAabb(&copy);
    }
}

}  // namespace lpss
