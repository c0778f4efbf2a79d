// One sector: a Bullet world in sector-local coordinates plus the bookkeeping the stages need.
#pragma once

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionDispatch/btSimulationIslandManager.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/Dynamics/btDiscreteDynamicsWorld.h>

#include <memory>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "bullet_convert.hpp"
#include "contact_tracker.hpp"
#include "lpss/common/body_desc.hpp"
#include "lpss/common/sector_key.hpp"
#include "lpss/common/world_settings.hpp"
#include "overhang_bound.hpp"
#include "sector_id.hpp"

namespace lpss::engine {

/// Bullet's dynamics world, with two changes:
/// - it gives back the manifolds of its last step's predictive (CCD) contacts when it is destroyed:
///   btDiscreteDynamicsWorld frees them only at the start of the next step, so a sector destroyed right
///   after stepping a fast body would leak them (LeakSanitizer found it);
/// - a bouncing contact gains no energy from penetration recovery (see bouncing_contacts_keep_their_energy);
/// - contacts combine their bodies' friction and restitution by the scene's rules (combine_materials).
class DynamicsWorld : public btDiscreteDynamicsWorld {
public:
    using btDiscreteDynamicsWorld::btDiscreteDynamicsWorld;
    ~DynamicsWorld() override { releasePredictiveContacts(); }
    void solveConstraints(btContactSolverInfo& info) override;
    /// A step of dt as stepSimulation(dt, 0) takes it, cut where the solver runs so that several worlds
    /// can share one solver call (island_batch.hpp): begin_step runs everything before the solver,
    /// collect_islands gives the batch this world's awake islands (with the contact rules applied, as
    /// solveConstraints does), end_step runs everything after. Bullet's profiler is left out.
    void begin_step(btScalar dt);
    void collect_islands(btSimulationIslandManager::IslandCallback& batch);
    void end_step(btScalar dt);
    /// Bullet's, but for bodies asleep with both velocities exactly zero, which Bullet damps (zero stays
    /// zero) and predicts (to where they are) every substep, asleep or not: in a sector of resting boxes
    /// with one ball rolling through, that was every box, every substep. What the prediction writes (the
    /// interpolation transform) is read before the next prediction only for bodies awake, so results do
    /// not change. Off for a naive sector, which is plain Bullet.
    void predictUnconstraintMotion(btScalar timeStep) override;

    /// The scene's rules for a contact's friction and restitution (Bullet's own rule is the product).
    CombineRule friction_rule = CombineRule::product;
    CombineRule restitution_rule = CombineRule::product;
    bool keep_bounce_energy = true;        ///< false: Bullet's own push (EngineOptions::bullet_bounces)
    bool skip_resting_prediction = false;  ///< see predictUnconstraintMotion

private:
    /// The scene's contact rules, applied to this step's contacts before they are solved.
    void apply_contact_rules(const btContactSolverInfo& info);
};

/// Sets every contact's friction and restitution by the world's rules: Bullet combines them by product
/// when it finds a contact (through process-wide callbacks, which lpss leaves alone), so the other rules
/// are applied here, before each solve, from the two bodies' coefficients.
void combine_materials(btDispatcher& dispatcher, CombineRule friction, CombineRule restitution);

/// Bullet pushes penetrating bodies apart by adding velocity (Baumgarte: erp x depth / dt) on top of the
/// velocity restitution gives them: at dt = 1/60 an impact is found up to a step's motion deep, so every
/// bounce gained energy (two equal spheres of restitution 1 left a head-on collision 10% faster; a ball of
/// restitution 1 bounced higher each time). For the contacts restitution acts on this step (approaching
/// faster than the solver's restitution threshold, restitution above 0), the push is turned off (the bounce
/// separates them), and a gap still open is taken as closed (else the bounce loses gap / dt). Resting
/// contacts keep Bullet's push, which holds stacks still.
void bouncing_contacts_keep_their_energy(btDispatcher& dispatcher, const btContactSolverInfo& info);

/// Bullet objects first, so that they are built before and destroyed after the world using them.
/// A sector owns no bodies: originals and clones belong to their BodyRecord and are only inserted here.
class Sector {
public:
    /// A sector sharing the world's collision configuration, stepped with a thread's solver.
    Sector(const SectorKey& key, const Eigen::Vector3d& anchor, btCollisionConfiguration* configuration,
           btConstraintSolver* solver, const btVector3& gravity, const WorldSettings& settings);
    /// A naive sector (EngineOptions::naive_sector_worlds): a default Bullet world of its own.
    Sector(const SectorKey& key, const btVector3& gravity, const WorldSettings& settings);
    ~Sector();
    Sector(const Sector&) = delete;
    Sector& operator=(const Sector&) = delete;

    /// Steps the Bullet world once by dt with the given solver (each thread brings its own; a naive
    /// sector uses its own).
    void step(btConstraintSolver* solver, btScalar dt);

    /// A sector-local position in the Bullet world's frame, and back.
    btVector3 to_physics(const Eigen::Vector3d& local) const { return to_bt(local - anchor); }
    Eigen::Vector3d from_physics(const btVector3& p) const { return anchor + to_eigen(p); }

    /// Moves the Bullet world's origin to a new anchor: every object in it is shifted.
    void move_anchor(const Eigen::Vector3d& to);

    const SectorKey key;
    SectorId id;  ///< given by the SectorTable that holds it
    // Only naive sectors own these; they come first so that they outlive the world using them.
    std::unique_ptr<btDefaultCollisionConfiguration> own_configuration;
    std::unique_ptr<btSequentialImpulseConstraintSolver> own_solver;
    /// Where, in sector-local coordinates, the Bullet world's origin sits. It follows the sector's
    /// bodies so that the floats Bullet computes with stay as small as the spread of those bodies,
    /// not as large as their offset from the sector's centre.
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
    btCollisionDispatcher dispatcher;
    btDbvtBroadphase broadphase;
    DynamicsWorld world;

    std::vector<std::uint32_t> originals;  ///< slots of the bodies this sector owns
    std::vector<std::uint32_t> hosted;     ///< slots of bodies with a clone or plane instance here
    /// Slots of the originals with partners (kept by the BorderIndex): the only ones the cloning stage
    /// looks at, so that a stepped sector's bodies far from its borders cost nothing there.
    std::vector<std::uint32_t> partnered;
    std::vector<ContactRecord> contacts;        ///< touching pairs at the last step, sorted by (a, b)
    std::vector<ContactRecord> fresh_contacts;  ///< filled by the step, merged serially afterwards
    std::vector<std::uint32_t> moved;  ///< originals active during the step (slots), logged serially after
    /// Slots of the originals the step moved that the next frame's sectorization or border index has
    /// work for (beyond the hysteresis band, or out of their fat reach box): found by the stepping
    /// thread, where the body is in cache, so that the serial stages do not walk the rest (Box2D's
    /// enlarged-box flags, set in its solver's threads, serve the same end).
    std::vector<std::uint32_t> visits;

    /// How far its originals' fat reach boxes reach beyond their broadphase boxes, measured each time
    /// either moved (BorderIndex::note_overhang): the growth of queries that look for this sector's
    /// bodies by fat box.
    OverhangBound overhangs;
    bool awake = false;   ///< holds an awake dynamic original
    bool remote = false;  ///< simulated by another process: holds ghosts, never stepped here
    bool in_awake_list = false;
    bool stepping = false;  ///< in this frame's set of sectors to step
};

}  // namespace lpss::engine
