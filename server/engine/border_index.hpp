// The border index: which bodies of different sectors may touch, found incrementally.
//
// Each body keeps a *fat* reach box, in its owner sector's frame: its bounding box swept by the motion of
// the coming frames, grown by a slack and stretched along its velocity, so that it changes only when the
// body has moved by that slack or turned (the fat boxes of Box2D's dynamic tree, for the same reason). Where
// a fat box enters cells of the grid other than its owner's, it is a leaf in those cells' trees. Bodies of
// different sectors whose fat boxes overlap are *partners*: the pairs that need clones. They meet either in a
// cell foreign to both (both are leaves there) or in the cell of one of them (the other is a leaf there, and
// the cell's own bodies are found through its Bullet broadphase). Partners are kept from frame to frame and
// re-examined only for a body whose fat box changed, so the per-frame cost follows the bodies that move out
// of their slack; a body whose fat box stays inside its sector, in a cell nobody reaches into, costs a
// lookup.
//
// As Box2D's b2BroadPhase owns its trees and pair set while each shape keeps its own fat box, the index
// owns the cell trees and each body record keeps its BorderEntry; the cloning stage only asks it.
#pragma once

#include <BulletCollision/BroadphaseCollision/btDbvt.h>

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "aabb.hpp"
#include "body_record.hpp"
#include "lpss/common/sector_grid.hpp"
#include "lpss/common/world_settings.hpp"
#include "sector_table.hpp"

namespace lpss::engine {

/// How far ahead a fat box reaches along its body's velocity, in frames (Box2D v2's predictive fat boxes,
/// b2DynamicTree::MoveProxy, for the same reason): a body that keeps its heading stays inside for about
/// half a second instead of the few frames its slack gives. Measured in `lpss-bench --quick overhead` at
/// 10,000 drifting bodies against no lookahead: cloning's share of the frame 0.24 to 0.145 at L = 8 in a
/// world's first frames and 0.128 to 0.114 once running; 0.11 to 0.057 and 0.063 to 0.052 at L = 32. 8, 16,
/// 20, 45 and 60 frames were slower (fewer refreshes against larger queries and more partners).
inline constexpr double kFatLookaheadFrames = 30.0;

class BorderIndex {
public:
    /// `bodies` and `sectors` are the world's, which outlive the index. Serial only, but for
    /// prepare_reach: never called from the threads that step sectors.
    BorderIndex(const WorldSettings& settings, std::vector<BodyRecord>& bodies, SectorTable& sectors);
    BorderIndex(const BorderIndex&) = delete;
    BorderIndex& operator=(const BorderIndex&) = delete;

    /// Brings a body's fat box, leaves and partners up to date for `frame`: a new fat box only when the
    /// tight reach has left the old one or the body changed sector. Partners are found only among bodies
    /// already placed, so bodies are updated in a fixed order (the candidates' order) for reproducibility.
    void update(std::uint32_t slot, std::uint64_t frame);
    /// Computes a body's tight reach for `frame` ahead of update, from the thread that has just stepped
    /// its sector (where the body is in cache, and in parallel: Box2D checks its fat boxes in the
    /// solver's threads for the same reason). Touches only this body's entry and its sector's
    /// overhangs (note_overhang): a sector is stepped by one thread. Whatever changes the body
    /// before that frame's update must call forget_reach (note_bounds_changed if it moved the body's
    /// broadphase box) and have the body updated. Returns whether that
    /// update would have nothing to do: the reach within its fat box, in the box's sector, the body
    /// listed as its partners say.
    bool prepare_reach(std::uint32_t slot, std::uint64_t frame);
    /// Drops a reach computed ahead: the body was moved, pushed or changed sector since.
    void forget_reach(std::uint32_t slot) { bodies_[slot].border.reach_frame = 0; }
    /// A command moved a body's broadphase box (set_state, a ghost update): drops its reach computed
    /// ahead, and notes how far its fat box now reaches beyond that box, before this frame's updates
    /// query its sector (an update of the body itself may come after theirs).
    void note_bounds_changed(std::uint32_t slot);
    /// Whether two partners may touch in `frame`: their tight reaches meet. After this frame's updates.
    bool reaches_meet(std::uint32_t a, std::uint32_t b, std::uint64_t frame);
    /// Whether two bodies' fat boxes overlap (both placed): what makes them partners.
    bool fat_boxes_overlap(std::uint32_t a, std::uint32_t b) const {
        return fat_overlap(bodies_[a].border, bodies_[b].border);
    }
    /// A body's tight reach in `frame`, in its sector's frame (for diagnostics).
    const Aabb& reach(std::uint32_t slot, std::uint64_t frame) { return current_reach(slot, frame); }
    /// The bodies of other sectors that may touch this one (its fat box overlaps theirs).
    const std::vector<std::uint32_t>& partners(std::uint32_t slot) const {
        return bodies_[slot].border.partners;
    }
    /// The originals of a sector that have partners, as of the last update of each of them.
    const std::vector<std::uint32_t>& partnered(const Sector& sector) const { return sector.partnered; }
    /// Takes a body out: its leaves, and its pairs on both sides. Before its slot is reused.
    void remove(std::uint32_t slot);
    /// Bodies whose fat box enters another cell.
    std::size_t border_bodies() const { return border_bodies_; }
    /// Bodies the queries of refreshed fat boxes have found (cell trees and sectors' broadphases, before
    /// their fat boxes are compared), since the index was made: what re-examining a body costs.
    std::uint64_t candidates_found() const { return candidates_found_; }
    /// Fat boxes made since the index was made (update found the tight reach outside the old one, or the
    /// body in another sector).
    std::uint64_t refreshes() const { return refreshes_; }
    /// How much a query for a sector's bodies by fat box is grown: at least the most any of its bodies'
    /// fat boxes overhangs its broadphase box (Sector::overhangs).
    double query_growth(const Sector& sector) const;

private:
    struct CellTree {
        btDbvt tree;
    };

    Aabb tight_reach(const BodyRecord& record) const;
    /// This frame's tight reach, computed once per frame.
    const Aabb& current_reach(std::uint32_t slot, std::uint64_t frame);
    void place_leaves(std::uint32_t slot);
    void remove_leaves(std::uint32_t slot);
    /// Takes one leaf out of its cell's tree, and the tree out of the index once it is empty.
    void remove_leaf(const BorderEntry::Leaf& leaf);
    void refresh_pairs(std::uint32_t slot);
    void drop_pairs(std::uint32_t slot);
    /// Lists a body among its sector's partnered originals, or takes it off, as its partners and its
    /// sector now are.
    void relist(std::uint32_t slot);
    bool fat_overlap(const BorderEntry& a, const BorderEntry& b) const;
    /// A body fallen asleep in a fat box made while it moved (stretched along its old velocity, with the
    /// slack of its old speed) would keep that box for as long as it sleeps, and with it partners and its
    /// sector's query growth: it is given a box as tight as a resting body's, once.
    bool asleep_in_a_moving_box(const BodyRecord& record) const;
    /// Counts how far the body's fat box reaches beyond its broadphase box now in the sector's overhangs
    /// (its count moved there from wherever it was).
    /// A sector's bodies are found by fat box through its broadphase, which holds their broadphase boxes:
    /// a query grown by the most any fat box overhangs its body's box finds every one it overlaps. Measured
    /// each time a box moves (the step, a command, a new fat box), not bounded from the fat box's growth:
    /// a box turning from 45 degrees to flat shrinks its broadphase box by more than any slack.
    void note_overhang(BodyRecord& record, Sector& sector);
    /// Takes the body's overhang out of the sector it is counted in.
    void uncount_overhang(BorderEntry& entry);
    Sector& sector_of(const BodyRecord& record) const { return sectors_.at(record.sector); }

    SectorGrid grid_;
    double sector_size_;
    double reach_dt_;  ///< the time a tight reach sweeps: the last substep and the coming frame
    double frame_dt_;
    double reach_margin_;           ///< contact distance added to every reach box
    double overhang_tolerance_;     ///< added to each overhang noted (note_overhang)
    OverhangScale overhang_scale_;  ///< the buckets of Sector::overhangs
    std::vector<BodyRecord>& bodies_;
    SectorTable& sectors_;
    /// For each cell some body's fat box touches, the tree of those boxes.
    std::unordered_map<SectorKey, std::unique_ptr<CellTree>, SectorKeyHash> cell_trees_;
    std::size_t border_bodies_ = 0;
    std::uint64_t candidates_found_ = 0;
    std::uint64_t refreshes_ = 0;
    std::vector<std::uint32_t> found_scratch_;  ///< kept to avoid allocation per refresh
};

}  // namespace lpss::engine
