// Stage 3, stepping: every sector in this frame's step set advances by dt, concurrently. A sector is
// only touched by the thread stepping it, and each thread brings its own solver (Debian's Bullet is
// not thread-safe: see shared_collision_configuration.hpp). After its step a sector records, for the
// next frame, whether it still holds anything awake, which originals were active, and what touches;
// then (merge_contacts) the stepped sectors hand what touched to the contact tracker.
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bullet_convert.hpp"
#include "island_batch.hpp"
#include "world_impl.hpp"

namespace lpss {

using engine::BodyRecord;
using engine::ContactRecord;
using engine::Role;
using engine::Sector;

namespace {

// Bullet keeps contact points up to 0.02 apart to warm-start the solver; bodies count as touching
// from this distance on.
constexpr btScalar kTouchDistance = btScalar(0.005);

Role role_of(const btCollisionObject* object) { return static_cast<Role>(object->getUserIndex2()); }

}  // namespace

void World::Impl::track_position(BodyRecord& rec, double dt) const {
    const Sector& sector = sector_of(rec);
    btTransform& transform = rec.rb->getWorldTransform();
    const btVector3 moved = transform.getOrigin();
    if (!precise_positions) {
        rec.local = sector.from_physics(moved);
        return;
    }
    // Per axis: if the float displacement Bullet made equals velocity * dt to within the float spacing
    // there, it is that motion plus rounding, and the motion is added in double; otherwise something
    // else moved the body (a contact's push-out, a clamped continuous-collision motion) and Bullet's
    // displacement is taken as it is. The float position is then the double one, rounded once, so
    // rounding never accumulates over frames in free flight.
    const btVector3& velocity = rec.rb->getLinearVelocity();
    const btScalar step = static_cast<btScalar>(dt);  // what Bullet stepped by
    const btVector3 start = sector.to_physics(rec.local);
    for (int a = 0; a < 3; ++a) {
        const btScalar before = start[a];
        const double displaced = static_cast<double>(moved[a]) - static_cast<double>(before);
        // The motion over the true step: Bullet steps by dt rounded to btScalar, which would make a body
        // at constant velocity drift by that rounding every frame. The comparison allows for both.
        const double by_velocity = static_cast<double>(velocity[a]) * dt;
        const double spacing =
            static_cast<double>(std::numeric_limits<btScalar>::epsilon()) *
                std::max(std::fabs(static_cast<double>(moved[a])), std::fabs(static_cast<double>(before))) +
            std::fabs(static_cast<double>(velocity[a]) * (static_cast<double>(step) - dt));
        rec.local[a] += std::fabs(displaced - by_velocity) <= spacing ? by_velocity : displaced;
    }
    transform.setOrigin(sector.to_physics(rec.local));
    rec.rb->setInterpolationWorldTransform(transform);
}

void World::Impl::note_active(Sector& sector) {
    // Bodies active before the step or after it may have moved: the change log's (a body woken by a
    // contact is active after; one that fell asleep, before).
    for (std::uint32_t slot : sector.originals) {
        BodyRecord& rec = bodies[slot];
        if (rec.dynamic && rec.moved_frame != frame && rec.rb->isActive()) {
            rec.moved_frame = frame;
            sector.moved.push_back(slot);
        }
    }
}

void World::Impl::track_positions(Sector& sector, double dt) {
    // The bodies active before the step (noted before it; one that fell asleep in it still moved) and
    // those a contact has woken since. A body asleep throughout has not moved: Bullet integrates active
    // bodies only, and a sector of resting boxes around one rolling ball is stepped whole.
    for (std::uint32_t slot : sector.originals) {
        BodyRecord& rec = bodies[slot];
        if (rec.dynamic && (rec.moved_frame == frame || rec.rb->isActive())) track_position(rec, dt);
    }
}

void World::Impl::finish_step(Sector& sector) {
    note_active(sector);
    bool awake = false;
    for (std::uint32_t slot : sector.originals) {
        const BodyRecord& rec = bodies[slot];
        if (rec.dynamic && rec.rb->isActive()) {
            awake = true;
            break;
        }
    }
    sector.awake = awake;

    // Touching pairs, named by the bodies' ids. Two clones touching say nothing about their
    // originals (who meet, if at all, in their own sectors), so they are skipped.
    sector.fresh_contacts.clear();
    const int manifolds = sector.dispatcher.getNumManifolds();
    for (int m = 0; m < manifolds; ++m) {
        const btPersistentManifold* manifold = sector.dispatcher.getManifoldByIndexInternal(m);
        const int points = manifold->getNumContacts();
        if (points == 0) continue;
        const btCollisionObject* o0 = manifold->getBody0();
        const btCollisionObject* o1 = manifold->getBody1();
        if (role_of(o0) == Role::Clone && role_of(o1) == Role::Clone) continue;
        btScalar nearest = std::numeric_limits<btScalar>::max();
        btScalar impulse = 0;
        btVector3 point(0, 0, 0);
        for (int p = 0; p < points; ++p) {
            const btManifoldPoint& contact = manifold->getContactPoint(p);
            nearest = std::min(nearest, contact.getDistance());
            impulse += contact.getAppliedImpulse();
            point += contact.getPositionWorldOnB();
        }
        if (nearest > kTouchDistance) continue;
        ContactRecord record;
        record.a = bodies[static_cast<std::size_t>(o0->getUserIndex())].id;
        record.b = bodies[static_cast<std::size_t>(o1->getUserIndex())].id;
        // Bullet's normal points from body 1 to body 0, ours from b to a.
        btVector3 normal = manifold->getContactPoint(0).m_normalWorldOnB;
        if (record.a > record.b) {
            std::swap(record.a, record.b);
            normal = -normal;
        }
        point /= static_cast<btScalar>(points);
        record.point = sector.from_physics(point);
        record.normal = Eigen::Vector3f(float(normal.x()), float(normal.y()), float(normal.z()));
        record.impulse = static_cast<float>(impulse);
        sector.fresh_contacts.push_back(record);
    }
    std::sort(
        sector.fresh_contacts.begin(), sector.fresh_contacts.end(),
        [](const ContactRecord& x, const ContactRecord& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
    // Last: moving the anchor leaves the manifolds' world points stale until the next step.
    follow_bodies(sector);
    // The bodies found active are the next frame's candidates: their reach is wanted then, and those
    // with nothing to do at the next sectorization and border update are left out of its visits.
    sector.visits.clear();
    for (std::uint32_t slot : sector.originals) {
        const BodyRecord& rec = bodies[slot];
        if (rec.moved_frame != frame) continue;
        const bool settled = border.prepare_reach(slot, frame + 1);
        if (!settled || rec.local.cwiseAbs().maxCoeff() >= band) sector.visits.push_back(slot);
    }
}

void World::Impl::step_sectors() {
    const int substeps = settings.substeps_per_frame();
    const double substep = settings.dt / substeps;
    const btScalar dt = static_cast<btScalar>(substep);
    // Consecutive small sectors go in groups that share their solver calls (island_batch.hpp); naive
    // sectors, which stand for plain Bullet, each go alone.
    step_groups.clear();
    step_sectors_scratch.clear();
    std::size_t group_objects = 0;
    for (std::size_t n = 0; n < step_set.size(); ++n) {
        Sector& sector = sectors.at(step_set[n]);
        step_sectors_scratch.push_back(&sector);
        const auto objects = static_cast<std::size_t>(sector.world.getNumCollisionObjects());
        const bool small =
            options.group_small_sectors && !sector.own_solver && objects <= kSmallSectorObjects;
        if (small && !step_groups.empty() && step_groups.back().small &&
            group_objects + objects <= kGroupObjects) {
            ++step_groups.back().end;
            group_objects += objects;
        } else {
            step_groups.push_back({n, n + 1, small});
            group_objects = objects;
        }
    }
    pool.run(step_groups.size(), [&](std::size_t index, int worker) {
        const StepGroup group = step_groups[index];
        btSequentialImpulseConstraintSolver& solver = *solvers[static_cast<std::size_t>(worker)];
        // Each sector is touched by one thread only.
        Sector* const* first = step_sectors_scratch.data() + group.begin;
        Sector* const* last = step_sectors_scratch.data() + group.end;
        for (Sector* const* sector = first; sector != last; ++sector)
            note_active(**sector);
        for (int n = 0; n < substeps; ++n) {
            if (last - first == 1) {
                (*first)->step(&solver, dt);
            } else {
                engine::step_together(first, group.end - group.begin, solver, dt);
            }
            for (Sector* const* sector = first; sector != last; ++sector)
                track_positions(**sector, substep);
        }
        for (Sector* const* sector = first; sector != last; ++sector)
            finish_step(**sector);
    });
}

void World::Impl::merge_contacts() {
    // In step-set order, so that a pair seen by several sectors takes its Begin event from the same one
    // in every run.
    for (engine::SectorId id : step_set) {
        Sector& sector = sectors.at(id);
        contacts.replace(sector.key, sector.contacts, sector.fresh_contacts);
        sector.contacts.swap(sector.fresh_contacts);
        if (sector.awake) wake(sector);
    }
    contacts.make_events();
}

}  // namespace lpss
