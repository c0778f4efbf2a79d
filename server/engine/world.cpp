// The engine's API: creating worlds, adding and removing bodies, commands and queries; the creation
// and destruction of sectors; and the frame driver that runs the stages in order.
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_set>

#include "bullet_convert.hpp"
#include "collision_shapes.hpp"
#include "world_impl.hpp"

namespace lpss {

using engine::BodyRecord;
using engine::Clone;
using engine::Role;
using engine::Sector;
using engine::to_bt;
using engine::to_eigen;

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <class T>
void erase_value(std::vector<T>& values, const T& value) {
    auto it = std::find(values.begin(), values.end(), value);
    if (it != values.end()) {
        *it = values.back();
        values.pop_back();
    }
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// Construction

World::Impl::Impl(const WorldSettings& s, const EngineOptions& o)
    : settings(s),
      options(o),
      grid(s.sector_size),
      band(o.monolithic ? std::numeric_limits<double>::infinity() : s.sector_size * (0.5 + s.hysteresis)),
      precise_positions(o.double_positions && !o.monolithic),
      // A power of two, about L/64: far coarser than the float spacing inside a sector, so shifting by
      // an anchor is exact, and fine enough to keep the bodies' coordinates small.
      anchor_quantum(o.floating_origins && !o.monolithic && !o.naive_sector_worlds
                         ? std::ldexp(1.0, std::ilogb(s.sector_size) - 6)
                         : 0.0),
      gravity(to_bt(s.gravity)),
      pool(std::max(1, o.threads)) {
    for (int t = 0; t < pool.size(); ++t) {
        solvers.push_back(std::make_unique<btSequentialImpulseConstraintSolver>());
    }
}

World::Impl::~Impl() {
    // Sectors take the objects out of their Bullet worlds; the bodies' Bullet objects go afterwards.
    sectors = engine::SectorTable{};
}

World::World(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;
World::~World() = default;

Expected<World> World::create(const WorldSettings& settings, const EngineOptions& options) {
    if (Status st = validate(settings); !st) return st.error();
    if (options.threads < 1 || options.threads > 256) {
        return Error{"threads must be between 1 and 256, got " + std::to_string(options.threads)};
    }
    return World(std::make_unique<Impl>(settings, options));
}

Expected<World> World::create(const Scene& scene, const EngineOptions& options) {
    Expected<World> world = create(scene.settings, options);
    if (!world) return world;
    if (Status st = world->add_bodies(scene.bodies); !st) return st.error();
    return world;
}

const char* World::physics_precision() { return sizeof(btScalar) == sizeof(double) ? "double" : "float"; }

// ---------------------------------------------------------------------------------------------------
// Sectors

Eigen::Vector3d World::Impl::anchor_near(const Eigen::Vector3d& local) const {
    if (anchor_quantum == 0.0) return Eigen::Vector3d::Zero();
    return (local / anchor_quantum).array().round() * anchor_quantum;
}

void World::Impl::follow_bodies(Sector& sector) {
    // The anchor follows the centre of the box around the sector's originals once that centre has moved
    // by more than L/16: rarely enough to cost nothing, often enough that Bullet's coordinates stay
    // within the bodies' own spread.
    if (anchor_quantum == 0.0 || sector.originals.empty()) return;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    for (std::uint32_t slot : sector.originals) {
        lo = lo.cwiseMin(record(slot).local);
        hi = hi.cwiseMax(record(slot).local);
    }
    Eigen::Vector3d centre = 0.5 * (lo + hi);
    if ((centre - sector.anchor).cwiseAbs().maxCoeff() <= settings.sector_size / 16.0) return;
    sector.move_anchor(anchor_near(centre));
    // Originals are placed again from their double positions, so that no rounding is added.
    for (std::uint32_t slot : sector.originals) {
        btRigidBody& rb = *record(slot).rb;
        rb.getWorldTransform().setOrigin(sector.to_physics(record(slot).local));
        rb.setInterpolationWorldTransform(rb.getWorldTransform());
        sector.world.updateSingleAabb(&rb);
    }
}

Sector& World::Impl::sector_for(const SectorKey& key, const Eigen::Vector3d& first_local) {
    if (Sector* existing = sectors.find(key)) return *existing;
    auto sector = options.naive_sector_worlds
                      ? std::make_unique<Sector>(key, gravity, settings)
                      : std::make_unique<Sector>(key, anchor_near(first_local), configuration.get(),
                                                 solvers[0].get(), gravity, settings);
    sector->remote = !owns(key);
    sector->world.keep_bounce_energy = !options.bullet_bounces;
    Sector& s = sectors.insert(std::move(sector));
    for (std::uint32_t slot : planes)
        add_plane_instance(slot, s);
    return s;
}

void World::Impl::destroy_sector(Sector& sector) {
    // Clones and plane instances hosted here go back to their bodies; what the sector saw touching ends.
    for (std::size_t n = sector.hosted.size(); n-- > 0;) {
        if (n >= sector.hosted.size()) continue;
        std::uint32_t slot = sector.hosted[n];
        BodyRecord& rec = record(slot);
        if (rec.plane) {
            auto it = std::find_if(rec.clones.begin(), rec.clones.end(),
                                   [&](const Clone& c) { return c.host == sector.id; });
            sector.world.removeRigidBody(it->rb.get());
            *it = std::move(rec.clones.back());
            rec.clones.pop_back();
            sector.hosted[n] = sector.hosted.back();
            sector.hosted.pop_back();
        } else {
            release_clone(slot, sector);
        }
    }
    contacts.forget_all(sector.contacts, sector.key);
    erase_value(awake_list, sector.id);
    erase_value(step_set, sector.id);
    sectors.erase(sector.id);
}

void World::Impl::wake(Sector& sector) {
    if (sector.remote) return;  // another process steps it
    sector.awake = true;
    if (!sector.in_awake_list) {
        sector.in_awake_list = true;
        awake_list.push_back(sector.id);
    }
}

void World::Impl::add_plane_instance(std::uint32_t slot, Sector& sector) {
    BodyRecord& rec = record(slot);
    const Plane& plane = std::get<Plane>(rec.desc->shape);
    // The plane's constant in this sector's frame. A sector far from the plane cannot hold anything
    // that touches it (bodies and their clones stay within about 2 L of the sector's centre), and its
    // constant would be a large float: such sectors get no instance.
    double constant = plane.offset + plane.normal.dot(grid.offset_in(rec.plane_anchor, sector.key));
    if (!options.monolithic && std::fabs(constant) > 3.0 * settings.sector_size) return;
    constant -= plane.normal.dot(sector.anchor);
    btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, rec.shape.get());
    info.m_friction = static_cast<btScalar>(rec.desc->material.friction);
    info.m_restitution = static_cast<btScalar>(rec.desc->material.restitution);
    auto rb = std::make_unique<btRigidBody>(info);
    rb->setUserIndex(static_cast<int>(slot));
    rb->setUserIndex2(static_cast<int>(Role::PlaneInstance));
    rb->setWorldTransform(btTransform(btQuaternion::getIdentity(), to_bt(plane.normal * constant)));
    sector.world.addRigidBody(rb.get());
    sector.hosted.push_back(slot);
    rec.clones.push_back(Clone{sector.id, std::move(rb), 0});
}

// ---------------------------------------------------------------------------------------------------
// Bodies

Expected<std::uint32_t> World::Impl::slot_of(BodyId id) const {
    auto it = slots.find(id);
    if (it == slots.end()) return Error{"unknown body id " + std::to_string(id)};
    return it->second;
}

Status World::Impl::check_new_body(const BodyDesc& body) const {
    if (Status st = validate_body(body, settings, !options.monolithic); !st) return st;
    if (slots.count(body.id)) return Error{describe_body(body) + ": id is used by another body"};
    return {};
}

void World::Impl::insert_body(const BodyDesc& desc) {
    std::uint32_t slot;
    if (!free_slots.empty()) {
        slot = free_slots.back();
        free_slots.pop_back();
    } else {
        slot = static_cast<std::uint32_t>(bodies.size());
        bodies.emplace_back();
    }
    BodyRecord& rec = record(slot);
    rec = BodyRecord{};
    rec.id = desc.id;
    rec.desc = std::make_unique<BodyDesc>(desc);
    rec.desc->orientation.normalize();
    rec.alive = true;
    rec.dynamic = desc.mass > 0.0;
    rec.plane = is_plane(desc.shape);
    rec.shape = shapes.get(desc.shape);
    rec.bound_radius = lpss::bounding_radius(desc.shape);
    slots.emplace(desc.id, slot);

    // Validated already: the position resolves.
    SectorPosition where;
    if (const auto* global = std::get_if<Eigen::Vector3d>(&desc.position)) {
        where = options.monolithic ? SectorPosition{{}, *global} : grid.from_global(*global).value();
    } else {
        const auto& given = std::get<SectorPosition>(desc.position);
        where =
            options.monolithic ? SectorPosition{{}, grid.to_global(given)} : grid.canonical(given).value();
    }

    if (rec.plane) {
        std::get<Plane>(rec.desc->shape).normal.normalize();
        rec.plane_anchor = where;
        planes.push_back(slot);
        sectors.for_each([&](Sector& sector) { add_plane_instance(slot, sector); });
        return;
    }

    rec.mass = static_cast<btScalar>(desc.mass);
    if (rec.dynamic) rec.shape->calculateLocalInertia(rec.mass, rec.inertia);
    btRigidBody::btRigidBodyConstructionInfo info(rec.mass, nullptr, rec.shape.get(), rec.inertia);
    info.m_friction = static_cast<btScalar>(desc.material.friction);
    info.m_restitution = static_cast<btScalar>(desc.material.restitution);
    rec.rb = std::make_unique<btRigidBody>(info);
    btRigidBody& rb = *rec.rb;
    rb.setUserIndex(static_cast<int>(slot));
    rb.setUserIndex2(static_cast<int>(Role::Original));
    if (desc.ccd && rec.dynamic) {
        rb.setCcdMotionThreshold(static_cast<btScalar>(0.5 * engine::inner_radius(desc.shape)));
        rb.setCcdSweptSphereRadius(static_cast<btScalar>(0.9 * engine::inner_radius(desc.shape)));
    }
    if (rec.dynamic && !settings.sleeping) rb.forceActivationState(DISABLE_DEACTIVATION);
    // Forced: a body merely set to sleep would be woken by Bullet at its first step.
    if (rec.dynamic && desc.asleep) rb.forceActivationState(ISLAND_SLEEPING);
    rb.setLinearVelocity(to_bt(desc.linear_velocity));
    rb.setAngularVelocity(to_bt(desc.angular_velocity));

    Sector& sector = sector_for(where.sector, where.local);
    // Without double positions the engine holds what Bullet holds: the position rounded to btScalar.
    rec.local = precise_positions ? where.local : sector.from_physics(sector.to_physics(where.local));
    rb.setWorldTransform(btTransform(to_bt(rec.desc->orientation), sector.to_physics(where.local)));
    rb.setInterpolationWorldTransform(rb.getWorldTransform());
    sector.world.addRigidBody(&rb);
    rec.sector = sector.id;
    rec.index_in_sector = static_cast<std::uint32_t>(sector.originals.size());
    sector.originals.push_back(slot);
    if (rec.dynamic && !desc.asleep) wake(sector);
    dirty.push_back(slot);
}

Status World::add_body(const BodyDesc& body) {
    if (Status st = impl_->check_new_body(body); !st) return st;
    impl_->insert_body(body);
    return {};
}

Status World::add_bodies(const std::vector<BodyDesc>& bodies) {
    std::unordered_set<BodyId> ids;
    for (const BodyDesc& body : bodies) {
        if (Status st = impl_->check_new_body(body); !st) return st;
        if (!ids.insert(body.id).second) return Error{describe_body(body) + ": id is used by another body"};
    }
    reserve(body_count() + bodies.size());
    for (const BodyDesc& body : bodies)
        impl_->insert_body(body);
    return {};
}

Status World::remove_body(BodyId id) {
    Impl& w = *impl_;
    Expected<std::uint32_t> found = w.slot_of(id);
    if (!found) return found.error();
    std::uint32_t slot = found.value();
    BodyRecord& rec = w.record(slot);
    if (rec.plane) {
        for (Clone& c : rec.clones) {
            Sector& host = w.sectors.at(c.host);
            host.world.removeRigidBody(c.rb.get());
            erase_value(host.hosted, slot);
            w.forget_contacts(host, id);
        }
        rec.clones.clear();
        erase_value(w.planes, slot);
    } else {
        while (!rec.clones.empty())
            w.release_clone(slot, w.sectors.at(rec.clones.back().host));
        Sector& sector = w.sector_of(rec);
        w.forget_contacts(sector, id);
        sector.world.removeRigidBody(rec.rb.get());
        std::uint32_t moved = sector.originals.back();
        sector.originals[rec.index_in_sector] = moved;
        w.record(moved).index_in_sector = rec.index_in_sector;
        sector.originals.pop_back();
        w.border.remove(slot);
        w.changes.left(sector.key, id);
        if (sector.originals.empty()) w.destroy_sector(sector);
    }
    w.dirty.erase(std::remove(w.dirty.begin(), w.dirty.end(), slot), w.dirty.end());
    w.spare_count -= rec.spare_clones.size();
    rec = BodyRecord{};
    w.free_slots.push_back(slot);
    w.slots.erase(id);
    return {};
}

void World::Impl::move_body(std::uint32_t slot, const SectorPosition& to) {
    BodyRecord& rec = record(slot);
    border.forget_reach(slot);
    Sector& dest = sector_for(to.sector, to.local);  // may create a sector: `from` is looked up after
    Sector& from = sector_of(rec);
    btTransform transform = rec.rb->getWorldTransform();
    transform.setOrigin(dest.to_physics(to.local));
    rec.local = precise_positions ? to.local : dest.from_physics(transform.getOrigin());
    if (Clone* clone = rec.clone_in(dest.id)) {
        // The body already has a clone in its new sector: the clone becomes the original and the old
        // original the clone. Both keep their contact manifolds, so resting contacts carry on unbroken.
        std::swap(clone->rb, rec.rb);
        clone->host = from.id;
        btRigidBody& now = *rec.rb;
        const btRigidBody& before = *clone->rb;
        now.setWorldTransform(transform);
        now.setInterpolationWorldTransform(transform);
        now.setLinearVelocity(before.getLinearVelocity());
        now.setAngularVelocity(before.getAngularVelocity());
        now.forceActivationState(before.getActivationState());
        now.setDeactivationTime(before.getDeactivationTime());
        now.setUserIndex2(static_cast<int>(Role::Original));
        clone->rb->setUserIndex2(static_cast<int>(Role::Clone));
        // Its broadphase box is the clone's, as of the last cloning stage: a body at rest keeps it until it
        // wakes, so its sector would find no pair for it where it is now (and its fat box would be made
        // from where it was). Seen in RandomCalls: a body moved by set_state into a sector holding its
        // clone.
        dest.world.updateSingleAabb(&now);
        erase_value(dest.hosted, slot);
        from.hosted.push_back(slot);
    } else {
        from.world.removeRigidBody(rec.rb.get());
        rec.rb->setWorldTransform(transform);
        rec.rb->setInterpolationWorldTransform(transform);
        dest.world.addRigidBody(rec.rb.get());
        forget_contacts(from, rec.id);
    }
    std::uint32_t moved = from.originals.back();
    from.originals[rec.index_in_sector] = moved;
    record(moved).index_in_sector = rec.index_in_sector;
    from.originals.pop_back();
    rec.sector = dest.id;
    rec.index_in_sector = static_cast<std::uint32_t>(dest.originals.size());
    dest.originals.push_back(slot);
    wake(dest);
    changes.left(from.key, rec.id);
    changes.touched(dest.key, slot);
    if (from.originals.empty()) pending_destroy.push_back(from.id);
    // A jump of more than a sector (set_state, a very fast body) leaves clones no partner can need.
    for (std::size_t n = rec.clones.size(); n-- > 0;) {
        Sector& host = sectors.at(rec.clones[n].host);
        if (sector_distance(host.key, dest.key) > engine::kCloneNeighbourhood) release_clone(slot, host);
    }
}

Status World::apply_impulse(BodyId id, const Eigen::Vector3d& impulse, const Eigen::Vector3d& offset) {
    Impl& w = *impl_;
    Expected<std::uint32_t> found = w.slot_of(id);
    if (!found) return found.error();
    BodyRecord& rec = w.record(found.value());
    if (!impulse.allFinite() || !offset.allFinite()) {
        return Error{describe_body(*rec.desc) + ": impulse and offset must be finite"};
    }
    if (!rec.dynamic) return Error{describe_body(*rec.desc) + ": is static and takes no impulse"};
    Sector& sector = w.sector_of(rec);
    if (sector.remote) return Error{describe_body(*rec.desc) + ": is simulated by another worker"};
    // The velocities the impulse would give, checked before it is applied, so that a refused one
    // changes nothing.
    // In double, so that an impulse beyond float's range is named as too fast, not as infinite.
    const btRigidBody& rb = *rec.rb;
    const Eigen::Vector3d linear = to_eigen(rb.getLinearVelocity()) + impulse * rb.getInvMass();
    const btMatrix3x3& inv_inertia = rb.getInvInertiaTensorWorld();
    const Eigen::Vector3d torque = offset.cross(impulse);
    Eigen::Vector3d angular = to_eigen(rb.getAngularVelocity());
    for (int r = 0; r < 3; ++r)
        angular[r] += to_eigen(inv_inertia.getRow(r)).dot(torque);
    if (Status st = check_velocity(linear, angular, w.settings); !st) {
        return Error{describe_body(*rec.desc) + ": the impulse is too large: " + st.error().message};
    }
    rec.rb->activate(true);
    rec.rb->applyImpulse(to_bt(impulse), to_bt(offset));
    w.wake(sector);
    w.dirty.push_back(found.value());
    return {};
}

Status World::set_velocity(BodyId id, const Eigen::Vector3d& linear, const Eigen::Vector3d& angular) {
    Impl& w = *impl_;
    Expected<std::uint32_t> found = w.slot_of(id);
    if (!found) return found.error();
    BodyRecord& rec = w.record(found.value());
    if (Status st = check_velocity(linear, angular, w.settings); !st) {
        return Error{describe_body(*rec.desc) + ": " + st.error().message};
    }
    if (!rec.dynamic) return Error{describe_body(*rec.desc) + ": is static and has no velocity"};
    Sector& sector = w.sector_of(rec);
    if (sector.remote) return Error{describe_body(*rec.desc) + ": is simulated by another worker"};
    rec.rb->activate(true);
    rec.rb->setLinearVelocity(to_bt(linear));
    rec.rb->setAngularVelocity(to_bt(angular));
    w.wake(sector);
    w.dirty.push_back(found.value());
    return {};
}

Status World::set_state(const BodySnapshot& state) {
    Impl& w = *impl_;
    Expected<std::uint32_t> found = w.slot_of(state.id);
    if (!found) return found.error();
    const std::uint32_t slot = found.value();
    BodyRecord& rec = w.record(slot);
    if (!rec.dynamic) return Error{describe_body(*rec.desc) + ": is static and cannot be moved"};
    if (!state.position.local.allFinite() || !in_range(state.position.sector) ||
        !state.orientation.coeffs().allFinite() || state.orientation.norm() < 1e-9 ||
        !state.linear_velocity.allFinite() || !state.angular_velocity.allFinite()) {
        return Error{describe_body(*rec.desc) + ": state is not finite"};
    }
    if (Status st = check_velocity(state.linear_velocity, state.angular_velocity, w.settings); !st) {
        return Error{describe_body(*rec.desc) + ": " + st.error().message};
    }
    // The body goes to the sector given, as its owner keeps it (past the border by up to the hysteresis
    // band): a ghost must not become this engine's own body by crossing a border its owner has not
    // handed it over yet. Only an offset beyond a whole sector is brought back into its cell.
    Expected<SectorPosition> at = state.position.local.cwiseAbs().maxCoeff() <= w.settings.sector_size
                                      ? Expected<SectorPosition>(state.position)
                                      : w.grid.canonical(state.position);
    if (!at) return Error{describe_body(*rec.desc) + ": " + at.error().message};
    w.place_body(slot, at.value(), state.orientation.normalized());
    btRigidBody& rb = *rec.rb;
    rb.setLinearVelocity(to_bt(state.linear_velocity));
    rb.setAngularVelocity(to_bt(state.angular_velocity));
    if (state.awake) {
        rb.activate(true);
        w.wake(w.sector_of(rec));
    } else if (rb.getActivationState() != DISABLE_DEACTIVATION) {
        rb.forceActivationState(ISLAND_SLEEPING);
    }
    w.dirty.push_back(slot);
    return {};
}

void World::Impl::place_body(std::uint32_t slot, const SectorPosition& at,
                             const Eigen::Quaterniond& orientation) {
    BodyRecord& rec = record(slot);
    if (at.sector != sector_of(rec).key) move_body(slot, at);
    Sector& sector = sector_of(rec);
    rec.local = precise_positions ? at.local : sector.from_physics(sector.to_physics(at.local));
    btRigidBody& rb = *rec.rb;
    rb.setWorldTransform(btTransform(to_bt(orientation), sector.to_physics(at.local)));
    rb.setInterpolationWorldTransform(rb.getWorldTransform());
    if (rb.getBroadphaseHandle() != nullptr) sector.world.updateSingleAabb(&rb);
}

void World::set_ownership(std::function<bool(const SectorKey&)> owns) {
    Impl& w = *impl_;
    w.options.owns = std::move(owns);
    w.sectors.for_each([&](Sector& sector) {
        const bool remote = !w.owns(sector.key);
        if (remote == sector.remote) return;
        sector.remote = remote;
        if (remote) {
            // Its bodies become ghosts: nothing here steps them any more.
            sector.awake = false;
            erase_value(w.awake_list, sector.id);
            sector.in_awake_list = false;
        } else {
            for (std::uint32_t slot : sector.originals) {
                if (w.record(slot).dynamic && w.record(slot).rb->isActive()) w.wake(sector);
            }
        }
        for (std::uint32_t slot : sector.originals)
            w.dirty.push_back(slot);
    });
}

bool World::is_ghost(BodyId id) const {
    Expected<std::uint32_t> slot = impl_->slot_of(id);
    return slot && !impl_->record(slot.value()).plane && impl_->sector_of(impl_->record(slot.value())).remote;
}

bool World::Impl::departs(const BodyRecord& rec) const {
    if (!rec.alive || rec.plane || !rec.dynamic || rec.local.cwiseAbs().maxCoeff() < band) return false;
    const Sector& sector = sector_of(rec);
    if (sector.remote) return false;
    Expected<SectorPosition> to = grid.canonical(SectorPosition{sector.key, rec.local});
    return to && !owns(to->sector);
}

std::vector<Departure> World::departures() const {
    const Impl& w = *impl_;
    std::vector<Departure> out;
    // Sectorization lists the bodies it leaves past a border; a slot reused since may be listed twice.
    for (std::uint32_t slot : w.departing) {
        const BodyRecord& rec = w.record(slot);
        if (!w.departs(rec)) continue;
        out.push_back(
            Departure{rec.id, w.grid.canonical(SectorPosition{w.sector_of(rec).key, rec.local}).value()});
    }
    std::sort(out.begin(), out.end(), [](const Departure& a, const Departure& b) { return a.id < b.id; });
    out.erase(std::unique(out.begin(), out.end(),
                          [](const Departure& a, const Departure& b) { return a.id == b.id; }),
              out.end());
    return out;
}

std::vector<BodySnapshot> World::sector_bodies(const SectorKey& key) const {
    std::vector<BodySnapshot> out;
    const Sector* sector = impl_->find_sector(key);
    if (sector == nullptr) return out;
    out.reserve(sector->originals.size());
    for (std::uint32_t slot : sector->originals)
        out.push_back(impl_->snapshot_of(impl_->record(slot)));
    std::sort(out.begin(), out.end(),
              [](const BodySnapshot& a, const BodySnapshot& b) { return a.id < b.id; });
    return out;
}

std::vector<SectorKey> World::changed_sectors() const { return impl_->changes.sectors(); }

SectorChanges World::sector_changes(const SectorKey& key) const {
    const Impl& w = *impl_;
    SectorChanges out;
    const engine::ChangeLog::Entry* entry = w.changes.find(key);
    if (entry == nullptr) return out;
    auto here = [&](const BodyRecord& rec) { return rec.alive && !rec.plane && w.sector_of(rec).key == key; };
    std::vector<std::pair<BodyId, std::uint32_t>> present;  // by id, as publishers keep sectors
    present.reserve(entry->touched.size());
    for (std::uint32_t slot : entry->touched) {
        const BodyRecord& rec = w.record(slot);
        if (here(rec)) present.emplace_back(rec.id, slot);
    }
    std::sort(present.begin(), present.end());
    present.erase(std::unique(present.begin(), present.end()), present.end());  // a slot touched twice
    out.bodies.reserve(present.size());
    out.radii.reserve(present.size());
    for (const auto& [id, slot] : present) {
        const BodyRecord& rec = w.record(slot);
        out.bodies.push_back(w.snapshot_of(rec));
        out.radii.push_back(rec.bound_radius);
    }
    out.left = entry->left;
    std::sort(out.left.begin(), out.left.end());
    out.left.erase(std::unique(out.left.begin(), out.left.end()), out.left.end());
    out.left.erase(std::remove_if(out.left.begin(), out.left.end(),
                                  [&](BodyId id) {
                                      Expected<std::uint32_t> slot = w.slot_of(id);
                                      return slot && here(w.record(slot.value()));
                                  }),
                   out.left.end());
    return out;
}

std::vector<SectorKey> World::stepped_sectors() const {
    std::vector<SectorKey> out;
    out.reserve(impl_->step_set.size());
    for (engine::SectorId id : impl_->step_set)
        out.push_back(impl_->sectors.at(id).key);
    std::sort(out.begin(), out.end());
    return out;
}

// ---------------------------------------------------------------------------------------------------
// The frame

void World::step() { impl_->step(); }

void World::Impl::step() {
    auto start = std::chrono::steady_clock::now();
    ++frame;
    stats = FrameStats{};
    stats.frame = frame;

    // Only bodies the last step found active (before or after it: see step_sectors), and bodies touched
    // by commands, can have moved. Not every body of a stepped sector: a ball rolling through a sector of
    // resting boxes cost a border and sector check for each box, every frame. Of the active ones, only
    // those the step found with work here (Sector::visits): a body drifting within its sector and its fat
    // box costs nothing serially. A sector made remote since its step has all of its active bodies
    // visited (as ghosts they may push this engine's bodies: clone_stage).
    std::vector<std::uint32_t>& candidates = candidate_scratch;
    candidates.clear();
    for (engine::SectorId id : step_set) {
        Sector& s = sectors.at(id);
        s.stepping = false;
        for (std::uint32_t slot : s.remote ? s.originals : s.visits) {
            BodyRecord& rec = record(slot);
            if (rec.moved_frame + 1 == frame && rec.visit_frame != frame) {
                rec.visit_frame = frame;
                candidates.push_back(slot);
            }
        }
    }
    for (std::uint32_t slot : dirty) {
        BodyRecord& rec = record(slot);
        if (!rec.alive) continue;
        border.note_bounds_changed(slot);  // what the step computed ahead is stale after a command
        if (!rec.plane) changes.touched(sector_of(rec).key, slot);
        if (rec.visit_frame != frame) {
            rec.visit_frame = frame;
            candidates.push_back(slot);
        }
    }
    dirty.clear();
    // Bodies handed off, removed or brought back since they were found departing are no longer listed.
    departing.erase(std::remove_if(departing.begin(), departing.end(),
                                   [&](std::uint32_t slot) {
                                       BodyRecord& rec = record(slot);
                                       const bool still = departs(rec);
                                       if (!still && rec.alive) rec.departing = false;
                                       return !still;
                                   }),
                    departing.end());

    stats.visited_bodies = candidates.size();
    if (!options.monolithic) sectorize(candidates);
    // A sector may have been emptied and refilled (keep it), emptied more than once (destroy it once), or
    // destroyed meanwhile by a command that removed its last body (its id is stale: nothing to do).
    for (engine::SectorId id : pending_destroy) {
        Sector* s = sectors.get(id);
        if (s != nullptr && s->originals.empty()) destroy_sector(*s);
    }
    pending_destroy.clear();
    auto sectorized = std::chrono::steady_clock::now();

    const std::uint64_t found_before = border.candidates_found();
    const std::uint64_t refreshed_before = border.refreshes();
    const std::uint64_t made_before = clones_made;
    const std::uint64_t released_before = clones_released;
    clone_stage(candidates);
    auto cloned = std::chrono::steady_clock::now();
    stats.border_candidates = border.candidates_found() - found_before;
    stats.fat_box_refreshes = border.refreshes() - refreshed_before;
    stats.clones_made = clones_made - made_before;
    stats.clones_released = clones_released - released_before;

    step_sectors();
    auto stepped = std::chrono::steady_clock::now();

    merge_contacts();

    // What this frame may have changed, for publishers: calls since the last step, sector changes, and
    // the bodies the step found active.
    for (engine::SectorId id : step_set) {
        Sector& s = sectors.at(id);
        for (std::uint32_t moved : s.moved)
            changes.touched(s.key, moved);
        s.moved.clear();
    }
    changes.end_frame();

    stats.sectorize_seconds = std::chrono::duration<double>(sectorized - start).count();
    stats.clone_seconds = std::chrono::duration<double>(cloned - sectorized).count();
    stats.step_seconds = std::chrono::duration<double>(stepped - cloned).count();
    stats.bodies = slots.size();
    stats.sectors = sectors.size();
    stats.stepped_sectors = step_set.size();
    stats.grouped_sectors = 0;
    for (const StepGroup& group : step_groups) {
        if (group.end - group.begin > 1) stats.grouped_sectors += group.end - group.begin;
    }
    stats.border_bodies = border.border_bodies();
    stats.clones = clone_count;
    stats.spare_clones = spare_count;
    stats.touching_pairs = contacts.touching_pairs();
    stats.total_seconds = seconds_since(start);
}

// ---------------------------------------------------------------------------------------------------
// Queries

BodySnapshot World::Impl::snapshot_of(const BodyRecord& rec) const {
    BodySnapshot out;
    out.id = rec.id;
    if (rec.plane) {
        out.position = rec.plane_anchor;
        out.orientation = rec.desc->orientation;
        return out;
    }
    const btRigidBody& rb = *rec.rb;
    out.position = SectorPosition{sector_of(rec).key, rec.local};
    out.orientation = to_eigen(rb.getWorldTransform().getRotation());
    out.linear_velocity = to_eigen(rb.getLinearVelocity());
    out.angular_velocity = to_eigen(rb.getAngularVelocity());
    out.awake = rec.dynamic && rb.isActive();
    return out;
}

std::uint64_t World::frame() const { return impl_->frame; }
bool World::contains(BodyId id) const { return impl_->slots.count(id) != 0; }
std::size_t World::body_count() const { return impl_->slots.size(); }

std::optional<BodySnapshot> World::body(BodyId id) const {
    Expected<std::uint32_t> slot = impl_->slot_of(id);
    if (!slot) return std::nullopt;
    return impl_->snapshot_of(impl_->record(slot.value()));
}

std::vector<BodySnapshot> World::snapshot() const {
    std::vector<BodySnapshot> out;
    out.reserve(impl_->slots.size());
    for (const BodyRecord& rec : impl_->bodies) {
        if (rec.alive) out.push_back(impl_->snapshot_of(rec));
    }
    std::sort(out.begin(), out.end(),
              [](const BodySnapshot& a, const BodySnapshot& b) { return a.id < b.id; });
    return out;
}

std::optional<BodyDesc> World::description(BodyId id) const {
    Expected<std::uint32_t> slot = impl_->slot_of(id);
    if (!slot) return std::nullopt;
    return *impl_->record(slot.value()).desc;
}

double World::bounding_radius(BodyId id) const {
    Expected<std::uint32_t> slot = impl_->slot_of(id);
    if (!slot || impl_->record(slot.value()).plane) return 0.0;
    return impl_->record(slot.value()).bound_radius;
}

const std::vector<ContactEvent>& World::contact_events() const { return impl_->contacts.events(); }
const FrameStats& World::last_frame_stats() const { return impl_->stats; }

std::optional<CloneCounts> World::clone_counts(BodyId id) const {
    Expected<std::uint32_t> slot = impl_->slot_of(id);
    if (!slot) return std::nullopt;
    const BodyRecord& rec = impl_->record(slot.value());
    if (rec.plane) return CloneCounts{0, 0};
    return CloneCounts{rec.clones.size(), rec.spare_clones.size()};
}

bool World::has_sector(const SectorKey& key) const { return impl_->find_sector(key) != nullptr; }

void World::reserve(std::size_t count) {
    // (Seen: a worker reserving one more body a frame spent a sixth of its time copying its records.)
    Impl& w = *impl_;
    const std::size_t room = w.bodies.capacity();
    if (count <= room) return;
    const std::size_t more = std::max(count, room + room / 2);
    w.bodies.reserve(more);
    if (double(more) > double(w.slots.bucket_count()) * w.slots.max_load_factor()) w.slots.reserve(more);
}

std::vector<SectorKey> World::sectors() const {
    std::vector<SectorKey> out;
    out.reserve(impl_->sectors.size());
    impl_->sectors.for_each([&](const Sector& sector) { out.push_back(sector.key); });
    std::sort(out.begin(), out.end());
    return out;
}

Status World::check_consistency() const {
    const Impl& w = *impl_;
    auto fail = [](const BodyRecord& rec, const std::string& what) {
        return Error{describe_body(*rec.desc) + ": " + what};
    };
    auto in_world = [](const Sector& sector, const btCollisionObject* object) {
        const btCollisionObjectArray& objects = sector.world.getCollisionObjectArray();
        const int at = object->getWorldArrayIndex();
        return at >= 0 && at < objects.size() && objects[at] == object;
    };
    auto lists = [](const std::vector<std::uint32_t>& slots, std::uint32_t slot) {
        return std::find(slots.begin(), slots.end(), slot) != slots.end();
    };
    if (!w.clone_check_failure.empty())
        return Error{"the cloning stage missed a clone: " + w.clone_check_failure};
    std::size_t alive = 0, owned = 0, clones = 0, spares = 0;
    for (std::uint32_t slot = 0; slot < w.bodies.size(); ++slot) {
        const BodyRecord& rec = w.bodies[slot];
        if (!rec.alive) continue;
        ++alive;
        if (w.slots.count(rec.id) == 0 || w.slots.at(rec.id) != slot)
            return fail(rec, "is not in the id index");
        if (rec.spare_clones.size() > w.options.max_spare_clones)
            return fail(rec, "keeps too many spare clones");
        spares += rec.spare_clones.size();
        for (const Clone& c : rec.clones) {
            const Sector* host = w.sectors.get(c.host);
            if (host == nullptr) return fail(rec, "has a clone in a sector that does not exist");
            if (!lists(host->hosted, slot)) return fail(rec, "has a clone its host sector does not list");
            if (!in_world(*host, c.rb.get()))
                return fail(rec, "has a clone outside its host's physics world");
            if (rec.plane) continue;
            ++clones;
            if (c.host == rec.sector) return fail(rec, "has a clone in its own sector");
            if (sector_distance(host->key, w.sector_of(rec).key) > engine::kCloneNeighbourhood)
                return fail(rec, "has a clone far from its own sector");
        }
        if (rec.plane) continue;
        ++owned;
        const btRigidBody& rb = *rec.rb;
        if (!rec.local.allFinite() || !to_eigen(rb.getLinearVelocity()).allFinite() ||
            !to_eigen(rb.getAngularVelocity()).allFinite() ||
            !to_eigen(rb.getWorldTransform().getRotation()).coeffs().allFinite()) {
            return fail(rec, "state is not finite");
        }
        const Sector* owner = w.sectors.get(rec.sector);
        if (owner == nullptr) return fail(rec, "owner sector does not exist");
        if (rec.index_in_sector >= owner->originals.size() || owner->originals[rec.index_in_sector] != slot) {
            return fail(rec, "is not listed by its owner sector");
        }
        if (!in_world(*owner, &rb)) return fail(rec, "is not in its sector's physics world");
        // After sectorization a centre is within the band; a frame's motion may carry it further.
        const double frame_motion = to_eigen(rb.getLinearVelocity()).norm() * w.settings.dt;
        const double reach = w.band + (rec.dynamic ? 4.0 * w.settings.sector_size + frame_motion : 0.0);
        if (rec.local.cwiseAbs().maxCoeff() > reach) return fail(rec, "lies far outside its sector");
        // Listed among its sector's partnered originals while it has partners (in the sector it was in
        // at its last update: a command may have moved it since).
        const engine::BorderEntry& entry = rec.border;
        if (entry.partners.empty() != !entry.listed_in.valid())
            return fail(rec, entry.listed_in.valid() ? "is listed as partnered without partners"
                                                     : "has partners but is not listed as partnered");
        if (const Sector* listing = entry.listed_in.valid() ? w.sectors.get(entry.listed_in) : nullptr) {
            if (entry.listed_at >= listing->partnered.size() || listing->partnered[entry.listed_at] != slot)
                return fail(rec, "is not where its sector's partnered list says");
        }
        for (std::uint32_t other : w.border.partners(slot)) {
            const BodyRecord& partner = w.bodies[other];
            if (!partner.alive || partner.plane) return fail(rec, "has a partner that is gone");
            if (!lists(w.border.partners(other), slot)) return fail(rec, "is not its partner's partner");
        }
    }
    if (alive != w.slots.size()) return Error{"body count and id index disagree"};
    if (clones != w.clone_count) return Error{"clone count disagrees with the bodies' clones"};
    if (spares != w.spare_count) return Error{"spare clone count disagrees with the bodies' pools"};
    std::size_t listed = 0;
    Status sectors_ok;
    std::map<std::pair<BodyId, BodyId>, int> seeing;  // touching pair -> sectors whose last step saw it
    w.sectors.for_each([&](const Sector& sector) {
        listed += sector.originals.size();
        for (const engine::ContactRecord& c : sector.contacts)
            ++seeing[{c.a, c.b}];
        // An empty sector waits for the next step's sectorization to end it, and for nothing else.
        if (sector.originals.empty() && sectors_ok &&
            std::find(w.pending_destroy.begin(), w.pending_destroy.end(), sector.id) ==
                w.pending_destroy.end())
            sectors_ok = Error{"a sector owns no body but is not queued for destruction"};
        for (std::size_t n = 0; n < sector.partnered.size() && sectors_ok; ++n) {
            const BodyRecord& rec = w.bodies[sector.partnered[n]];
            if (!rec.alive || rec.border.listed_in != sector.id || rec.border.listed_at != n)
                sectors_ok = Error{"a sector's partnered list names a body that is not listed there"};
        }
    });
    if (!sectors_ok) return sectors_ok;
    if (seeing.size() != w.contacts.touching_pairs())
        return Error{"the contact tracker counts " + std::to_string(w.contacts.touching_pairs()) +
                     " touching pairs, the sectors see " + std::to_string(seeing.size())};
    for (const auto& [pair, count] : seeing) {
        if (w.contacts.sectors_seeing(pair.first, pair.second) != count)
            return Error{"the contact tracker counts bodies " + std::to_string(pair.first) + " and " +
                         std::to_string(pair.second) + " touching in " +
                         std::to_string(w.contacts.sectors_seeing(pair.first, pair.second)) + " sectors, " +
                         std::to_string(count) + " see it"};
    }
    if (listed != owned)
        return Error{"sectors list " + std::to_string(listed) + " bodies, " + std::to_string(owned) +
                     " bodies are owned"};
    for (engine::SectorId id : w.awake_list) {
        if (w.sectors.get(id) == nullptr) return Error{"a destroyed sector is listed as awake"};
    }
    for (engine::SectorId id : w.step_set) {
        if (w.sectors.get(id) == nullptr) return Error{"a destroyed sector is listed as stepped"};
    }
    return {};
}

const WorldSettings& World::settings() const { return impl_->settings; }
const EngineOptions& World::options() const { return impl_->options; }
const SectorGrid& World::grid() const { return impl_->grid; }

}  // namespace lpss
