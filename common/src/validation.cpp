// Validation of settings and bodies. Every message names the body and the field, as written in scene
// files, so that a user can find the line to fix.
#include <cmath>
#include <sstream>
#include <unordered_set>

#include "lpss/common/scene.hpp"

namespace lpss {
namespace {

std::string number(double v) {
    std::ostringstream out;
    out.precision(10);
    out << v;
    return out.str();
}

/// A speed and its ceiling (WorldSettings::max_linear_speed, max_angular_speed), for the messages.
struct SpeedLimit {
    const char* kind;
    const char* unit;
    const char* per_step;
    double (WorldSettings::*limit)() const;
};
constexpr SpeedLimit kLinearSpeed{"linear", "units/s", "10^5 units", &WorldSettings::max_linear_speed};
constexpr SpeedLimit kAngularSpeed{"angular", "rad/s", "100 radians", &WorldSettings::max_angular_speed};

/// Why `velocity` is too fast under `s`, or empty if it is not (it must be finite).
std::string too_fast(const SpeedLimit& l, const Eigen::Vector3d& velocity, const WorldSettings& s) {
    const double limit = (s.*l.limit)();
    if (velocity.norm() <= limit) return {};
    return std::string(l.kind) + " speed " + number(velocity.norm()) + " " + l.unit + " is above the " +
           number(limit) + " " + l.unit + " an engine step of " + number(s.step_seconds()) +
           " s can simulate (" + l.per_step + " a step; more substeps per frame allow more)";
}

class BodyChecker {
public:
    BodyChecker(const BodyDesc& body, const WorldSettings& settings, bool sectorized)
        : body_(body), settings_(settings), sectorized_(sectorized) {}

    Status run() {
        if (body_.id == 0) fail("id", "must be non-zero (is it missing?)");
        check_shape();
        finite_at_least("mass", body_.mass, 0.0);
        if (is_plane(body_.shape) && body_.mass != 0.0) {
            fail("shape.plane", "a plane must be static (mass 0), got mass " + number(body_.mass));
        }
        check_position();
        const Eigen::Quaterniond& q = body_.orientation;
        if (!q.coeffs().allFinite()) {
            fail("orientation", "is not finite");
        } else if (q.norm() < 1e-9) {
            fail("orientation", "is a zero quaternion");
        }
        check_velocity("linear_velocity", body_.linear_velocity, kLinearSpeed);
        check_velocity("angular_velocity", body_.angular_velocity, kAngularSpeed);
        finite_at_least("material.friction", body_.material.friction, 0.0);
        finite_at_least("material.restitution", body_.material.restitution, 0.0);
        if (body_.asleep) {
            if (body_.mass == 0.0) fail("asleep", "applies to dynamic bodies only (this one is static)");
            if (!settings_.sleeping) fail("asleep", "needs a scene that allows sleeping (sleeping: false)");
            if (body_.linear_velocity.squaredNorm() > 0.0 || body_.angular_velocity.squaredNorm() > 0.0)
                fail("asleep", "is at rest: a body starting asleep cannot have a velocity");
        }
        if (body_.material.restitution > 1.0) {
            fail("material.restitution",
                 "must be <= 1 (a bounce may not add energy), got " + number(body_.material.restitution));
        }
        if (problems_.empty()) return {};
        return Error{problems_};
    }

private:
    void fail(const std::string& field, const std::string& what) {
        if (!problems_.empty()) problems_ += "\n";
        problems_ += describe_body(body_) + ": " + field + " " + what;
    }

    void check_velocity(const std::string& field, const Eigen::Vector3d& v, const SpeedLimit& limit) {
        if (!v.allFinite()) {
            fail(field, "is not finite");
        } else if (std::string why = too_fast(limit, v, settings_); !why.empty()) {
            fail(field, "is too fast: " + why);
        }
    }

    void finite_at_least(const std::string& field, double v, double least) {
        if (!std::isfinite(v)) {
            fail(field, "is not finite");
        } else if (v < least) {
            fail(field, "must be >= " + number(least) + ", got " + number(v));
        }
    }

    void positive(const std::string& field, double v) {
        if (!std::isfinite(v)) {
            fail(field, "is not finite");
        } else if (v <= 0.0) {
            fail(field, "must be > 0, got " + number(v));
        }
    }

    void check_shape() {
        const Shape& shape = body_.shape;
        if (const auto* s = std::get_if<Sphere>(&shape)) {
            positive("shape.sphere.radius", s->radius);
        } else if (const auto* b = std::get_if<Box>(&shape)) {
            positive("shape.box.half_extents.x", b->half_extents.x());
            positive("shape.box.half_extents.y", b->half_extents.y());
            positive("shape.box.half_extents.z", b->half_extents.z());
        } else if (const auto* c = std::get_if<Capsule>(&shape)) {
            positive("shape.capsule.radius", c->radius);
            finite_at_least("shape.capsule.height", c->height, 0.0);
        } else if (const auto* h = std::get_if<ConvexHull>(&shape)) {
            check_hull(*h);
        } else if (const auto* p = std::get_if<Plane>(&shape)) {
            if (!p->normal.allFinite() || p->normal.norm() < 1e-9) {
                fail("shape.plane.normal", "must be a finite non-zero vector");
            }
            if (!std::isfinite(p->offset)) fail("shape.plane.offset", "is not finite");
        }
        if (problems_.empty() && sectorized_ && !is_plane(shape)) {
            double extent = 2.0 * bounding_radius(shape);
            if (extent > settings_.sector_size) {
                fail(std::string("shape.") + shape_kind_name(shape),
                     "spans up to " + number(extent) + " units in some orientation, more than sector_size " +
                         number(settings_.sector_size) +
                         ": lpss cannot simulate a body larger than a sector");
            }
        }
    }

    void check_hull(const ConvexHull& hull) {
        if (hull.points.size() < 4) {
            fail("shape.convex_hull.points",
                 "needs at least 4 points, got " + std::to_string(hull.points.size()));
            return;
        }
        for (std::size_t n = 0; n < hull.points.size(); ++n) {
            if (!hull.points[n].allFinite()) {
                fail("shape.convex_hull.points[" + std::to_string(n) + "]", "is not finite");
                return;
            }
        }
        // A hull must enclose a volume: find a far pair, the point farthest from their line and the point
        // farthest from their plane; a flat or collinear set has no such point.
        const auto& pts = hull.points;
        std::size_t a = 0, b = 0;
        for (std::size_t n = 0; n < pts.size(); ++n) {
            if ((pts[n] - pts[a]).squaredNorm() > (pts[b] - pts[a]).squaredNorm()) b = n;
        }
        double scale = (pts[b] - pts[a]).norm();
        Eigen::Vector3d axis = (pts[b] - pts[a]).normalized();
        std::size_t c = a;
        double best = 0.0;
        for (std::size_t n = 0; n < pts.size(); ++n) {
            double d = (pts[n] - pts[a]).cross(axis).norm();
            if (d > best) best = d, c = n;
        }
        double volume_height = 0.0;
        if (best > 1e-9 * scale) {
            Eigen::Vector3d normal = (pts[b] - pts[a]).cross(pts[c] - pts[a]).normalized();
            for (const auto& p : pts)
                volume_height = std::max(volume_height, std::fabs((p - pts[a]).dot(normal)));
        }
        if (!(scale > 0.0) || volume_height <= 1e-9 * scale) {
            fail("shape.convex_hull.points", "are flat or collinear: a hull must enclose a volume");
        }
    }

    void check_position() {
        if (const auto* global = std::get_if<Eigen::Vector3d>(&body_.position)) {
            if (!global->allFinite()) {
                fail("position.global", "is not finite");
            } else if (sectorized_) {
                Expected<SectorPosition> p = SectorGrid(settings_.sector_size).from_global(*global);
                if (!p.ok()) fail("position.global", p.error().message);
            }
        } else {
            const auto& sector = std::get<SectorPosition>(body_.position);
            if (!in_range(sector.sector)) {
                fail("position.sector", "has an index beyond 2^62");
            } else if (!sector.local.allFinite()) {
                fail("position.sector.local", "is not finite");
            } else if (sectorized_) {
                Expected<SectorPosition> p = SectorGrid(settings_.sector_size).canonical(sector);
                if (!p.ok()) fail("position.sector", p.error().message);
            }
        }
    }

    const BodyDesc& body_;
    const WorldSettings& settings_;
    bool sectorized_;
    std::string problems_;
};

}  // namespace

std::string describe_body(const BodyDesc& body) {
    std::string out = "body ";
    if (!body.name.empty()) out += "'" + body.name + "' (";
    out += "id " + std::to_string(body.id);
    if (!body.name.empty()) out += ")";
    return out;
}

Status validate(const WorldSettings& s) {
    auto positive = [](const char* field, double v) -> Status {
        if (!std::isfinite(v) || v <= 0.0) {
            return Error{std::string("scene: ") + field + " must be a finite number > 0, got " + number(v) +
                         (v == 0.0 ? " (is it missing?)" : "")};
        }
        return {};
    };
    if (Status st = positive("sector_size", s.sector_size); !st) return st;
    if (Status st = positive("dt", s.dt); !st) return st;
    if (s.dt > 1.0) return Error{"scene: dt must be <= 1 second, got " + number(s.dt)};
    if (!std::isfinite(s.precision_radius) || s.precision_radius < 0.0) {
        return Error{"scene: precision_radius must be a finite number >= 0, got " +
                     number(s.precision_radius)};
    }
    if (s.precision_radius > 0.0) {
        if (Status st = check_sector_size(s.sector_size, s.precision_radius); !st) {
            return Error{"scene: " + st.error().message};
        }
    }
    if (!s.gravity.allFinite()) return Error{"scene: gravity is not finite"};
    if (s.substeps < 0 || s.substeps > 64) {
        return Error{"scene: substeps must be between 0 (automatic) and 64, got " +
                     std::to_string(s.substeps)};
    }
    if (s.solver_iterations < 1 || s.solver_iterations > 1000) {
        return Error{"scene: solver_iterations must be between 1 and 1000, got " +
                     std::to_string(s.solver_iterations)};
    }
    // A number the enum does not name (a scene written by a later version, or as a number) is refused.
    for (const auto& [field, rule] : {std::pair{"friction_combine", s.friction_combine},
                                      std::pair{"restitution_combine", s.restitution_combine}}) {
        if (static_cast<int>(rule) > static_cast<int>(CombineRule::max)) {
            return Error{std::string("scene: ") + field +
                         " must be PRODUCT, GEOMETRIC_MEAN, AVERAGE, MIN or MAX, got " +
                         std::to_string(static_cast<int>(rule))};
        }
    }
    if (s.geo.frame == GeoReference::Frame::local_tangent) {
        const GeoReference& g = s.geo;
        if (!(std::abs(g.latitude_deg) <= 90.0) || !(std::abs(g.longitude_deg) <= 180.0) ||
            !std::isfinite(g.height_m)) {
            return Error{
                "scene: geo.local_tangent must have latitude_deg in [-90, 90], longitude_deg in "
                "[-180, 180] and a finite height_m, got (" +
                number(g.latitude_deg) + ", " + number(g.longitude_deg) + ", " + number(g.height_m) + ")"};
        }
    }
    if (static_cast<int>(s.geo.frame) > static_cast<int>(GeoReference::Frame::local_tangent))
        return Error{"scene: geo: unknown frame " + std::to_string(static_cast<int>(s.geo.frame))};
    if (!std::isfinite(s.hysteresis) || s.hysteresis < 0.0 || s.hysteresis > 0.25) {
        return Error{"scene: hysteresis must be a fraction of sector_size in [0, 0.25], got " +
                     number(s.hysteresis)};
    }
    return {};
}

int WorldSettings::substeps_per_frame() const {
    if (substeps > 0) return substeps;
    return std::max(1, static_cast<int>(std::ceil(dt * 60.0 - 1e-9)));
}

double WorldSettings::step_seconds() const { return dt / substeps_per_frame(); }

double WorldSettings::max_linear_speed() const { return 1e5 / step_seconds(); }

double WorldSettings::max_angular_speed() const { return 100.0 / step_seconds(); }

Status check_velocity(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular, const WorldSettings& s) {
    if (!linear.allFinite() || !angular.allFinite()) return Error{"velocities must be finite"};
    for (const auto& [limit, v] : {std::pair{&kLinearSpeed, &linear}, std::pair{&kAngularSpeed, &angular}}) {
        if (std::string why = too_fast(*limit, *v, s); !why.empty()) return Error{why};
    }
    return {};
}

Status validate_body(const BodyDesc& body, const WorldSettings& settings, bool sectorized) {
    return BodyChecker(body, settings, sectorized).run();
}

Status validate_scene(const Scene& scene, bool sectorized) {
    if (Status st = validate(scene.settings); !st) return st;
    std::string problems;
    int count = 0;
    auto add = [&](const std::string& message) {
        if (++count > 20) return;
        if (!problems.empty()) problems += "\n";
        problems += message;
    };
    std::unordered_set<BodyId> ids;
    for (const BodyDesc& body : scene.bodies) {
        if (Status st = validate_body(body, scene.settings, sectorized); !st) add(st.error().message);
        if (body.id != 0 && !ids.insert(body.id).second)
            add(describe_body(body) + ": id is used by another body");
    }
    if (count > 20) problems += "\n... and " + std::to_string(count - 20) + " more problems";
    if (count > 0) return Error{problems};
    return {};
}

}  // namespace lpss
