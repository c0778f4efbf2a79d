// The parameters of a sectorized world, shared by the scene file, the engine and the cluster.
#pragma once

#include <Eigen/Core>

#include "lpss/common/combine_rule.hpp"
#include "lpss/common/expected.hpp"
#include "lpss/common/geo_reference.hpp"

namespace lpss {

struct WorldSettings {
    double sector_size = 128.0;  ///< L, the sector edge
    double dt = 1.0 / 60.0;      ///< seconds per frame
    /// Radius within which coordinates must stay precise; 0 means no bound beyond the one L implies.
    double precision_radius = 0.0;
    Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
    /// A body changes sector once its centre is past the border by this fraction of L, so that a body
    /// resting on a border does not move back and forth between sectors.
    double hysteresis = 1.0 / 16.0;
    bool sleeping = true;  ///< resting bodies fall asleep and cost nothing
    /// Physics steps per frame, each of dt/substeps; 0 picks enough for steps of at most 1/60 s, so that
    /// a coarse frame rate does not make contacts coarse.
    int substeps = 0;
    int solver_iterations = 10;  ///< constraint solver iterations per step (Bullet's default is 10)
    CombineRule friction_combine = CombineRule::product;     ///< a contact's friction from its bodies'
    CombineRule restitution_combine = CombineRule::product;  ///< a contact's restitution from its bodies'
    GeoReference geo;  ///< where the world is on the Earth, for geocentric clients; not used by the engine

    /// The substeps actually used (resolving 0).
    int substeps_per_frame() const;
    /// Seconds per physics step: dt / substeps_per_frame().
    double step_seconds() const;
    /// The fastest a body may move: 10^5 units in one physics step. Bullet stops simulating a body whose
    /// box swept in one step passes 10^6 units, silently, so faster bodies are refused, not lost.
    double max_linear_speed() const;
    /// The fastest a body may spin: 100 radians in one physics step. Faster, a body falls through its
    /// contacts, and from about 10^15 rad/s its state turns NaN.
    double max_angular_speed() const;
};

/// Refuses velocities that are not finite or above the settings' limits; the message names which and
/// says how to allow more (substeps).
Status check_velocity(const Eigen::Vector3d& linear, const Eigen::Vector3d& angular,
                      const WorldSettings& settings);

/// Refuses non-finite or non-positive sizes and steps, a hysteresis outside [0, 1/4], a sector size that
/// breaks the precision bound, and a geo reference off the Earth's latitudes and longitudes. The message names the field.
Status validate(const WorldSettings& settings);

}  // namespace lpss
