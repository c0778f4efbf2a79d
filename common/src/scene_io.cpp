// Reading and writing scene files: Protobuf text format <-> lpss::Scene.
#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <fstream>
#include <sstream>

#include "lpss/common/scene.hpp"
#include "scene.pb.h"

namespace lpss {
namespace {

namespace pb = lpss::scene;

class ParseErrors : public google::protobuf::io::ErrorCollector {
public:
    explicit ParseErrors(std::string_view source) : source_(source) {}
    void AddError(int line, google::protobuf::io::ColumnNumber column, const std::string& message) override {
        if (!text_.empty()) text_ += "\n";
        text_ += source_ + ":" + std::to_string(line + 1) + ":" + std::to_string(column + 1) + ": " + message;
    }
    const std::string& text() const { return text_; }

private:
    std::string source_;
    std::string text_;
};

Eigen::Vector3d from_pb(const pb::Vec3& v) { return {v.x(), v.y(), v.z()}; }

void to_pb(const Eigen::Vector3d& v, pb::Vec3* out) {
    out->set_x(v.x());
    out->set_y(v.y());
    out->set_z(v.z());
}

Shape shape_from_pb(const pb::Shape& s) {
    switch (s.kind_case()) {
        case pb::Shape::kSphere:
            return Sphere{s.sphere().radius()};
        case pb::Shape::kBox:
            return Box{from_pb(s.box().half_extents())};
        case pb::Shape::kCapsule:
            return Capsule{s.capsule().radius(), s.capsule().height()};
        case pb::Shape::kConvexHull: {
            ConvexHull hull;
            for (const pb::Vec3& p : s.convex_hull().points())
                hull.points.push_back(from_pb(p));
            return hull;
        }
        case pb::Shape::kPlane: {
            Plane plane{from_pb(s.plane().normal()), s.plane().offset()};
            if (plane.normal.allFinite() && plane.normal.norm() > 0.0) plane.normal.normalize();
            return plane;
        }
        case pb::Shape::KIND_NOT_SET:
            break;
    }
    return Sphere{0.0};  // refused by validation ("shape.sphere.radius must be > 0")
}

void shape_to_pb(const Shape& shape, pb::Shape* out) {
    if (const auto* s = std::get_if<Sphere>(&shape)) {
        out->mutable_sphere()->set_radius(s->radius);
    } else if (const auto* b = std::get_if<Box>(&shape)) {
        to_pb(b->half_extents, out->mutable_box()->mutable_half_extents());
    } else if (const auto* c = std::get_if<Capsule>(&shape)) {
        out->mutable_capsule()->set_radius(c->radius);
        out->mutable_capsule()->set_height(c->height);
    } else if (const auto* h = std::get_if<ConvexHull>(&shape)) {
        for (const auto& p : h->points)
            to_pb(p, out->mutable_convex_hull()->add_points());
    } else if (const auto* p = std::get_if<Plane>(&shape)) {
        to_pb(p->normal, out->mutable_plane()->mutable_normal());
        out->mutable_plane()->set_offset(p->offset);
    }
}

BodyDesc body_from_pb(const pb::Body& b, std::string& shape_problem) {
    BodyDesc body;
    body.id = b.id();
    body.name = b.name();
    if (!b.has_shape() || b.shape().kind_case() == pb::Shape::KIND_NOT_SET) {
        shape_problem =
            describe_body(body) + ": shape is missing (sphere, box, capsule, convex_hull or plane)";
    }
    body.shape = shape_from_pb(b.shape());
    body.mass = b.mass();
    if (b.position().has_sector()) {
        const pb::SectorPos& s = b.position().sector();
        body.position = SectorPosition{{s.i(), s.j(), s.k()}, from_pb(s.local())};
    } else {
        body.position = from_pb(b.position().global());
    }
    if (b.has_orientation()) {
        const pb::Quat& q = b.orientation();
        body.orientation = Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z());
        if (body.orientation.coeffs().allFinite() && body.orientation.norm() > 1e-9)
            body.orientation.normalize();
    }
    body.linear_velocity = from_pb(b.linear_velocity());
    body.angular_velocity = from_pb(b.angular_velocity());
    if (b.has_material()) body.material = Material{b.material().friction(), b.material().restitution()};
    body.ccd = b.ccd();
    body.asleep = b.asleep();
    return body;
}

}  // namespace

Expected<Scene> parse_scene(std::string_view text, std::string_view source, bool sectorized) {
    pb::Scene message;
    ParseErrors errors(source);
    google::protobuf::TextFormat::Parser parser;
    parser.RecordErrorsTo(&errors);
    if (!parser.ParseFromString(std::string(text), &message)) {
        return Error{errors.text().empty() ? std::string(source) + ": not a valid scene" : errors.text()};
    }
    Scene scene;
    WorldSettings& s = scene.settings;
    s.sector_size = message.sector_size();
    if (message.has_dt()) s.dt = message.dt();
    if (message.has_precision_radius()) s.precision_radius = message.precision_radius();
    s.gravity = from_pb(message.gravity());
    if (message.has_hysteresis()) s.hysteresis = message.hysteresis();
    if (message.has_sleeping()) s.sleeping = message.sleeping();
    if (message.has_substeps()) s.substeps = message.substeps();
    if (message.has_solver_iterations()) s.solver_iterations = message.solver_iterations();
    s.friction_combine = static_cast<CombineRule>(message.friction_combine());
    s.restitution_combine = static_cast<CombineRule>(message.restitution_combine());
    if (message.geo().has_ecef()) s.geo.frame = GeoReference::Frame::ecef;
    if (message.geo().has_local_tangent()) {
        const pb::LocalTangent& at = message.geo().local_tangent();
        s.geo = GeoReference{GeoReference::Frame::local_tangent, at.latitude_deg(), at.longitude_deg(),
                             at.height_m()};
    }
    if (message.has_precision_radius() && !(message.precision_radius() > 0.0)) {
        return Error{std::string(source) + ": scene: precision_radius must be > 0 when given"};
    }
    std::string problems;
    for (const pb::Body& b : message.bodies()) {
        std::string shape_problem;
        scene.bodies.push_back(body_from_pb(b, shape_problem));
        if (!shape_problem.empty()) problems += (problems.empty() ? "" : "\n") + shape_problem;
    }
    if (!problems.empty()) return Error{std::string(source) + ": " + problems};
    if (Status st = validate_scene(scene, sectorized); !st) {
        return Error{std::string(source) + ": " + st.error().message};
    }
    return scene;
}

Expected<Scene> load_scene(const std::string& path, bool sectorized) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path + ": cannot open scene file"};
    std::ostringstream text;
    text << in.rdbuf();
    return parse_scene(text.str(), path, sectorized);
}

std::string format_scene(const Scene& scene) {
    pb::Scene message;
    const WorldSettings& s = scene.settings;
    message.set_sector_size(s.sector_size);
    message.set_dt(s.dt);
    if (s.precision_radius > 0.0) message.set_precision_radius(s.precision_radius);
    to_pb(s.gravity, message.mutable_gravity());
    message.set_hysteresis(s.hysteresis);
    message.set_sleeping(s.sleeping);
    if (s.substeps != 0) message.set_substeps(s.substeps);
    message.set_solver_iterations(s.solver_iterations);
    message.set_friction_combine(static_cast<pb::CombineRule>(s.friction_combine));
    message.set_restitution_combine(static_cast<pb::CombineRule>(s.restitution_combine));
    if (s.geo.frame == GeoReference::Frame::ecef) message.mutable_geo()->mutable_ecef();
    if (s.geo.frame == GeoReference::Frame::local_tangent) {
        pb::LocalTangent* at = message.mutable_geo()->mutable_local_tangent();
        at->set_latitude_deg(s.geo.latitude_deg);
        at->set_longitude_deg(s.geo.longitude_deg);
        at->set_height_m(s.geo.height_m);
    }
    for (const BodyDesc& body : scene.bodies) {
        pb::Body* b = message.add_bodies();
        b->set_id(body.id);
        b->set_name(body.name);
        shape_to_pb(body.shape, b->mutable_shape());
        b->set_mass(body.mass);
        if (const auto* global = std::get_if<Eigen::Vector3d>(&body.position)) {
            to_pb(*global, b->mutable_position()->mutable_global());
        } else {
            const auto& p = std::get<SectorPosition>(body.position);
            pb::SectorPos* out = b->mutable_position()->mutable_sector();
            out->set_i(p.sector.i);
            out->set_j(p.sector.j);
            out->set_k(p.sector.k);
            to_pb(p.local, out->mutable_local());
        }
        pb::Quat* q = b->mutable_orientation();
        q->set_x(body.orientation.x());
        q->set_y(body.orientation.y());
        q->set_z(body.orientation.z());
        q->set_w(body.orientation.w());
        to_pb(body.linear_velocity, b->mutable_linear_velocity());
        to_pb(body.angular_velocity, b->mutable_angular_velocity());
        b->mutable_material()->set_friction(body.material.friction);
        b->mutable_material()->set_restitution(body.material.restitution);
        b->set_ccd(body.ccd);
        b->set_asleep(body.asleep);
    }
    std::string text;
    google::protobuf::TextFormat::Printer printer;
    printer.PrintToString(message, &text);
    return text;
}

}  // namespace lpss
