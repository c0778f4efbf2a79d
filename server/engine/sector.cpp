#include "sector.hpp"

namespace lpss::engine {

Sector::Sector(const SectorKey& k, btCollisionConfiguration* configuration, btConstraintSolver* solver,
               const btVector3& gravity)
    : key(k), dispatcher(configuration), broadphase(), world(&dispatcher, &broadphase, solver, configuration) {
    world.setGravity(gravity);
    // Bodies are placed, moved and read by the engine directly: no interpolation of motion states.
    world.setSynchronizeAllMotionStates(false);
    // Only moving objects need their broadphase boxes refreshed each step; the engine refreshes a
    // sleeping clone's box itself when it moves one.
    world.setForceUpdateAllAabbs(false);
}

Sector::~Sector() {
    // Objects still inserted belong to bodies that outlive this sector: take them out first so that the
    // world does not touch them while it is torn down.
    btCollisionObjectArray& objects = world.getCollisionObjectArray();
    for (int n = objects.size() - 1; n >= 0; --n) world.removeCollisionObject(objects[n]);
}

void Sector::step(btConstraintSolver* solver, btScalar dt) {
    world.setConstraintSolver(solver);
    // maxSubSteps = 0: exactly one step of dt, no accumulator, no interpolation.
    world.stepSimulation(dt, 0);
}

}  // namespace lpss::engine
