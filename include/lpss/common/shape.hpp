// Collision shapes as plain values, independent of any physics engine.
#pragma once

#include <Eigen/Core>
#include <variant>
#include <vector>

namespace lpss {

struct Sphere {
    double radius = 0.5;
};

struct Box {
    Eigen::Vector3d half_extents = Eigen::Vector3d::Constant(0.5);
};

/// A cylinder of `height` between the centres of two hemispheres, along the body's y axis.
struct Capsule {
    double radius = 0.5;
    double height = 1.0;
};

/// Points in the body's frame; the body's origin is its centre of mass.
struct ConvexHull {
    std::vector<Eigen::Vector3d> points;
};

/// The infinite static plane dot(normal, p - position) = offset; normal is unit length once validated.
struct Plane {
    Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
    double offset = 0.0;
};

using Shape = std::variant<Sphere, Box, Capsule, ConvexHull, Plane>;

inline bool is_plane(const Shape& shape) { return std::holds_alternative<Plane>(shape); }

/// Largest distance from the body's origin to a point of the shape: its axis-aligned bounding box has
/// an edge of at most twice this in any orientation. Infinite for a plane.
double bounding_radius(const Shape& shape);

/// The shape's kind as written in scene files ("sphere", "box", ...), for messages.
const char* shape_kind_name(const Shape& shape);

}  // namespace lpss
