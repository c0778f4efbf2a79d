// Small sector worlds stepped together, with one solver call for all of them.
//
// Bullet's world hands its islands to the solver in batches of at least m_minimumSolverBatchSize (128)
// contacts: one sector of 128 boxes resting apart makes one solver call per step. 128 sectors of one box
// made 128 calls, each with the solver's fixed cost (its set-up, and ten iterations over its arrays): a
// third of what many small sectors cost beyond one large one. Islands of different worlds share no body,
// and the sequential impulse solver treats contacts one by one in the order given, each island's in the
// same order whatever else is in the batch; with Bullet's residual threshold of zero it runs every
// iteration either way. So a group of small sectors goes through Bullet's stages world by world, but for
// the solver, which takes all their islands at once, as a single world of them all would.
#pragma once

#include <BulletCollision/CollisionDispatch/btSimulationIslandManager.h>
#include <BulletDynamics/ConstraintSolver/btConstraintSolver.h>
#include <BulletDynamics/ConstraintSolver/btContactSolverInfo.h>

#include <cstddef>

namespace lpss::engine {

class Sector;

/// The islands of several worlds, gathered for one solver call. Only for worlds without constraints
/// (lpss makes none) and sharing one solver configuration.
class IslandBatch : public btSimulationIslandManager::IslandCallback {
public:
    IslandBatch(btConstraintSolver& solver, const btContactSolverInfo& info) : solver_(solver), info_(info) {}
    /// Bullet's island manager hands each awake island here; a full batch is solved at once, as
    /// Bullet's own island callback does.
    void processIsland(btCollisionObject** bodies, int body_count, btPersistentManifold** manifolds,
                       int manifold_count, int island) override;
    /// Solves what is gathered.
    void solve();

private:
    btConstraintSolver& solver_;
    const btContactSolverInfo& info_;
    btAlignedObjectArray<btCollisionObject*> bodies_;
    btAlignedObjectArray<btPersistentManifold*> manifolds_;
};

/// One step of dt for the `count` sectors from `first` on, as Sector::step takes it for each, with one
/// solver call for their islands together. The sectors share the world's collision configuration and
/// settings.
void step_together(Sector* const* first, std::size_t count, btConstraintSolver& solver, btScalar dt);

}  // namespace lpss::engine
