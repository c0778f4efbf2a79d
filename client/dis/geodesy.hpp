// Where a world's bodies are on the Earth, as DIS wants them: WGS84 geocentric (ECEF) metres for
// locations, vectors in ECEF axes, and orientations as DIS Euler angles relative to the ECEF axes.
#pragma once

#include <Eigen/Geometry>

namespace lpss::dis {

/// The WGS84 ellipsoid, which DIS world coordinates (IEEE 1278.1, 6.2.97) are defined against.
struct Wgs84 {
    static constexpr double semi_major_axis_m = 6378137.0;
    static constexpr double flattening = 1.0 / 298.257223563;
    static constexpr double semi_minor_axis_m = semi_major_axis_m * (1.0 - flattening);
    /// First eccentricity squared, e^2 = f (2 - f).
    static constexpr double eccentricity_squared = flattening * (2.0 - flattening);
};

struct Geodetic {
    double latitude_deg = 0;
    double longitude_deg = 0;
    /// Above the ellipsoid, along its normal.
    double height_m = 0;
};

Eigen::Vector3d geodetic_to_ecef(double latitude_deg, double longitude_deg, double height_m);

/// Inverse of geodetic_to_ecef, to well under a micrometre from below the Earth's centre region out to
/// planetary distances. Longitude is in (-180, 180]; on the polar axis it is 0.
Geodetic ecef_to_geodetic(const Eigen::Vector3d& ecef);

/// How a world's global coordinates map to ECEF metres. A world is either already geocentric
/// (identity) or a flat patch of the Earth whose global axes are east, north and up at an origin point
/// (local_tangent). Everything is done in double: a body 10,000 km away keeps its micrometres.
class GeocentricFrame {
public:
    /// The world's global coordinates are ECEF metres.
    static GeocentricFrame identity();
    /// Global x points east, y north, z up (along the ellipsoid normal) at the given point, which is the
    /// origin of global coordinates. The axes stay those of the origin everywhere: far from it, "up" is
    /// no longer the local vertical, as on any tangent plane.
    static GeocentricFrame local_tangent(double latitude_deg, double longitude_deg, double height_m);

    /// A global position as ECEF metres: origin + R * global.
    Eigen::Vector3d position(const Eigen::Vector3d& global) const;
    /// A global vector (velocity, acceleration, angular velocity) in ECEF axes.
    Eigen::Vector3d direction(const Eigen::Vector3d& v) const;
    /// A body's orientation (body -> global) as body -> ECEF.
    Eigen::Quaterniond orientation(const Eigen::Quaterniond& q_global) const;

    /// Columns are the global axes expressed in ECEF.
    const Eigen::Matrix3d& rotation() const { return rotation_; }
    const Eigen::Vector3d& origin() const { return origin_; }

private:
    GeocentricFrame(const Eigen::Vector3d& origin, const Eigen::Matrix3d& rotation);

    Eigen::Vector3d origin_;
    Eigen::Matrix3d rotation_;
    // The same rotation, so that orientations are composed without a matrix -> quaternion round trip.
    Eigen::Quaterniond rotation_quaternion_;
};

/// DIS Euler angles (IEEE 1278.1-2012, Euler Angles record, 6.2.33), radians. The body frame is obtained
/// from the ECEF frame by rotating psi about Z, then theta about the new Y, then phi about the new X
/// (intrinsic Tait-Bryan z-y'-x''). Ranges: psi and phi in [-pi, pi], theta in [-pi/2, pi/2].
///
/// An lpss body's own axes are taken as its DIS body axes as they are: the body's x axis is its DIS
/// forward axis, y its right and z its down. A scene whose models face another way must turn them.
struct EulerAngles {
    double psi = 0;
    double theta = 0;
    double phi = 0;
};

/// The Euler angles of a body whose orientation (body -> ECEF) is body_to_ecef. At theta = +-90 degrees
/// (gimbal lock) psi and phi are not separable: phi is set to 0 and psi carries the whole rotation about
/// the vertical axis, so the result is finite and from_dis_euler_angles gives the orientation back.
EulerAngles dis_euler_angles(const Eigen::Quaterniond& body_to_ecef);

/// Body -> ECEF orientation of DIS Euler angles: Rz(psi) * Ry(theta) * Rx(phi).
Eigen::Quaterniond from_dis_euler_angles(const EulerAngles& angles);

}  // namespace lpss::dis
