#include "lpss/common/shape.hpp"

#include <algorithm>
#include <limits>

namespace lpss {

double bounding_radius(const Shape& shape) {
    struct Visitor {
        double operator()(const Sphere& s) const { return s.radius; }
        double operator()(const Box& b) const { return b.half_extents.norm(); }
        double operator()(const Capsule& c) const { return c.radius + 0.5 * c.height; }
        double operator()(const ConvexHull& h) const {
            double r = 0.0;
            for (const Eigen::Vector3d& p : h.points)
                r = std::max(r, p.norm());
            return r;
        }
        double operator()(const Plane&) const { return std::numeric_limits<double>::infinity(); }
    };
    return std::visit(Visitor{}, shape);
}

const char* shape_kind_name(const Shape& shape) {
    static constexpr const char* kNames[] = {"sphere", "box", "capsule", "convex_hull", "plane"};
    return kNames[shape.index()];
}

}  // namespace lpss
