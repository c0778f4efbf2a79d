// The border index (border_index.hpp says what it keeps and why).
#include "border_index.hpp"

#include <algorithm>
#include <cmath>

#include <BulletCollision/BroadphaseCollision/btBroadphaseInterface.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include "bullet_convert.hpp"
#include "sector.hpp"

namespace lpss::engine {

namespace {

btDbvtVolume volume(const Aabb& box) { return btDbvtVolume::FromMM(to_bt(box.min), to_bt(box.max)); }

std::uint32_t slot_of_leaf(const btDbvtNode* leaf) {
    return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(leaf->data));
}

struct CollectLeaves : btDbvt::ICollide {
    explicit CollectLeaves(std::vector<std::uint32_t>& out) : found(out) {}
    void Process(const btDbvtNode* leaf) override { found.push_back(slot_of_leaf(leaf)); }
    std::vector<std::uint32_t>& found;
};

/// Collects the originals of a sector whose broadphase boxes overlap a query box.
struct CollectOriginals : btBroadphaseAabbCallback {
    explicit CollectOriginals(std::vector<std::uint32_t>& out) : found(out) {}
    bool process(const btBroadphaseProxy* proxy) override {
        const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
        if (object->getUserIndex2() == static_cast<int>(Role::Original)) {
            found.push_back(static_cast<std::uint32_t>(object->getUserIndex()));
        }
        return true;
    }
    std::vector<std::uint32_t>& found;
};

}  // namespace

BorderIndex::BorderIndex(const WorldSettings& settings, std::vector<BodyRecord>& bodies, SectorTable& sectors)
    : grid_(settings.sector_size),
      sector_size_(settings.sector_size),
      reach_dt_(settings.dt * (1.0 + 1.0 / settings.substeps_per_frame())),
      frame_dt_(settings.dt),
      // Bullet tracks contact points up to gContactBreakingThreshold apart; its broadphase boxes carry
      // that margin once refreshed by a step, not when just inserted. Reach boxes add twice the margin.
      reach_margin_(2.0 * gContactBreakingThreshold + 0.01),
      // A sector's anchor moving makes its broadphase boxes anew from float positions: they may differ
      // from those measured by the rounding of coordinates up to a few sectors out.
      overhang_tolerance_(1e-5 * settings.sector_size + 1e-4),
      overhang_scale_(settings.sector_size / 4.0),
      bodies_(bodies),
      sectors_(sectors) {}

Aabb BorderIndex::tight_reach(const BodyRecord& rec) const {
    // Bullet's broadphase box (current pose, plus its contact threshold once refreshed by a step) as of
    // the start of the last physics step, swept by the motion of that step and of the coming frame.
    const btRigidBody& rb = *rec.rb;
    const btBroadphaseProxy* proxy = rb.getBroadphaseHandle();
    const Sector& sector = sector_of(rec);
    Aabb box{sector.from_physics(proxy->m_aabbMin), sector.from_physics(proxy->m_aabbMax)};
    if (rec.dynamic) {
        const double dt = reach_dt_;
        const Eigen::Vector3d travel = to_eigen(rb.getLinearVelocity()) * dt;
        box.min += travel.cwiseMin(0.0);
        box.max += travel.cwiseMax(0.0);
        box = box.grown(static_cast<double>(rb.getAngularVelocity().length()) * rec.bound_radius * dt);
    }
    return box.grown(reach_margin_);
}

const Aabb& BorderIndex::current_reach(std::uint32_t slot, std::uint64_t frame) {
    BodyRecord& rec = bodies_[slot];
    BorderEntry& entry = rec.border;
    if (entry.reach_frame != frame) {
        entry.reach = tight_reach(rec);
        entry.reach_frame = frame;
    }
    return entry.reach;
}

bool BorderIndex::prepare_reach(std::uint32_t slot, std::uint64_t frame) {
    const Aabb& tight = current_reach(slot, frame);
    BodyRecord& rec = bodies_[slot];
    const BorderEntry& entry = rec.border;
    Sector& sector = sector_of(rec);
    // What update checks before it returns early, and what relist would find to do.
    if (!entry.has_fat || !(entry.fat_frame == sector.key) || !entry.fat.contains(tight)) return false;
    if (asleep_in_a_moving_box(rec)) return false;
    // Its overhang counted in another sector (it came back to a sector made anew under the same key): moved
    // by update, serially, for this thread may touch only the sector it steps.
    if (entry.overhang_in.valid() && entry.overhang_in != rec.sector && sectors_.get(entry.overhang_in))
        return false;
    // The step moved its broadphase box within the fat box it keeps: queries of the sector must reach as
    // far. (Only this thread steps the sector, and queries come after every thread is done.)
    note_overhang(rec, sector);
    return entry.partners.empty() ? !entry.listed_in.valid() : entry.listed_in == rec.sector;
}

void BorderIndex::note_overhang(BodyRecord& rec, Sector& sector) {
    const btBroadphaseProxy* proxy = rec.rb->getBroadphaseHandle();
    if (proxy == nullptr) return;
    const Eigen::Vector3d lo = sector.from_physics(proxy->m_aabbMin);
    const Eigen::Vector3d hi = sector.from_physics(proxy->m_aabbMax);
    BorderEntry& entry = rec.border;
    const double overhang =
        std::max((entry.fat.max - hi).maxCoeff(), (lo - entry.fat.min).maxCoeff()) + overhang_tolerance_;
    const std::uint8_t bucket = overhang_scale_.bucket_of(overhang, entry.overhang_bucket);
    if (entry.overhang_in == sector.id && entry.overhang_bucket == bucket) {
        if (bucket == OverhangBound::kBuckets - 1) sector.overhangs.add_beyond(overhang);
        return;
    }
    uncount_overhang(entry);
    sector.overhangs.add(bucket, overhang);
    entry.overhang_bucket = bucket;
    entry.overhang_in = sector.id;
}

void BorderIndex::uncount_overhang(BorderEntry& entry) {
    if (!entry.overhang_in.valid()) return;
    // A sector destroyed since has taken its counts with it.
    if (Sector* was = sectors_.get(entry.overhang_in)) was->overhangs.remove(entry.overhang_bucket);
    entry.overhang_in = SectorId{};
    entry.overhang_bucket = OverhangScale::kNoBucket;
}

double BorderIndex::query_growth(const Sector& sector) const {
    return sector.overhangs.bound(overhang_scale_);
}

void BorderIndex::note_bounds_changed(std::uint32_t slot) {
    forget_reach(slot);
    BodyRecord& rec = bodies_[slot];
    if (!rec.alive || rec.plane || !rec.border.has_fat) return;
    Sector& sector = sector_of(rec);
    if (rec.border.fat_frame == sector.key) note_overhang(rec, sector);
}

bool BorderIndex::asleep_in_a_moving_box(const BodyRecord& rec) const {
    return rec.border.made_moving && rec.dynamic && !rec.rb->isActive();
}

bool BorderIndex::reaches_meet(std::uint32_t a, std::uint32_t b, std::uint64_t frame) {
    const Aabb& ra = current_reach(a, frame);
    const Aabb& rb = current_reach(b, frame);
    // Partners have fat boxes, and once this frame's updates are done a fat box's frame is its body's
    // sector (a body that changed sector was updated): the keys are there without a sector lookup.
    return ra.overlaps(
        rb.translated(grid_.centre_offset(bodies_[a].border.fat_frame, bodies_[b].border.fat_frame)));
}

void BorderIndex::update(std::uint32_t slot, std::uint64_t frame) {
    BodyRecord& rec = bodies_[slot];
    if (!rec.alive || rec.plane) return;
    relist(slot);  // it may have changed sector, or its sector been made anew, since it was listed
    const Aabb& tight = current_reach(slot, frame);
    Sector& sector = sector_of(rec);
    BorderEntry& entry = rec.border;
    if (entry.has_fat && entry.fat_frame == sector.key && entry.fat.contains(tight) &&
        !asleep_in_a_moving_box(rec)) {
        note_overhang(rec, sector);  // (a command may have moved it within its fat box)
        return;
    }
    // The slack: a tenth of a unit, or the distance of two frames at the current speed, whichever is
    // larger (but at most L/8): a resting body never refreshes, a moving one every few frames; and a
    // stretch along its velocity (kFatLookaheadFrames, at most L/8 long) for one that keeps its heading.
    // A static body's slack is Bullet's contact threshold: its broadphase box gains that margin when
    // first refreshed (its sector's anchor moving, say), and nothing makes it update then (seen in
    // RandomCalls: a reach 0.02 out of its fat box met another's that the fat boxes missed).
    double slack = gContactBreakingThreshold + 1e-3;
    Eigen::Vector3d ahead = Eigen::Vector3d::Zero();
    if (rec.dynamic) {
        const Eigen::Vector3d velocity = to_eigen(rec.rb->getLinearVelocity());
        slack = std::min(sector_size_ / 8.0, std::max(0.1, 2.0 * velocity.norm() * frame_dt_));
        ahead = velocity * (kFatLookaheadFrames * frame_dt_);
        if (ahead.norm() > sector_size_ / 8.0) ahead *= sector_size_ / 8.0 / ahead.norm();
    }
    ++refreshes_;
    entry.fat = tight.grown(slack);
    entry.fat.min += ahead.cwiseMin(0.0);
    entry.fat.max += ahead.cwiseMax(0.0);
    entry.fat_frame = sector.key;
    entry.has_fat = true;
    entry.made_moving = slack > 0.1 || ahead.norm() > 0.1;
    note_overhang(rec, sector);
    place_leaves(slot);
    refresh_pairs(slot);
}

void BorderIndex::remove(std::uint32_t slot) {
    drop_pairs(slot);
    remove_leaves(slot);
    uncount_overhang(bodies_[slot].border);
}

void BorderIndex::place_leaves(std::uint32_t slot) {
    BorderEntry& rec = bodies_[slot].border;
    const double size = sector_size_;
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        // A fat box wider than a few sectors only happens at absurd speeds: clamp to keep it bounded.
        lo[a] = static_cast<std::int64_t>(std::max(-4.0, std::floor(rec.fat.min[a] / size + 0.5)));
        hi[a] = static_cast<std::int64_t>(std::min(4.0, std::floor(rec.fat.max[a] / size + 0.5)));
    }
    const SectorKey owner = rec.fat_frame;
    // The cells within lo..hi of the owner's, but its own (found through the broadphase). Compared key by
    // key, not by difference: a leaf's cell can be as far from a new owner as a teleported body went.
    auto wanted = [&](const SectorKey& cell) {
        return !(cell == owner) && cell.i >= owner.i + lo[0] && cell.i <= owner.i + hi[0] &&
               cell.j >= owner.j + lo[1] && cell.j <= owner.j + hi[1] && cell.k >= owner.k + lo[2] &&
               cell.k <= owner.k + hi[2] && in_range(cell);
    };
    auto leaf_volume = [&](const SectorKey& cell) {
        return volume(rec.fat.translated(grid_.centre_offset(cell, owner)));
    };
    // A refreshed fat box mostly enters the cells it entered before: those leaves move within their trees
    // (no node allocated or freed, one tree lookup); the others go, and the new cells get leaves. Which
    // tree holds which leaf decides nothing but the cost: candidates are sorted before use.
    const bool had_leaves = !rec.leaves.empty();
    std::size_t kept = 0;
    for (std::size_t n = 0; n < rec.leaves.size(); ++n) {
        BorderEntry::Leaf leaf = rec.leaves[n];
        if (wanted(leaf.cell)) {
            btDbvtVolume box = leaf_volume(leaf.cell);
            cell_trees_.at(leaf.cell)->tree.update(leaf.node, box);
            rec.leaves[kept++] = leaf;
        } else {
            remove_leaf(leaf);
        }
    }
    const std::size_t moved = kept;
    rec.leaves.resize(kept);
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
            for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
                const SectorKey cell = owner + SectorKey{i, j, k};
                if (!wanted(cell)) continue;
                const auto moved_end = rec.leaves.begin() + static_cast<std::ptrdiff_t>(moved);
                if (std::any_of(rec.leaves.begin(), moved_end,
                                [&](const BorderEntry::Leaf& leaf) { return leaf.cell == cell; }))
                    continue;
                std::unique_ptr<CellTree>& tree = cell_trees_[cell];
                if (!tree) tree = std::make_unique<CellTree>();
                btDbvtNode* node =
                    tree->tree.insert(leaf_volume(cell), reinterpret_cast<void*>(std::uintptr_t{slot}));
                rec.leaves.push_back({cell, node});
            }
        }
    }
    if (had_leaves && rec.leaves.empty()) --border_bodies_;
    if (!had_leaves && !rec.leaves.empty()) ++border_bodies_;
}

void BorderIndex::remove_leaves(std::uint32_t slot) {
    BorderEntry& rec = bodies_[slot].border;
    if (!rec.leaves.empty()) --border_bodies_;
    for (const BorderEntry::Leaf& leaf : rec.leaves)
        remove_leaf(leaf);
    rec.leaves.clear();
}

void BorderIndex::remove_leaf(const BorderEntry::Leaf& leaf) {
    auto it = cell_trees_.find(leaf.cell);
    it->second->tree.remove(leaf.node);
    if (it->second->tree.empty()) cell_trees_.erase(it);  // no tree kept for a cell nobody reaches into
}

bool BorderIndex::fat_overlap(const BorderEntry& a, const BorderEntry& b) const {
    return a.fat.overlaps(b.fat.translated(grid_.centre_offset(a.fat_frame, b.fat_frame)));
}

void BorderIndex::refresh_pairs(std::uint32_t slot) {
    BodyRecord& rec = bodies_[slot];
    BorderEntry& entry = rec.border;
    // Partners that no longer overlap, or now share the sector, are dropped on both sides.
    for (std::size_t n = entry.partners.size(); n-- > 0;) {
        const std::uint32_t other = entry.partners[n];
        BodyRecord& partner = bodies_[other];
        if (partner.sector != rec.sector && fat_overlap(entry, partner.border)) continue;
        std::vector<std::uint32_t>& back = partner.border.partners;
        auto it = std::find(back.begin(), back.end(), slot);
        *it = back.back();
        back.pop_back();
        relist(other);
        entry.partners[n] = entry.partners.back();
        entry.partners.pop_back();
    }
    // New partners: where the fat box enters other cells, the leaves there and those cells' own bodies;
    // in its own cell, the leaves of bodies reaching in.
    found_scratch_.clear();
    CollectLeaves leaves(found_scratch_);
    CollectOriginals originals(found_scratch_);
    for (const BorderEntry::Leaf& leaf : entry.leaves) {
        const btDbvt& tree = cell_trees_.at(leaf.cell)->tree;
        tree.collideTV(tree.m_root, leaf.node->volume, leaves);
        if (Sector* sector = sectors_.find(leaf.cell)) {
            const Aabb query = entry.fat.translated(grid_.centre_offset(leaf.cell, entry.fat_frame))
                                   .grown(query_growth(*sector))
                                   .translated(-sector->anchor);
            sector->broadphase.aabbTest(to_bt(query.min), to_bt(query.max), originals);
        }
    }
    if (auto own = cell_trees_.find(entry.fat_frame); own != cell_trees_.end()) {
        own->second->tree.collideTV(own->second->tree.m_root, volume(entry.fat), leaves);
    }
    candidates_found_ += found_scratch_.size();
    std::sort(found_scratch_.begin(), found_scratch_.end());
    found_scratch_.erase(std::unique(found_scratch_.begin(), found_scratch_.end()), found_scratch_.end());
    for (std::uint32_t other : found_scratch_) {
        BodyRecord& partner = bodies_[other];
        if (other == slot || partner.sector == rec.sector || (!rec.dynamic && !partner.dynamic)) continue;
        if (!partner.border.has_fat) continue;  // not placed yet: it finds this body when it is
        if (std::find(entry.partners.begin(), entry.partners.end(), other) != entry.partners.end()) continue;
        if (!fat_overlap(entry, partner.border)) continue;
        entry.partners.push_back(other);
        partner.border.partners.push_back(slot);
        relist(other);
    }
    relist(slot);
}

void BorderIndex::drop_pairs(std::uint32_t slot) {
    BorderEntry& entry = bodies_[slot].border;
    for (std::uint32_t other : entry.partners) {
        std::vector<std::uint32_t>& back = bodies_[other].border.partners;
        back.erase(std::find(back.begin(), back.end(), slot));
        relist(other);
    }
    entry.partners.clear();
    relist(slot);
}

void BorderIndex::relist(std::uint32_t slot) {
    BodyRecord& rec = bodies_[slot];
    BorderEntry& entry = rec.border;
    const bool wanted = rec.alive && !entry.partners.empty();
    if (entry.listed_in.valid() && (!wanted || entry.listed_in != rec.sector)) {
        // A sector destroyed since has taken its list with it.
        if (Sector* was = sectors_.get(entry.listed_in)) {
            std::vector<std::uint32_t>& list = was->partnered;
            const std::uint32_t last = list.back();
            list[entry.listed_at] = last;
            bodies_[last].border.listed_at = entry.listed_at;
            list.pop_back();
        }
        entry.listed_in = SectorId{};
    }
    if (wanted && !entry.listed_in.valid()) {
        Sector& sector = sector_of(rec);
        entry.listed_in = rec.sector;
        entry.listed_at = static_cast<std::uint32_t>(sector.partnered.size());
        sector.partnered.push_back(slot);
    }
}

}  // namespace lpss::engine
