// The engine's state and its stages. One frame runs, in order: sectorize (sectorize.cpp), clone
// (cloning.cpp), step (stepping.cpp), then merges contacts (contacts.cpp). world.cpp holds the API:
// adding and removing bodies, commands, queries.
#pragma once

#include <BulletCollision/BroadphaseCollision/btDbvt.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>

#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "body_record.hpp"
#include "change_log.hpp"
#include "lpss/engine/world.hpp"
#include "sector.hpp"
#include "sector_table.hpp"
#include "shared_collision_configuration.hpp"
#include "thread_pool.hpp"

namespace lpss {
namespace engine {

/// The fat reach boxes of every body touching one cell of the grid, in that cell's frame: the spatial
/// index in which bodies of different sectors find each other (reach.cpp).
struct CellTree {
    btDbvt tree;
};

}  // namespace engine

struct World::Impl {
    Impl(const WorldSettings& settings, const EngineOptions& options);
    ~Impl();

    // ---- one frame
    void step();
    void sectorize(const std::vector<std::uint32_t>& candidates);
    void clone_stage(const std::vector<std::uint32_t>& candidates);
    void step_sectors();
    void track_position(engine::BodyRecord& record, double dt) const;
    void merge_contacts();

    // ---- sectors
    engine::Sector* find_sector(const SectorKey& key) const { return sectors.find(key); }
    /// The sector that owns a (non-plane) body.
    engine::Sector& sector_of(const engine::BodyRecord& rec) const { return sectors.at(rec.sector); }
    /// Finds or creates a sector; a new sector's anchor is placed near `first_local`, the sector-local
    /// position of the body that brings it into being.
    engine::Sector& sector_for(const SectorKey& key, const Eigen::Vector3d& first_local);
    Eigen::Vector3d anchor_near(const Eigen::Vector3d& local) const;
    void follow_bodies(engine::Sector& sector);
    void destroy_sector(engine::Sector& sector);
    void wake(engine::Sector& sector);

    // ---- bodies
    Status check_new_body(const BodyDesc& body) const;
    void insert_body(const BodyDesc& body);
    void move_body(std::uint32_t slot, const SectorPosition& to);
    /// Whether an owned body lies past the border into a sector this engine does not own.
    bool departs(const engine::BodyRecord& rec) const;
    Expected<std::uint32_t> slot_of(BodyId id) const;
    bool owns(const SectorKey& key) const { return !options.owns || options.owns(key); }
    void place_body(std::uint32_t slot, const SectorPosition& at, const Eigen::Quaterniond& orientation);
    BodySnapshot snapshot_of(const engine::BodyRecord& record) const;
    void add_plane_instance(std::uint32_t slot, engine::Sector& sector);

    // ---- reach (reach.cpp) and cloning (cloning.cpp)
    void update_reach(std::uint32_t slot);
    engine::Aabb tight_reach(const engine::BodyRecord& record) const;
    /// This frame's tight reach, computed once per frame.
    const engine::Aabb& current_reach(std::uint32_t slot);
    /// Whether two bodies of different sectors may touch this frame.
    bool reaches_meet(std::uint32_t a, std::uint32_t b);
    void place_leaves(std::uint32_t slot);
    void remove_leaves(std::uint32_t slot);
    void refresh_pairs(std::uint32_t slot);
    void drop_pairs(std::uint32_t slot);
    bool fat_overlap(const engine::BodyRecord& a, const engine::BodyRecord& b) const;
    engine::Clone& create_clone(std::uint32_t slot, engine::Sector& host);
    void release_clone(std::uint32_t slot, engine::Sector& host);
    void sync_clone(const engine::BodyRecord& record, engine::Clone& clone) const;

    // ---- contacts (contacts.cpp)
    void forget_contacts(engine::Sector& sector, BodyId id);
    void count_contact(const engine::ContactRecord& contact, const SectorKey& where, int delta);

    engine::BodyRecord& record(std::uint32_t slot) { return bodies[slot]; }
    const engine::BodyRecord& record(std::uint32_t slot) const { return bodies[slot]; }

    WorldSettings settings;
    EngineOptions options;
    SectorGrid grid;
    double band = 0.0;          ///< a centre this far from its sector's centre (on an axis) changes sector
    double reach_margin = 0.0;  ///< contact distance added to every reach box
    bool precise_positions = true;  ///< EngineOptions::double_positions, off in monolithic mode
    double anchor_quantum = 0.0;    ///< anchors are multiples of this power of two; 0: anchors stay at 0
    btVector3 gravity;

    engine::SharedCollisionConfiguration configuration;
    std::vector<std::unique_ptr<btSequentialImpulseConstraintSolver>> solvers;  ///< one per thread
    engine::ThreadPool pool;

    engine::SectorTable sectors;
    std::vector<engine::BodyRecord> bodies;  ///< by slot; slots are reused through free_slots
    std::vector<std::uint32_t> free_slots;
    std::unordered_map<BodyId, std::uint32_t> slots;
    std::vector<std::uint32_t> planes;

    /// For each cell some body's fat box touches, the tree of those boxes.
    std::unordered_map<SectorKey, std::unique_ptr<engine::CellTree>, SectorKeyHash> cell_trees;
    std::size_t border_bodies = 0;

    std::vector<std::uint32_t> dirty;  ///< bodies changed by commands since the last step
    /// Owned bodies found past the border into a sector not owned (World::departures), until handed off.
    std::vector<std::uint32_t> departing;
    engine::ChangeLog changes;  ///< what moved, arrived and left where: for publishers
    // Sectors by id, never by pointer: a sector may be destroyed while listed (a body removed by a command
    // empties it), and a stale id then resolves to nothing.
    std::vector<engine::SectorId> awake_list;       ///< sectors that may hold awake originals
    std::vector<engine::SectorId> step_set;         ///< sectors stepped this (or the last) frame
    std::vector<engine::SectorId> pending_destroy;  ///< emptied by sectorization; destroyed if still empty

    // Scratch, kept to avoid allocation per frame.
    std::vector<std::uint32_t> candidate_scratch;
    std::vector<std::uint32_t> found_scratch;
    std::vector<std::pair<engine::SectorId, std::uint32_t>> missing_scratch;
    std::vector<std::pair<engine::SectorId, std::uint32_t>> requirements;

    struct PairHash {
        std::size_t operator()(const std::pair<BodyId, BodyId>& p) const {
            return std::hash<BodyId>()(p.first * 0x9E3779B97F4A7C15ULL ^ p.second);
        }
    };
    /// How many sectors currently report each touching pair: a pair begins at 1 and ends at 0.
    std::unordered_map<std::pair<BodyId, BodyId>, int, PairHash> touching;
    /// A pair whose count changed since the last events were made: its count before, and where and how
    /// it was first seen touching (for the Begin event).
    struct PairChange {
        int before = 0;
        engine::ContactRecord record;
        SectorKey where;
        bool seen = false;
    };
    std::unordered_map<std::pair<BodyId, BodyId>, PairChange, PairHash> changed_pairs;
    std::vector<ContactEvent> events;  ///< of the last step, and of commands before it

    std::size_t clone_count = 0;
    std::size_t spare_count = 0;
    std::uint64_t frame = 0;
    FrameStats stats;
};

}  // namespace lpss
