#include "lpss_dds/convert.hpp"

namespace lpss::dds {
namespace {

Eigen::Vector3d from_array(const std::array<float, 3>& v) { return {v[0], v[1], v[2]}; }

std::array<float, 3> to_array(const wire::Vec3f& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

wire::SectorKey to_wire(const SectorKey& key) {
    wire::SectorKey out;
    out.i(key.i);
    out.j(key.j);
    out.k(key.k);
    return out;
}

SectorKey from_wire(const wire::SectorKey& key) { return {key.i(), key.j(), key.k()}; }

wire::Vec3d to_wire(const Eigen::Vector3d& v) {
    wire::Vec3d out;
    out.x(v.x());
    out.y(v.y());
    out.z(v.z());
    return out;
}

Eigen::Vector3d from_wire(const wire::Vec3d& v) { return {v.x(), v.y(), v.z()}; }

PackedBodyState pack(const BodySnapshot& body) {
    auto f3 = [](const Eigen::Vector3d& v) {
        return std::array<float, 3>{static_cast<float>(v.x()), static_cast<float>(v.y()),
                                    static_cast<float>(v.z())};
    };
    PackedBodyState out;
    out.id = body.id;
    out.position = f3(body.position.local);
    const Eigen::Quaterniond& q = body.orientation;
    out.orientation = {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()),
                       static_cast<float>(q.w())};
    out.linear_velocity = f3(body.linear_velocity);
    out.angular_velocity = f3(body.angular_velocity);
    out.flags = body.awake ? 1u : 0u;
    return out;
}

wire::BodyState to_wire(const PackedBodyState& state) {
    auto f3 = [](const std::array<float, 3>& v) {
        wire::Vec3f out;
        out.x(v[0]);
        out.y(v[1]);
        out.z(v[2]);
        return out;
    };
    wire::BodyState out;
    out.id(state.id);
    out.position(f3(state.position));
    wire::Quatf q;
    q.x(state.orientation[0]);
    q.y(state.orientation[1]);
    q.z(state.orientation[2]);
    q.w(state.orientation[3]);
    out.orientation(q);
    out.linear_velocity(f3(state.linear_velocity));
    out.angular_velocity(f3(state.angular_velocity));
    out.flags(state.flags);
    return out;
}

PackedBodyState pack(const wire::BodyState& state) {
    PackedBodyState out;
    out.id = state.id();
    out.position = to_array(state.position());
    const wire::Quatf& q = state.orientation();
    out.orientation = {q.x(), q.y(), q.z(), q.w()};
    out.linear_velocity = to_array(state.linear_velocity());
    out.angular_velocity = to_array(state.angular_velocity());
    out.flags = state.flags();
    return out;
}

wire::BodyState to_wire(const BodySnapshot& body) { return to_wire(pack(body)); }

BodySnapshot unpack(const PackedBodyState& state, const SectorKey& sector) {
    BodySnapshot out;
    out.id = state.id;
    out.position = SectorPosition{sector, from_array(state.position)};
    const std::array<float, 4>& q = state.orientation;
    out.orientation = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
    out.linear_velocity = from_array(state.linear_velocity);
    out.angular_velocity = from_array(state.angular_velocity);
    out.awake = state.awake();
    return out;
}

BodySnapshot from_wire(const wire::BodyState& state, const SectorKey& sector) {
    return unpack(pack(state), sector);
}

wire::BodyKind kind_of(const BodyDesc& body) {
    wire::BodyKind k;
    k.id(body.id);
    k.name(body.name);
    std::vector<wire::Vec3d> points;
    if (const auto* s = std::get_if<Sphere>(&body.shape)) {
        k.shape(0);
        k.size(to_wire(Eigen::Vector3d(s->radius, 0, 0)));
    } else if (const auto* b = std::get_if<Box>(&body.shape)) {
        k.shape(1);
        k.size(to_wire(b->half_extents));
    } else if (const auto* c = std::get_if<Capsule>(&body.shape)) {
        k.shape(2);
        k.size(to_wire(Eigen::Vector3d(c->radius, c->height, 0)));
    } else if (const auto* h = std::get_if<ConvexHull>(&body.shape)) {
        k.shape(3);
        for (const Eigen::Vector3d& p : h->points)
            points.push_back(to_wire(p));
    } else if (const auto* p = std::get_if<Plane>(&body.shape)) {
        k.shape(4);
        k.size(to_wire(p->normal));
        k.plane_offset(p->offset);
    }
    k.hull_points(std::move(points));
    k.mass(body.mass);
    k.friction(body.material.friction);
    k.restitution(body.material.restitution);
    k.ccd(body.ccd);
    return k;
}

BodyDesc from_wire(const wire::BodyKind& k) {
    BodyDesc body;
    body.id = k.id();
    body.name = k.name();
    const Eigen::Vector3d size = from_wire(k.size());
    switch (k.shape()) {
        case 0:
            body.shape = Sphere{size.x()};
            break;
        case 1:
            body.shape = Box{size};
            break;
        case 2:
            body.shape = Capsule{size.x(), size.y()};
            break;
        case 3: {
            ConvexHull hull;
            for (const wire::Vec3d& p : k.hull_points())
                hull.points.push_back(from_wire(p));
            body.shape = hull;
            break;
        }
        case 4:
            body.shape = Plane{size, k.plane_offset()};
            break;
        default:
            body.shape = Sphere{0.0};  // refused by validation
    }
    body.mass = k.mass();
    body.material = Material{k.friction(), k.restitution()};
    body.ccd = k.ccd();
    return body;
}

BodyDesc placed(BodyDesc body, const BodySnapshot& state) {
    body.position = state.position;
    body.orientation = state.orientation;
    body.linear_velocity = state.linear_velocity;
    body.angular_velocity = state.angular_velocity;
    return body;
}

wire::BodyDescription describe(const BodyDesc& body, const BodySnapshot& state) {
    wire::BodyDescription d;
    d.id(body.id);
    d.kind(kind_of(body));
    d.sector(to_wire(state.position.sector));
    d.offset(to_wire(state.position.local));
    wire::Quatd q;
    q.x(state.orientation.x());
    q.y(state.orientation.y());
    q.z(state.orientation.z());
    q.w(state.orientation.w());
    d.orientation(q);
    d.linear_velocity(to_wire(state.linear_velocity));
    d.angular_velocity(to_wire(state.angular_velocity));
    d.asleep(body.asleep);
    return d;
}

BodyDesc from_wire(const wire::BodyDescription& d) {
    BodyDesc body = from_wire(d.kind());
    body.id = d.id();
    body.position = SectorPosition{from_wire(d.sector()), from_wire(d.offset())};
    body.orientation = Eigen::Quaterniond(d.orientation().w(), d.orientation().x(), d.orientation().y(),
                                          d.orientation().z());
    body.linear_velocity = from_wire(d.linear_velocity());
    body.angular_velocity = from_wire(d.angular_velocity());
    body.asleep = d.asleep();
    return body;
}

wire::WorldSettings to_wire(const WorldSettings& s) {
    wire::WorldSettings out;
    out.sector_size(s.sector_size);
    out.dt(s.dt);
    out.precision_radius(s.precision_radius);
    out.gravity(to_wire(s.gravity));
    out.hysteresis(s.hysteresis);
    out.sleeping(s.sleeping);
    out.substeps(s.substeps);
    out.solver_iterations(s.solver_iterations);
    out.friction_combine(static_cast<std::uint8_t>(s.friction_combine));
    out.restitution_combine(static_cast<std::uint8_t>(s.restitution_combine));
    out.geo_frame(static_cast<std::uint8_t>(s.geo.frame));
    out.geo_latitude_deg(s.geo.latitude_deg);
    out.geo_longitude_deg(s.geo.longitude_deg);
    out.geo_height_m(s.geo.height_m);
    return out;
}

WorldSettings from_wire(const wire::WorldSettings& s) {
    WorldSettings out;
    out.sector_size = s.sector_size();
    out.dt = s.dt();
    out.precision_radius = s.precision_radius();
    out.gravity = from_wire(s.gravity());
    out.hysteresis = s.hysteresis();
    out.sleeping = s.sleeping();
    out.substeps = s.substeps();
    out.solver_iterations = s.solver_iterations();
    out.friction_combine = static_cast<CombineRule>(s.friction_combine());
    out.restitution_combine = static_cast<CombineRule>(s.restitution_combine());
    out.geo = GeoReference{static_cast<GeoReference::Frame>(s.geo_frame()), s.geo_latitude_deg(),
                           s.geo_longitude_deg(), s.geo_height_m()};
    return out;
}

wire::MortonCode to_wire(const MortonCode& code) {
    wire::MortonCode out;
    out.high(code.high);
    out.middle(code.middle);
    out.low(code.low);
    return out;
}

MortonCode from_wire(const wire::MortonCode& code) { return {code.high(), code.middle(), code.low()}; }

wire::Assignment to_wire(const SectorAssignment& a, const WorldSettings& settings, double largest_radius) {
    wire::Assignment out;
    out.largest_radius(largest_radius);
    out.coordinator(1);
    out.epoch(a.epoch);
    out.from_frame(a.from_frame);
    out.settings(to_wire(settings));
    out.block_size(static_cast<std::int32_t>(a.block_size));
    out.workers(a.workers);
    std::vector<wire::MortonCode> starts;
    for (const MortonCode& c : a.starts)
        starts.push_back(to_wire(c));
    out.starts(starts);
    return out;
}

SectorAssignment from_wire(const wire::Assignment& a) {
    SectorAssignment out;
    out.epoch = a.epoch();
    out.from_frame = a.from_frame();
    out.block_size = a.block_size();
    out.workers = a.workers();
    for (const wire::MortonCode& c : a.starts())
        out.starts.push_back(from_wire(c));
    return out;
}

}  // namespace lpss::dds
