// Everything needed to create one body: what a scene file or a spawn command describes.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <variant>

#include "lpss/common/sector_grid.hpp"
#include "lpss/common/shape.hpp"

namespace lpss {

/// A body's identity, chosen by the user; 0 is never a valid id.
using BodyId = std::uint64_t;

struct Material {
    double friction = 0.5;
    double restitution = 0.0;
};

/// Where a body starts: a double global position (good to about 1e15) or an exact sector position.
using Placement = std::variant<Eigen::Vector3d, SectorPosition>;

struct BodyDesc {
    BodyId id = 0;
    std::string name;
    Shape shape;
    double mass = 0.0;  ///< 0 = static
    Placement position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
    Material material;
    bool ccd = false;
    bool asleep = false;  ///< starts deactivated, at rest (dynamic bodies, scenes that allow sleeping)

    bool is_static() const { return mass == 0.0; }
};

/// "body 'name' (id 7)" or "body id 7": how messages name a body.
std::string describe_body(const BodyDesc& body);

}  // namespace lpss
