#include "sector.hpp"

#include <algorithm>

namespace lpss::engine {

Sector::Sector(const SectorKey& k, const Eigen::Vector3d& a, btCollisionConfiguration* configuration,
               btConstraintSolver* solver, const btVector3& gravity, const WorldSettings& settings)
    : key(k),
      anchor(a),
      dispatcher(configuration),
      broadphase(),
      world(&dispatcher, &broadphase, solver, configuration) {
    world.setGravity(gravity);
    world.getSolverInfo().m_numIterations = settings.solver_iterations;
    world.friction_rule = settings.friction_combine;
    world.restitution_rule = settings.restitution_combine;
    // Bodies are placed, moved and read by the engine directly: no interpolation of motion states.
    world.setSynchronizeAllMotionStates(false);
    // Only moving objects need their broadphase boxes refreshed each step; the engine refreshes a
    // sleeping clone's box itself when it moves one.
    world.setForceUpdateAllAabbs(false);
    world.skip_resting_prediction = true;
}

Sector::Sector(const SectorKey& k, const btVector3& gravity, const WorldSettings& settings)
    : key(k),
      own_configuration(std::make_unique<btDefaultCollisionConfiguration>()),
      own_solver(std::make_unique<btSequentialImpulseConstraintSolver>()),
      dispatcher(own_configuration.get()),
      broadphase(),
      world(&dispatcher, &broadphase, own_solver.get(), own_configuration.get()) {
    world.setGravity(gravity);
    world.getSolverInfo().m_numIterations = settings.solver_iterations;
    world.friction_rule = settings.friction_combine;
    world.restitution_rule = settings.restitution_combine;
    world.setSynchronizeAllMotionStates(false);
}

void DynamicsWorld::predictUnconstraintMotion(btScalar timeStep) {
    if (!skip_resting_prediction) return btDiscreteDynamicsWorld::predictUnconstraintMotion(timeStep);
    for (int i = 0; i < m_nonStaticRigidBodies.size(); i++) {
        btRigidBody* body = m_nonStaticRigidBodies[i];
        if (body->isStaticOrKinematicObject()) continue;
        if (body->getActivationState() == ISLAND_SLEEPING && body->getLinearVelocity().isZero() &&
            body->getAngularVelocity().isZero())
            continue;
        body->applyDamping(timeStep);
        body->predictIntegratedTransform(timeStep, body->getInterpolationWorldTransform());
    }
}

void DynamicsWorld::apply_contact_rules(const btContactSolverInfo& info) {
    if (friction_rule != CombineRule::product || restitution_rule != CombineRule::product)
        combine_materials(*getDispatcher(), friction_rule, restitution_rule);
    if (keep_bounce_energy) bouncing_contacts_keep_their_energy(*getDispatcher(), info);
}

void DynamicsWorld::solveConstraints(btContactSolverInfo& info) {
    apply_contact_rules(info);
    btDiscreteDynamicsWorld::solveConstraints(info);
}

// The three parts below are btDiscreteDynamicsWorld::stepSimulation(dt, 0) and the
// internalSingleStepSimulation it makes (Bullet 3.24), in order, cut around solveConstraints.
void DynamicsWorld::begin_step(btScalar dt) {
    m_localTime = m_latencyMotionStateInterpolation ? 0 : dt;
    m_fixedTimeStep = 0;
    saveKinematicState(dt);
    applyGravity();
    if (m_internalPreTickCallback != nullptr) m_internalPreTickCallback(this, dt);
    predictUnconstraintMotion(dt);
    btDispatcherInfo& dispatch = getDispatchInfo();
    dispatch.m_timeStep = dt;
    dispatch.m_stepCount = 0;
    dispatch.m_debugDraw = getDebugDrawer();
    createPredictiveContacts(dt);
    performDiscreteCollisionDetection();
    calculateSimulationIslands();
    getSolverInfo().m_timeStep = dt;
}

void DynamicsWorld::collect_islands(btSimulationIslandManager::IslandCallback& batch) {
    apply_contact_rules(getSolverInfo());
    m_islandManager->buildAndProcessIslands(getDispatcher(), this, &batch);
}

void DynamicsWorld::end_step(btScalar dt) {
    integrateTransforms(dt);
    updateActions(dt);
    updateActivationState(dt);
    if (m_internalTickCallback != nullptr) m_internalTickCallback(this, dt);
    synchronizeMotionStates();
    clearForces();
}

void combine_materials(btDispatcher& dispatcher, CombineRule friction, CombineRule restitution) {
    const int manifolds = dispatcher.getNumManifolds();
    for (int m = 0; m < manifolds; ++m) {
        btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
        const btCollisionObject* a = manifold->getBody0();
        const btCollisionObject* b = manifold->getBody1();
        // Bullet clamps a combined friction to 10 (MAX_FRICTION in btManifoldResult.cpp): so does lpss.
        const auto combined_friction =
            static_cast<btScalar>(std::min(combine(friction, a->getFriction(), b->getFriction()), 10.0));
        const auto combined_restitution =
            static_cast<btScalar>(combine(restitution, a->getRestitution(), b->getRestitution()));
        for (int p = 0; p < manifold->getNumContacts(); ++p) {
            btManifoldPoint& point = manifold->getContactPoint(p);
            point.m_combinedFriction = combined_friction;
            point.m_combinedRestitution = combined_restitution;
        }
    }
}

void bouncing_contacts_keep_their_energy(btDispatcher& dispatcher, const btContactSolverInfo& info) {
    const int manifolds = dispatcher.getNumManifolds();
    for (int m = 0; m < manifolds; ++m) {
        btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
        const btRigidBody* a = btRigidBody::upcast(manifold->getBody0());
        const btRigidBody* b = btRigidBody::upcast(manifold->getBody1());
        for (int p = 0; p < manifold->getNumContacts(); ++p) {
            btManifoldPoint& point = manifold->getContactPoint(p);
            // As Bullet's solver finds it (setupContactConstraint): the velocity of A relative to B along
            // the normal, which points from B to A; restitution acts when it approaches faster than the
            // threshold.
            btScalar approach = 0;
            if (point.m_combinedRestitution > 0) {
                const btVector3 va =
                    a ? a->getVelocityInLocalPoint(point.getPositionWorldOnA() - a->getCenterOfMassPosition())
                      : btVector3(0, 0, 0);
                const btVector3 vb =
                    b ? b->getVelocityInLocalPoint(point.getPositionWorldOnB() - b->getCenterOfMassPosition())
                      : btVector3(0, 0, 0);
                approach = -point.m_normalWorldOnB.dot(va - vb);
            }
            if (approach > info.m_restitutionVelocityThreshold) {
                point.m_contactPointFlags |= BT_CONTACT_FLAG_HAS_CONTACT_ERP;
                point.m_contactERP = 0;
                // A contact found before touching (a gap within the contact threshold) lets the bodies
                // close the gap: Bullet takes gap / dt off the bounce (a ball at 13 u/s between walls
                // came back at 12, then 11). Taken as touching, the bounce keeps its speed; the position
                // is off by at most the gap. Collision detection measures the gap again next step.
                if (point.getDistance() > 0) point.setDistance(0);
            } else {
                point.m_contactPointFlags &= ~BT_CONTACT_FLAG_HAS_CONTACT_ERP;
            }
        }
    }
}

Sector::~Sector() {
    // Objects still inserted belong to bodies that outlive this sector: take them out first so that the
    // world does not touch them while it is torn down.
    btCollisionObjectArray& objects = world.getCollisionObjectArray();
    for (int n = objects.size() - 1; n >= 0; --n)
        world.removeCollisionObject(objects[n]);
}

void Sector::move_anchor(const Eigen::Vector3d& to) {
    // Anchors are multiples of a power of two no finer than the float spacing at the sector's scale, so
    // the shift is exact for every coordinate it applies to; contact manifolds keep body-relative
    // points and refresh their world points at the next step.
    const btVector3 shift = to_bt(to - anchor);
    anchor = to;
    btCollisionObjectArray& objects = world.getCollisionObjectArray();
    for (int n = 0; n < objects.size(); ++n) {
        btCollisionObject* object = objects[n];
        btTransform t = object->getWorldTransform();
        t.setOrigin(t.getOrigin() - shift);
        object->setWorldTransform(t);
        object->setInterpolationWorldTransform(t);
        world.updateSingleAabb(object);
    }
}

void Sector::step(btConstraintSolver* solver, btScalar dt) {
    if (!own_solver) world.setConstraintSolver(solver);
    // maxSubSteps = 0: exactly one step of dt, no accumulator, no interpolation.
    world.stepSimulation(dt, 0);
}

}  // namespace lpss::engine
