// Axis-aligned boxes in double precision, for the cloning stage's reach tests.
#pragma once

#include <Eigen/Core>

namespace lpss::engine {

struct Aabb {
    Eigen::Vector3d min = Eigen::Vector3d::Zero();
    Eigen::Vector3d max = Eigen::Vector3d::Zero();

    bool overlaps(const Aabb& other) const {
        return (min.array() <= other.max.array()).all() && (other.min.array() <= max.array()).all();
    }
    bool contains(const Aabb& inner) const {
        return (min.array() <= inner.min.array()).all() && (inner.max.array() <= max.array()).all();
    }
    Aabb translated(const Eigen::Vector3d& by) const { return {min + by, max + by}; }
    Aabb grown(double by) const { return {min.array() - by, max.array() + by}; }
};

}  // namespace lpss::engine
