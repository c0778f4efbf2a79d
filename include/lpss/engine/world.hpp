// The in-process LPSS engine: a sectorized world of rigid bodies, precise at any distance from the
// origin. Each sector is simulated by its own physics world in sector-local coordinates; bodies near
// borders are cloned into neighbouring sectors so that collisions across borders happen as they would
// inside one sector. The physics engine (Bullet) stays behind this header.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "lpss/common/body_desc.hpp"
#include "lpss/common/body_snapshot.hpp"
#include "lpss/common/expected.hpp"
#include "lpss/common/scene.hpp"
#include "lpss/common/sector_grid.hpp"
#include "lpss/common/world_settings.hpp"

namespace lpss {

/// How the engine runs, as opposed to what it simulates (WorldSettings).
struct EngineOptions {
    int threads = 1;  ///< sectors are stepped concurrently on this many threads
    /// One physics world in global coordinates, no sectors, no clones: plain Bullet, kept for
    /// comparison with the sectorized engine on the same scene.
    bool monolithic = false;
    std::size_t max_spare_clones = 4;  ///< per body, clones kept for reuse once no longer needed
    /// Keep each body's sector-local position in double and let the physics engine's float position
    /// be its rounding: motion that Bullet's velocity explains is integrated in double, so float
    /// rounding no longer accumulates over frames. Off: plain float Bullet in sector-local coordinates.
    /// No effect in monolithic mode.
    bool double_positions = true;
    /// Let each sector's physics world keep its origin near the sector's bodies (a quantised anchor
    /// that follows their bounding box) instead of at the sector's centre, so that the floats the
    /// physics engine computes with are as small as at the world origin. Off: the paper's sector-centred
    /// frames. No effect in monolithic mode.
    bool floating_origins = true;
    /// For comparison only (lpss-bench's naive-bullet): every sector gets a default Bullet world of its
    /// own (its own default collision configuration and solver, all boxes refreshed every step) and
    /// every sector is stepped every frame, as one would without lpss's sharing and sleeping rules.
    bool naive_sector_worlds = false;
    /// For comparison only (lpss-bench accuracy): Bullet's own penetration push on bouncing contacts, which
    /// gives bounces energy (docs/design.md, "Solver settings"). Off: bounces keep what restitution says.
    bool bullet_bounces = false;
    /// Step consecutive small sectors together, with one solver call for all their islands (see
    /// server/engine/island_batch.hpp): the same results as stepping each alone, at less cost. Off only
    /// to check that equality.
    bool group_small_sectors = true;
    /// For tests: after every cloning stage, check that each dynamic body of a stepped sector has there a
    /// clone of every body of another sector whose reach meets its own (partners or not: O(bodies^2));
    /// check_consistency reports the first that did not.
    bool check_clones = false;
    /// Which sectors this engine simulates (every sector when empty). A body in a sector it does not own
    /// is a *ghost*: a copy of a body another process simulates, kept so that it can be cloned across
    /// the border; set_state moves it. An owned body whose centre crosses into a sector not owned stays
    /// where it is and is listed by departures() until it is removed (handed off).
    std::function<bool(const SectorKey&)> owns;
};

/// An owned body that has crossed into a sector this engine does not own.
struct Departure {
    BodyId id = 0;
    SectorPosition to;  ///< its position in the sector it entered
};

/// Two bodies started or stopped touching. Reported with the ids of the bodies the user created,
/// whichever sector or clone saw the contact.
struct ContactEvent {
    enum class Kind : std::uint8_t { Begin, End };
    Kind kind = Kind::Begin;
    BodyId a = 0;  ///< a < b
    BodyId b = 0;
    SectorPosition point;                              ///< Begin: where they touch
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< Begin: contact normal, pointing from b to a
    double impulse = 0.0;                              ///< Begin: total normal impulse of the first step
};

/// What changed in one sector in the last frame (World::sector_changes), each list ordered by id.
struct SectorChanges {
    std::vector<BodySnapshot> bodies;  ///< bodies that may have moved or arrived, in their state now
    std::vector<double> radii;         ///< their bounding radii (World::bounding_radius)
    std::vector<BodyId> left;          ///< bodies that left it (moved out, handed off, removed)
};

/// What the last frame did and what each stage cost.
struct FrameStats {
    std::uint64_t frame = 0;
    std::size_t bodies = 0;
    std::size_t sectors = 0;          ///< sectors that exist
    std::size_t stepped_sectors = 0;  ///< sectors simulated this frame (the others hold nothing awake)
    std::size_t grouped_sectors = 0;  ///< of those, sectors stepped in groups sharing solver calls
    std::size_t sector_changes = 0;   ///< bodies that moved to another sector
    std::size_t border_bodies = 0;    ///< bodies whose reach crosses their sector's border
    /// Bodies found by the border index's queries for the bodies that left their fat reach boxes this
    /// frame, before those boxes are compared: the work of finding new pairs to clone.
    std::size_t border_candidates = 0;
    /// Bodies that left their fat reach box (or changed sector) this frame and were given a new one: the
    /// bodies whose queries border_candidates counts.
    std::size_t fat_box_refreshes = 0;
    /// Clones the cloning stage put into sectors this frame (new ones, or from their body's pool), and let
    /// go after they went unneeded for a few frames: what adding to and taking out of Bullet worlds costs.
    std::size_t clones_made = 0;
    std::size_t clones_released = 0;
    std::size_t clones = 0;        ///< clones in sectors, planes' per-sector instances excluded
    std::size_t spare_clones = 0;  ///< clones kept in per-body pools for reuse
    std::size_t touching_pairs = 0;
    /// Bodies the serial stages (sectorize, clone) looked at: those the last step moved past the
    /// hysteresis band or out of their fat reach box, and those calls touched since. A body drifting
    /// within its sector and its fat box is not among them.
    std::size_t visited_bodies = 0;
    double sectorize_seconds = 0.0;
    double clone_seconds = 0.0;
    double step_seconds = 0.0;
    double total_seconds = 0.0;
};

/// The clones of one body: in use in other sectors, and kept in its pool for reuse.
struct CloneCounts {
    std::size_t active = 0;
    std::size_t spare = 0;
};

class World {
public:
    /// A world with no bodies. Refuses invalid settings (see validate(WorldSettings)).
    static Expected<World> create(const WorldSettings& settings, const EngineOptions& options = {});

    /// A world holding every body of the scene.
    static Expected<World> create(const Scene& scene, const EngineOptions& options = {});

    World(World&&) noexcept;
    World& operator=(World&&) noexcept;
    ~World();

    /// Adds a body; refused (the world unchanged) for an invalid body or an id already in use.
    Status add_body(const BodyDesc& body);
    /// Adds all the bodies (in their order) or, if any is refused, none of them.
    Status add_bodies(const std::vector<BodyDesc>& bodies);
    /// Removes a body; refused for an unknown id.
    Status remove_body(BodyId id);
    /// Applies an impulse (N s, world axes) at an offset from the centre of mass; wakes the body.
    Status apply_impulse(BodyId id, const Eigen::Vector3d& impulse,
                         const Eigen::Vector3d& offset = Eigen::Vector3d::Zero());
    /// Sets a dynamic body's velocities; wakes it.
    Status set_velocity(BodyId id, const Eigen::Vector3d& linear, const Eigen::Vector3d& angular);
    /// Moves a body to a state (position, orientation, velocities, awake): how ghosts follow the bodies
    /// they copy. Refused for a static body or a non-finite state.
    Status set_state(const BodySnapshot& state);
    /// Changes which sectors this engine simulates: bodies of sectors no longer owned become ghosts,
    /// ghosts of sectors now owned become bodies it simulates.
    void set_ownership(std::function<bool(const SectorKey&)> owns);

    /// Advances the world by one frame of settings().dt.
    void step();

    /// Frames stepped so far.
    std::uint64_t frame() const;
    bool contains(BodyId id) const;
    std::size_t body_count() const;
    /// The body's current state, or nothing for an unknown id.
    std::optional<BodySnapshot> body(BodyId id) const;
    /// Every body's current state, ordered by id.
    std::vector<BodySnapshot> snapshot() const;
    /// The description the body was created from, or nothing for an unknown id.
    std::optional<BodyDesc> description(BodyId id) const;
    /// The radius of the sphere around its centre that holds the body in any orientation (0 for an
    /// unknown id or a plane).
    double bounding_radius(BodyId id) const;
    /// Whether a body is a ghost (in a sector this engine does not own).
    bool is_ghost(BodyId id) const;
    /// Owned bodies that have crossed into sectors this engine does not own, ordered by id. Costs what
    /// the departing bodies cost, not what the world holds.
    std::vector<Departure> departures() const;
    /// The bodies a sector owns (not clones, not planes), ordered by id.
    std::vector<BodySnapshot> sector_bodies(const SectorKey& key) const;
    /// Sectors stepped in the last frame, in key order.
    std::vector<SectorKey> stepped_sectors() const;
    /// Sectors whose bodies may have changed (moved, arrived, left, been added or removed) in the last
    /// frame or by calls made before it, in key order; sectors that no longer exist included. Every other
    /// sector holds exactly what it held after the frame before: a publisher needs to look nowhere else.
    std::vector<SectorKey> changed_sectors() const;
    /// What changed in one of those sectors: costs what changed, not what the sector holds.
    SectorChanges sector_changes(const SectorKey& key) const;

    /// Contacts that began or ended during the last step, ordered by kind and ids.
    const std::vector<ContactEvent>& contact_events() const;
    const FrameStats& last_frame_stats() const;
    /// Clone counts of a body (for tests and diagnostics), or nothing for an unknown id.
    std::optional<CloneCounts> clone_counts(BodyId id) const;
    /// Sectors that exist, in key order.
    std::vector<SectorKey> sectors() const;
    /// Whether a sector exists (holds a body).
    bool has_sector(const SectorKey& key) const;
    /// Makes room for this many bodies in all, so that adding a large world does not grow its tables
    /// again and again. Beyond the room there is, it grows by half at least: called before every few
    /// bodies added, it must not copy the tables each time.
    void reserve(std::size_t bodies);
    /// Checks the engine's invariants: every body finite and owned by a sector that exists and lists
    /// it, no empty sector, every clone hosted by a live sector. For tests and diagnostics: O(bodies).
    Status check_consistency() const;

    const WorldSettings& settings() const;
    const EngineOptions& options() const;
    const SectorGrid& grid() const;

    /// "float" or "double": the precision of the physics engine this program was built with.
    static const char* physics_precision();

    struct Impl;

private:
    explicit World(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace lpss
