// Conversions between Eigen doubles (the API) and Bullet's btScalar (float or double by build).
#pragma once

#include <LinearMath/btQuaternion.h>
#include <LinearMath/btVector3.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace lpss::engine {

inline btVector3 to_bt(const Eigen::Vector3d& v) {
    return btVector3(static_cast<btScalar>(v.x()), static_cast<btScalar>(v.y()),
                     static_cast<btScalar>(v.z()));
}

inline btQuaternion to_bt(const Eigen::Quaterniond& q) {
    return btQuaternion(static_cast<btScalar>(q.x()), static_cast<btScalar>(q.y()),
                        static_cast<btScalar>(q.z()), static_cast<btScalar>(q.w()));
}

inline Eigen::Vector3d to_eigen(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

inline Eigen::Quaterniond to_eigen(const btQuaternion& q) {
    return Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z());
}

}  // namespace lpss::engine
