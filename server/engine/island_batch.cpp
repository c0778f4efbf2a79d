// Small sector worlds stepped together (island_batch.hpp says why that gives what stepping each does).
#include "island_batch.hpp"

#include "sector.hpp"

namespace lpss::engine {

void IslandBatch::processIsland(btCollisionObject** bodies, int body_count, btPersistentManifold** manifolds,
                                int manifold_count, int /*island*/) {
    for (int n = 0; n < body_count; ++n)
        bodies_.push_back(bodies[n]);
    for (int n = 0; n < manifold_count; ++n)
        manifolds_.push_back(manifolds[n]);
    if (manifolds_.size() > info_.m_minimumSolverBatchSize) solve();
}

void IslandBatch::solve() {
    if (bodies_.size() == 0) return;
    solver_.solveGroup(&bodies_[0], bodies_.size(), manifolds_.size() != 0 ? &manifolds_[0] : nullptr,
                       manifolds_.size(), nullptr, 0, info_, nullptr, nullptr);
    bodies_.resize(0);
    manifolds_.resize(0);
}

void step_together(Sector* const* first, std::size_t count, btConstraintSolver& solver, btScalar dt) {
    Sector* const* last = first + count;
    for (Sector* const* sector = first; sector != last; ++sector)
        (*sector)->world.begin_step(dt);
    IslandBatch batch(solver, (*first)->world.getSolverInfo());
    for (Sector* const* sector = first; sector != last; ++sector)
        (*sector)->world.collect_islands(batch);
    batch.solve();
    for (Sector* const* sector = first; sector != last; ++sector)
        (*sector)->world.end_step(dt);
}

}  // namespace lpss::engine
