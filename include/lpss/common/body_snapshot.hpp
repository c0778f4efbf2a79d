// The state of one body at one frame, as the engine reports it and clients receive it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "lpss/common/body_desc.hpp"
#include "lpss/common/sector_grid.hpp"

namespace lpss {

struct BodySnapshot {
    BodyId id = 0;
    SectorPosition position;  ///< exact; SectorGrid::to_global gives the double global position
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
    bool awake = false;
};

}  // namespace lpss
