// Reach, the first half of the cloning stage: which bodies of different sectors may touch.
//
// Each body keeps a *fat* reach box, in its owner sector's frame: its bounding box swept by the motion of
// the coming frames and grown by a slack, so that it changes only when the body has moved by that slack
// (the fat boxes of Box2D's dynamic tree, for the same reason). Where a fat box enters cells of the grid
// other than its owner's, it is a leaf in those cells' trees. Bodies of different sectors whose fat boxes
// overlap are *partners*: the pairs that need clones. They meet either in a cell foreign to both (both
// are leaves there) or in the cell of one of them (the other is a leaf there, and the cell's own bodies
// are found through its Bullet broadphase). Partners are kept from frame to frame and re-examined only
// for a body whose fat box changed, so the per-frame cost follows the bodies that move out of their
// slack; a body whose fat box stays inside its sector, in a cell nobody reaches into, costs a lookup.
#include <algorithm>
#include <cmath>

#include "bullet_convert.hpp"
#include "world_impl.hpp"

namespace lpss {

using engine::Aabb;
using engine::BodyRecord;
using engine::Sector;
using engine::to_bt;
using engine::to_eigen;

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
        if (object->getUserIndex2() == static_cast<int>(engine::Role::Original)) {
            found.push_back(static_cast<std::uint32_t>(object->getUserIndex()));
        }
        return true;
    }
    std::vector<std::uint32_t>& found;
};

}  // namespace

Aabb World::Impl::tight_reach(const BodyRecord& rec) const {
    // Bullet's broadphase box (current pose, plus its contact threshold once refreshed by a step) as of
    // the start of the last physics step, swept by the motion of that step and of the coming frame.
    const btRigidBody& rb = *rec.rb;
    const btBroadphaseProxy* proxy = rb.getBroadphaseHandle();
    const Sector& sector = sector_of(rec);
    Aabb box{sector.from_physics(proxy->m_aabbMin), sector.from_physics(proxy->m_aabbMax)};
    if (rec.dynamic) {
        const double dt = settings.dt * (1.0 + 1.0 / settings.substeps_per_frame());
        const Eigen::Vector3d travel = to_eigen(rb.getLinearVelocity()) * dt;
        box.min += travel.cwiseMin(0.0);
        box.max += travel.cwiseMax(0.0);
        box = box.grown(static_cast<double>(rb.getAngularVelocity().length()) * rec.bound_radius * dt);
    }
    return box.grown(reach_margin);
}

const Aabb& World::Impl::current_reach(std::uint32_t slot) {
    BodyRecord& rec = record(slot);
    if (rec.reach_frame != frame) {
        rec.reach = tight_reach(rec);
        rec.reach_frame = frame;
    }
    return rec.reach;
}

bool World::Impl::reaches_meet(std::uint32_t a, std::uint32_t b) {
    const Aabb& ra = current_reach(a);
    const Aabb& rb = current_reach(b);
    return ra.overlaps(rb.translated(grid.centre_offset(sector_of(record(a)).key, sector_of(record(b)).key)));
}

void World::Impl::update_reach(std::uint32_t slot) {
    BodyRecord& rec = record(slot);
    if (!rec.alive || rec.plane) return;
    const Aabb& tight = current_reach(slot);
    Sector& sector = sector_of(rec);
    if (rec.has_fat && rec.fat_frame == sector.key && rec.fat.contains(tight)) return;
    // The slack: a tenth of a unit, or the distance of two frames at the current speed, whichever is
    // larger (but at most L/8): a resting body never refreshes, a moving one every few frames.
    double slack = 0.0;
    if (rec.dynamic) {
        const double speed = static_cast<double>(rec.rb->getLinearVelocity().length());
        slack = std::min(settings.sector_size / 8.0, std::max(0.1, 2.0 * speed * settings.dt));
    }
    rec.fat = tight.grown(slack);
    rec.fat_frame = sector.key;
    rec.has_fat = true;
    // How far the fat box may reach beyond the body's broadphase box, for queries of that broadphase.
    const Eigen::Vector3d excess = (rec.fat.max - rec.fat.min) - (tight.max - tight.min) +
                                   2.0 * Eigen::Vector3d::Constant(reach_margin + slack);
    sector.fat_excess = std::max(sector.fat_excess, excess.maxCoeff());
    place_leaves(slot);
    refresh_pairs(slot);
}

void World::Impl::place_leaves(std::uint32_t slot) {
    remove_leaves(slot);
    BodyRecord& rec = record(slot);
    const double size = settings.sector_size;
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        // A fat box wider than a few sectors only happens at absurd speeds: clamp to keep it bounded.
        lo[a] = static_cast<std::int64_t>(std::max(-4.0, std::floor(rec.fat.min[a] / size + 0.5)));
        hi[a] = static_cast<std::int64_t>(std::min(4.0, std::floor(rec.fat.max[a] / size + 0.5)));
    }
    const SectorKey owner = rec.fat_frame;
    for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j) {
            for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
                if (i == 0 && j == 0 && k == 0) continue;  // its own cell: found through the broadphase
                const SectorKey cell = owner + SectorKey{i, j, k};
                if (!in_range(cell)) continue;
                std::unique_ptr<engine::CellTree>& tree = cell_trees[cell];
                if (!tree) tree = std::make_unique<engine::CellTree>();
                const Aabb box = rec.fat.translated(grid.centre_offset(cell, owner));
                btDbvtNode* node =
                    tree->tree.insert(volume(box), reinterpret_cast<void*>(std::uintptr_t{slot}));
                rec.leaves.push_back({cell, node});
            }
        }
    }
    if (!rec.leaves.empty()) ++border_bodies;
}

void World::Impl::remove_leaves(std::uint32_t slot) {
    BodyRecord& rec = record(slot);
    if (!rec.leaves.empty()) --border_bodies;
    for (const BodyRecord::Leaf& leaf : rec.leaves) {
        auto it = cell_trees.find(leaf.cell);
        it->second->tree.remove(leaf.node);
        if (it->second->tree.empty()) cell_trees.erase(it);
    }
    rec.leaves.clear();
}

bool World::Impl::fat_overlap(const BodyRecord& a, const BodyRecord& b) const {
    return a.fat.overlaps(b.fat.translated(grid.centre_offset(a.fat_frame, b.fat_frame)));
}

void World::Impl::refresh_pairs(std::uint32_t slot) {
    BodyRecord& rec = record(slot);
    // Partners that no longer overlap, or now share the sector, are dropped on both sides.
    for (std::size_t n = rec.partners.size(); n-- > 0;) {
        const std::uint32_t other = rec.partners[n];
        BodyRecord& partner = record(other);
        if (partner.sector != rec.sector && fat_overlap(rec, partner)) continue;
        auto back = std::find(partner.partners.begin(), partner.partners.end(), slot);
        *back = partner.partners.back();
        partner.partners.pop_back();
        rec.partners[n] = rec.partners.back();
        rec.partners.pop_back();
    }
    // New partners: where the fat box enters other cells, the leaves there and those cells' own bodies;
    // in its own cell, the leaves of bodies reaching in.
    found_scratch.clear();
    CollectLeaves leaves(found_scratch);
    CollectOriginals originals(found_scratch);
    for (const BodyRecord::Leaf& leaf : rec.leaves) {
        const btDbvt& tree = cell_trees.at(leaf.cell)->tree;
        tree.collideTV(tree.m_root, leaf.node->volume, leaves);
        if (Sector* sector = find_sector(leaf.cell)) {
            const Aabb query = rec.fat.translated(grid.centre_offset(leaf.cell, rec.fat_frame))
                                   .grown(sector->fat_excess)
                                   .translated(-sector->anchor);
            sector->broadphase.aabbTest(to_bt(query.min), to_bt(query.max), originals);
        }
    }
    if (auto own = cell_trees.find(rec.fat_frame); own != cell_trees.end()) {
        own->second->tree.collideTV(own->second->tree.m_root, volume(rec.fat), leaves);
    }
    std::sort(found_scratch.begin(), found_scratch.end());
    found_scratch.erase(std::unique(found_scratch.begin(), found_scratch.end()), found_scratch.end());
    for (std::uint32_t other : found_scratch) {
        BodyRecord& partner = record(other);
        if (other == slot || partner.sector == rec.sector || (!rec.dynamic && !partner.dynamic)) continue;
        if (!partner.has_fat) continue;  // not placed yet: it finds this body when it is
        if (std::find(rec.partners.begin(), rec.partners.end(), other) != rec.partners.end()) continue;
        if (!fat_overlap(rec, partner)) continue;
        rec.partners.push_back(other);
        partner.partners.push_back(slot);
    }
}

void World::Impl::drop_pairs(std::uint32_t slot) {
    BodyRecord& rec = record(slot);
    for (std::uint32_t other : rec.partners) {
        std::vector<std::uint32_t>& back = record(other).partners;
        back.erase(std::find(back.begin(), back.end(), slot));
    }
    rec.partners.clear();
}

}  // namespace lpss
