// The engine's state and its stages. One frame runs, in order: sectorize (sectorize.cpp), clone
// (cloning.cpp), step (stepping.cpp), then hands each stepped sector's touching pairs to the contact
// tracker (contact_tracker.hpp). world.cpp holds the API: adding and removing bodies, commands, queries.
#pragma once

#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>

#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "body_record.hpp"
#include "border_index.hpp"
#include "change_log.hpp"
#include "contact_tracker.hpp"
#include "lpss/engine/world.hpp"
#include "sector.hpp"
#include "sector_table.hpp"
#include "shape_library.hpp"
#include "shared_collision_configuration.hpp"
#include "thread_pool.hpp"

namespace lpss {

struct World::Impl {
    Impl(const WorldSettings& settings, const EngineOptions& options);
    ~Impl();

    // ---- one frame
    void step();
    void sectorize(const std::vector<std::uint32_t>& candidates);
    void clone_stage(const std::vector<std::uint32_t>& candidates);
    /// EngineOptions::check_clones: notes in clone_check_failure a clone the stage should have made.
    void check_clones();
    void step_sectors();
    void note_active(engine::Sector& sector);
    void track_positions(engine::Sector& sector, double dt);
    /// After a sector's step: what is awake and touching, its anchor, and next frame's reaches.
    void finish_step(engine::Sector& sector);
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

    // ---- cloning (cloning.cpp)
    engine::Clone& create_clone(std::uint32_t slot, engine::Sector& host);
    void release_clone(std::uint32_t slot, engine::Sector& host);
    void sync_clone(const engine::BodyRecord& record, engine::Clone& clone) const;

    /// Ends what `sector` saw `id` touching (the body leaves it or goes away).
    void forget_contacts(engine::Sector& sector, BodyId id) {
        contacts.forget(sector.contacts, sector.key, id);
    }

    engine::BodyRecord& record(std::uint32_t slot) { return bodies[slot]; }
    const engine::BodyRecord& record(std::uint32_t slot) const { return bodies[slot]; }

    WorldSettings settings;
    EngineOptions options;
    SectorGrid grid;
    double band = 0.0;  ///< a centre this far from its sector's centre (on an axis) changes sector
    bool precise_positions = true;  ///< EngineOptions::double_positions, off in monolithic mode
    double anchor_quantum = 0.0;    ///< anchors are multiples of this power of two; 0: anchors stay at 0
    btVector3 gravity;

    engine::SharedCollisionConfiguration configuration;
    std::vector<std::unique_ptr<btSequentialImpulseConstraintSolver>> solvers;  ///< one per thread
    engine::ThreadPool pool;

    engine::ShapeLibrary shapes;
    engine::SectorTable sectors;
    std::vector<engine::BodyRecord> bodies;  ///< by slot; slots are reused through free_slots
    std::vector<std::uint32_t> free_slots;
    std::unordered_map<BodyId, std::uint32_t> slots;
    std::vector<std::uint32_t> planes;

    engine::BorderIndex border{settings, bodies, sectors};  ///< which bodies of different sectors may touch

    std::vector<std::uint32_t> dirty;  ///< bodies changed by commands since the last step
    /// Owned bodies found past the border into a sector not owned (World::departures), until handed off.
    std::vector<std::uint32_t> departing;
    engine::ChangeLog changes;  ///< what moved, arrived and left where: for publishers
    // Sectors by id, never by pointer: a sector may be destroyed while listed (a body removed by a command
    // empties it), and a stale id then resolves to nothing.
    std::vector<engine::SectorId> awake_list;       ///< sectors that may hold awake originals
    std::vector<engine::SectorId> step_set;         ///< sectors stepped this (or the last) frame
    std::vector<engine::SectorId> pending_destroy;  ///< emptied by sectorization; destroyed if still empty
    /// A run of step_set stepped by one thread: one sector, or consecutive small ones stepped together.
    struct StepGroup {
        std::size_t begin = 0, end = 0;
        bool small = false;
    };
    /// A sector of at most this many Bullet objects is stepped in a group with its small neighbours in
    /// step_set, up to kGroupObjects objects in all: Bullet's own batch of islands is 128 contacts.
    static constexpr std::size_t kSmallSectorObjects = 16;
    static constexpr std::size_t kGroupObjects = 128;
    std::vector<StepGroup> step_groups;
    std::vector<engine::Sector*> step_sectors_scratch;  ///< step_set's sectors, looked up before threads run

    // Scratch, kept to avoid allocation per frame.
    std::vector<std::uint32_t> candidate_scratch;
    std::vector<std::pair<engine::SectorId, std::uint32_t>> missing_scratch;  ///< clones to create this frame
    std::string clone_check_failure;  ///< the first clone check_clones found missing (none: empty)

    engine::ContactTracker contacts;  ///< touching pairs over every sector, and the events they make

    std::size_t clone_count = 0;
    std::size_t spare_count = 0;
    std::uint64_t clones_made = 0;      ///< since the world was made (FrameStats::clones_made)
    std::uint64_t clones_released = 0;  ///< (FrameStats::clones_released)
    std::uint64_t frame = 0;
    FrameStats stats;
};

}  // namespace lpss
