// Stage 2, cloning (paper section 3.2). Each body keeps its reach: the box it may sweep this frame,
// grown by the contact distance, and the foreign sectors that box enters (the border registry). For
// every sector about to be stepped, the pairs of bodies from different sectors whose reaches meet are
// found there, and each dynamic body gets, in its own sector, a clone of whatever it may touch:
// - static across borders and dynamic-static: a static body is cloned into the sector of a dynamic
//   body that reaches it;
// - dynamic-dynamic: both bodies are cloned into each other's sector.
// A clone takes its original's pose and velocity before every step; what happens to it during the
// step is discarded. Clones come from per-body pools, and a clone no longer needed in a stepped sector
// goes back to its pool. Bodies far from borders register nothing, so they cost nothing here.
#include <BulletCollision/BroadphaseCollision/btBroadphaseInterface.h>

#include <algorithm>
#include <cmath>

#include "bullet_convert.hpp"
#include "world_impl.hpp"

namespace lpss {

using engine::Aabb;
using engine::BodyRecord;
using engine::Clone;
using engine::Role;
using engine::Sector;
using engine::to_bt;
using engine::to_eigen;

namespace {

/// Collects the originals of a sector whose broadphase boxes overlap a query box.
struct OriginalsInBox : btBroadphaseAabbCallback {
    explicit OriginalsInBox(std::vector<std::uint32_t>& out) : found(out) {}
    bool process(const btBroadphaseProxy* proxy) override {
        const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
        if (object->getUserIndex2() == static_cast<int>(Role::Original)) {
            found.push_back(static_cast<std::uint32_t>(object->getUserIndex()));
        }
        return true;
    }
    std::vector<std::uint32_t>& found;
};

bool less_by_key(const SectorKey& a, const SectorKey& b) { return a < b; }

}  // namespace

void World::Impl::update_reach(std::uint32_t slot) {
    BodyRecord& rec = record(slot);
    if (!rec.alive || rec.plane) return;
    const btRigidBody& rb = *rec.rb;
    btVector3 lo, hi;
    rb.getCollisionShape()->getAabb(rb.getWorldTransform(), lo, hi);
    Aabb box{rec.sector->from_physics(lo), rec.sector->from_physics(hi)};
    if (rec.dynamic) {
        const double dt = settings.dt;
        Eigen::Vector3d travel = to_eigen(rb.getLinearVelocity()) * dt;
        box.min += travel.cwiseMin(0.0);
        box.max += travel.cwiseMax(0.0);
        box = box.grown(static_cast<double>(rb.getAngularVelocity().length()) * rec.bound_radius * dt);
    }
    rec.reach = box.grown(reach_margin);

    // Sector offsets (relative to the owner) covered by the reach on each axis.
    const double size = settings.sector_size;
    std::int64_t lo_idx[3], hi_idx[3];
    bool crosses = false;
    for (int a = 0; a < 3; ++a) {
        // A reach wider than a few sectors only happens for absurd speeds; clamp to keep it bounded.
        lo_idx[a] = static_cast<std::int64_t>(std::max(-4.0, std::floor(rec.reach.min[a] / size + 0.5)));
        hi_idx[a] = static_cast<std::int64_t>(std::min(4.0, std::floor(rec.reach.max[a] / size + 0.5)));
        crosses = crosses || lo_idx[a] != 0 || hi_idx[a] != 0;
    }
    if (!crosses) {
        if (!rec.border_cells.empty()) set_border_cells(slot, {});
        return;
    }
    std::vector<SectorKey> cells;
    const SectorKey& owner = rec.sector->key;
    for (std::int64_t i = lo_idx[0]; i <= hi_idx[0]; ++i) {
        for (std::int64_t j = lo_idx[1]; j <= hi_idx[1]; ++j) {
            for (std::int64_t k = lo_idx[2]; k <= hi_idx[2]; ++k) {
                if (i == 0 && j == 0 && k == 0) continue;
                SectorKey cell = owner + SectorKey{i, j, k};
                if (in_range(cell)) cells.push_back(cell);
            }
        }
    }
    set_border_cells(slot, std::move(cells));
}

void World::Impl::set_border_cells(std::uint32_t slot, std::vector<SectorKey> cells) {
    BodyRecord& rec = record(slot);
    std::sort(cells.begin(), cells.end(), less_by_key);
    if (cells == rec.border_cells) return;
    auto contains = [](const std::vector<SectorKey>& sorted, const SectorKey& key) {
        return std::binary_search(sorted.begin(), sorted.end(), key, less_by_key);
    };
    for (const SectorKey& old_cell : rec.border_cells) {
        if (contains(cells, old_cell)) continue;
        auto it = border_registry.find(old_cell);
        std::vector<std::uint32_t>& list = it->second;
        auto pos = std::find(list.begin(), list.end(), slot);
        *pos = list.back();
        list.pop_back();
        if (list.empty()) border_registry.erase(it);
    }
    for (const SectorKey& new_cell : cells) {
        if (!contains(rec.border_cells, new_cell)) border_registry[new_cell].push_back(slot);
    }
    if (rec.border_cells.empty() && !cells.empty()) ++border_bodies;
    if (!rec.border_cells.empty() && cells.empty()) --border_bodies;
    rec.border_cells = std::move(cells);
}

void World::Impl::require(std::uint32_t slot, Sector* target) { requirements.emplace_back(target, slot); }

void World::Impl::evaluate_cell(const SectorKey& cell) {
    auto it = border_registry.find(cell);
    if (it == border_registry.end()) return;
    const std::vector<std::uint32_t>& foreign = it->second;
    Sector* sector = find_sector(cell);
    const double dt = settings.dt;

    // Foreign bodies against the cell's own originals, found through the cell's broadphase. The query
    // grows by the distance the cell's fastest body may travel, which the broadphase boxes leave out.
    if (sector != nullptr) {
        const double grow = sector->max_speed * dt;
        for (std::uint32_t y : foreign) {
            const BodyRecord& ry = record(y);
            Aabb query = ry.reach.translated(grid.centre_offset(cell, ry.sector->key)).grown(grow);
            query = query.translated(-sector->anchor);
            found_scratch.clear();
            OriginalsInBox collect(found_scratch);
            sector->broadphase.aabbTest(to_bt(query.min), to_bt(query.max), collect);
            for (std::uint32_t x : found_scratch) {
                const BodyRecord& rx = record(x);
                if (!ry.dynamic && !rx.dynamic) continue;
                if (ry.dynamic) require(x, ry.sector);
                if (rx.dynamic) require(y, sector);
            }
        }
    }

    // Foreign bodies of different sectors meeting inside this cell: sweep and prune along x.
    if (foreign.size() < 2) return;
    box_scratch.clear();
    for (std::uint32_t y : foreign) {
        const BodyRecord& ry = record(y);
        box_scratch.emplace_back(ry.reach.translated(grid.centre_offset(cell, ry.sector->key)), y);
    }
    std::sort(box_scratch.begin(), box_scratch.end(),
              [](const auto& a, const auto& b) { return a.first.min.x() < b.first.min.x(); });
    for (std::size_t p = 0; p < box_scratch.size(); ++p) {
        const auto& [box_p, slot_p] = box_scratch[p];
        const BodyRecord& rp = record(slot_p);
        for (std::size_t q = p + 1; q < box_scratch.size() && box_scratch[q].first.min.x() <= box_p.max.x();
             ++q) {
            const auto& [box_q, slot_q] = box_scratch[q];
            const BodyRecord& rq = record(slot_q);
            if (rp.sector == rq.sector || (!rp.dynamic && !rq.dynamic) || !box_p.overlaps(box_q)) continue;
            if (rp.dynamic) require(slot_q, rp.sector);
            if (rq.dynamic) require(slot_p, rq.sector);
        }
    }
}

void World::Impl::clone_stage(const std::vector<std::uint32_t>& candidates) {
    if (!options.monolithic) {
        for (std::uint32_t slot : candidates)
            update_reach(slot);
    }

    // Sectors to step: those holding awake originals...
    step_set.clear();
    for (Sector* s : awake_list) {
        s->in_awake_list = false;
        if (s->awake) {
            s->stepping = true;
            step_set.push_back(s);
        }
    }
    awake_list.clear();
    if (options.monolithic) return;

    // ...plus those that receive a clone of an awake body. The cells to evaluate are the stepped sectors
    // and every cell that a body of a stepped sector reaches into; a sector that joins the set brings
    // its own cells, so repeat until the set stops growing.
    requirements.clear();
    evaluated_cells.clear();
    std::size_t first_new = 0;
    std::size_t checked = 0;
    while (first_new < step_set.size()) {
        live_cells.clear();
        for (std::size_t n = first_new; n < step_set.size(); ++n) {
            Sector* s = step_set[n];
            live_cells.push_back(s->key);
            for (std::uint32_t slot : s->originals) {
                const auto& cells = record(slot).border_cells;
                live_cells.insert(live_cells.end(), cells.begin(), cells.end());
            }
        }
        std::sort(live_cells.begin(), live_cells.end(), less_by_key);
        live_cells.erase(std::unique(live_cells.begin(), live_cells.end()), live_cells.end());
        first_new = step_set.size();
        for (const SectorKey& cell : live_cells) {
            if (std::binary_search(evaluated_cells.begin(), evaluated_cells.end(), cell, less_by_key))
                continue;
            evaluate_cell(cell);
        }
        std::vector<SectorKey> merged;
        merged.reserve(evaluated_cells.size() + live_cells.size());
        std::set_union(evaluated_cells.begin(), evaluated_cells.end(), live_cells.begin(), live_cells.end(),
                       std::back_inserter(merged), less_by_key);
        evaluated_cells.swap(merged);
        for (; checked < requirements.size(); ++checked) {
            auto [target, slot] = requirements[checked];
            const BodyRecord& source = record(slot);
            if (source.dynamic && source.rb->isActive() && !target->stepping) {
                target->stepping = true;
                step_set.push_back(target);
            }
        }
    }

    // Bring each stepped sector's clones to what is required: create the missing ones (in key order,
    // so that runs are reproducible), confirm the rest, and release the clones nobody needs any more.
    std::sort(requirements.begin(), requirements.end(), [&](const auto& a, const auto& b) {
        if (a.first != b.first) return a.first->key < b.first->key;
        return a.second < b.second;
    });
    requirements.erase(std::unique(requirements.begin(), requirements.end()), requirements.end());
    for (auto [target, slot] : requirements) {
        if (!target->stepping) continue;
        Clone* clone = record(slot).clone_in(target);
        if (clone == nullptr) clone = &create_clone(slot, *target);
        clone->confirmed_frame = frame;
    }
    for (Sector* s : step_set) {
        for (std::size_t n = s->hosted.size(); n-- > 0;) {
            std::uint32_t slot = s->hosted[n];
            BodyRecord& rec = record(slot);
            if (rec.plane) continue;
            Clone* clone = rec.clone_in(s);
            if (clone->confirmed_frame != frame) {
                release_clone(slot, *s);
            } else if (rec.dynamic) {
                sync_clone(rec, *clone);
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
    rec.clones.push_back(Clone{&host, std::move(rb), frame});
    Clone& clone = rec.clones.back();
    sync_clone(rec, clone);
    host.world.addRigidBody(clone.rb.get());
    host.hosted.push_back(slot);
    ++clone_count;
    return clone;
}

void World::Impl::release_clone(std::uint32_t slot, Sector& host) {
    BodyRecord& rec = record(slot);
    auto it =
        std::find_if(rec.clones.begin(), rec.clones.end(), [&](const Clone& c) { return c.host == &host; });
    std::unique_ptr<btRigidBody> rb = std::move(it->rb);
    *it = std::move(rec.clones.back());
    rec.clones.pop_back();
    host.world.removeRigidBody(rb.get());
    auto pos = std::find(host.hosted.begin(), host.hosted.end(), slot);
    *pos = host.hosted.back();
    host.hosted.pop_back();
    forget_contacts(host, rec.desc.id);
    --clone_count;
    if (rec.spare_clones.size() < options.max_spare_clones) {
        rec.spare_clones.push_back(std::move(rb));
        ++spare_count;
    }
}

void World::Impl::sync_clone(const BodyRecord& rec, Clone& clone) const {
    const btRigidBody& original = *rec.rb;
    btRigidBody& copy = *clone.rb;
    btTransform transform = original.getWorldTransform();
    transform.setOrigin(
        clone.host->to_physics(rec.local + grid.centre_offset(clone.host->key, rec.sector->key)));
    copy.setWorldTransform(transform);
    copy.setInterpolationWorldTransform(transform);
    copy.setLinearVelocity(original.getLinearVelocity());
    copy.setAngularVelocity(original.getAngularVelocity());
    copy.setInterpolationLinearVelocity(original.getLinearVelocity());
    copy.setInterpolationAngularVelocity(original.getAngularVelocity());
    copy.forceActivationState(original.getActivationState());
    copy.setDeactivationTime(original.getDeactivationTime());
    // The step refreshes only moving objects' broadphase boxes: a resting clone's box is refreshed here.
    if (!copy.isActive() && copy.getBroadphaseHandle() != nullptr) clone.host->world.updateSingleAabb(&copy);
}

}  // namespace lpss
