#include "geodesy.hpp"

#include <cmath>

namespace lpss::dis {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadiansPerDegree = kPi / 180.0;

struct SineCosine {
    double sine;
    double cosine;
};

// Sine and cosine of an angle in degrees, exact at multiples of 90 degrees: the pole is then exactly on
// the Z axis and longitude 90 exactly on Y, instead of 1e-10 m off because pi/2 is not a double.
SineCosine sine_cosine_degrees(double degrees) {
    double reduced = std::remainder(degrees, 360.0);  // [-180, 180], exact
    const long quadrant = std::lround(reduced / 90.0);
    reduced -= 90.0 * static_cast<double>(quadrant);  // [-45, 45], exact
    const double s = std::sin(reduced * kRadiansPerDegree);
    const double c = std::cos(reduced * kRadiansPerDegree);
    switch (quadrant & 3) {
        case 0:
            return {s, c};
        case 1:
            return {c, -s};
        case 2:
            return {-s, -c};
        default:
            return {-c, s};
    }
}

}  // namespace

Eigen::Vector3d geodetic_to_ecef(double latitude_deg, double longitude_deg, double height_m) {
    const auto latitude = sine_cosine_degrees(latitude_deg);
    const auto longitude = sine_cosine_degrees(longitude_deg);
    const double prime_vertical_radius =
        Wgs84::semi_major_axis_m /
        std::sqrt(1.0 - Wgs84::eccentricity_squared * latitude.sine * latitude.sine);
    const double distance_from_axis = (prime_vertical_radius + height_m) * latitude.cosine;
    return {distance_from_axis * longitude.cosine, distance_from_axis * longitude.sine,
            (prime_vertical_radius * (1.0 - Wgs84::eccentricity_squared) + height_m) * latitude.sine};
}

Geodetic ecef_to_geodetic(const Eigen::Vector3d& ecef) {
    constexpr double a = Wgs84::semi_major_axis_m;
    constexpr double b = Wgs84::semi_minor_axis_m;
    constexpr double e2 = Wgs84::eccentricity_squared;
    constexpr double second_eccentricity_squared = e2 / (1.0 - e2);
    constexpr double axis_ratio = 1.0 - Wgs84::flattening;  // b / a

    const double z = ecef.z();
    const double distance_from_axis = std::hypot(ecef.x(), ecef.y());
    if (distance_from_axis == 0.0) {
        // On the polar axis the longitude is arbitrary and Bowring's formula would divide 0 by 0 at
        // the centre.
        return {z >= 0.0 ? 90.0 : -90.0, 0.0, std::abs(z) - b};
    }

    // Bowring's formula iterated on the parametric latitude: one pass is good to a millimetre near
    // the surface; iterating to a fixed point makes it exact to rounding at any height.
    double parametric_latitude = std::atan2(z, axis_ratio * distance_from_axis);
    double latitude = 0.0;
    for (int iteration = 0; iteration < 16; ++iteration) {
        const double s = std::sin(parametric_latitude);
        const double c = std::cos(parametric_latitude);
        const double next_latitude = std::atan2(z + second_eccentricity_squared * b * s * s * s,
                                                distance_from_axis - e2 * a * c * c * c);
        const bool converged = iteration > 0 && std::abs(next_latitude - latitude) <= 1e-15;
        latitude = next_latitude;
        if (converged) break;
        parametric_latitude = std::atan2(axis_ratio * std::sin(latitude), std::cos(latitude));
    }

    const double sin_latitude = std::sin(latitude);
    // This form of the height has no 1/cos(latitude), so it stays exact near the poles.
    const double height = distance_from_axis * std::cos(latitude) + z * sin_latitude -
                          a * std::sqrt(1.0 - e2 * sin_latitude * sin_latitude);
    return {latitude / kRadiansPerDegree, std::atan2(ecef.y(), ecef.x()) / kRadiansPerDegree, height};
}

GeocentricFrame::GeocentricFrame(const Eigen::Vector3d& origin, const Eigen::Matrix3d& rotation)
    : origin_(origin), rotation_(rotation), rotation_quaternion_(rotation) {
    rotation_quaternion_.normalize();
}

GeocentricFrame GeocentricFrame::identity() {
    return GeocentricFrame(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
}

GeocentricFrame GeocentricFrame::local_tangent(double latitude_deg, double longitude_deg, double height_m) {
    const auto latitude = sine_cosine_degrees(latitude_deg);
    const auto longitude = sine_cosine_degrees(longitude_deg);
    Eigen::Matrix3d east_north_up;
    east_north_up.col(0) = Eigen::Vector3d(-longitude.sine, longitude.cosine, 0.0);
    east_north_up.col(1) =
        Eigen::Vector3d(-latitude.sine * longitude.cosine, -latitude.sine * longitude.sine, latitude.cosine);
    east_north_up.col(2) =
        Eigen::Vector3d(latitude.cosine * longitude.cosine, latitude.cosine * longitude.sine, latitude.sine);
    return GeocentricFrame(geodetic_to_ecef(latitude_deg, longitude_deg, height_m), east_north_up);
}

Eigen::Vector3d GeocentricFrame::position(const Eigen::Vector3d& global) const {
    return origin_ + rotation_ * global;
}

Eigen::Vector3d GeocentricFrame::direction(const Eigen::Vector3d& v) const { return rotation_ * v; }

Eigen::Quaterniond GeocentricFrame::orientation(const Eigen::Quaterniond& q_global) const {
    return (rotation_quaternion_ * q_global).normalized();
}

EulerAngles dis_euler_angles(const Eigen::Quaterniond& body_to_ecef) {
    const Eigen::Matrix3d r = body_to_ecef.normalized().toRotationMatrix();
    // r = Rz(psi) Ry(theta) Rx(phi); its first column is (cos psi cos theta, sin psi cos theta, -sin theta).
    const double cos_theta = std::hypot(r(0, 0), r(1, 0));
    EulerAngles angles;
    angles.theta = std::atan2(-r(2, 0), cos_theta);
    // Below this, r(0,0) and r(1,0) are rounding noise and say nothing of psi (gimbal lock): only
    // psi - phi (theta = +90) or psi + phi (theta = -90) is defined, and with phi = 0 both read
    // psi = atan2(-r(0,1), r(1,1)).
    constexpr double gimbal_lock_cos_theta = 1e-12;
    angles.psi =
        cos_theta > gimbal_lock_cos_theta ? std::atan2(r(1, 0), r(0, 0)) : std::atan2(-r(0, 1), r(1, 1));
    // phi from Rz(psi)^T r = Ry(theta) Rx(phi), whose second row is (0, cos phi, -sin phi): well
    // conditioned at any theta, and consistent with whatever psi was chosen above (0 at the lock).
    const double sin_psi = std::sin(angles.psi);
    const double cos_psi = std::cos(angles.psi);
    angles.phi = std::atan2(sin_psi * r(0, 2) - cos_psi * r(1, 2), cos_psi * r(1, 1) - sin_psi * r(0, 1));
    return angles;
}

Eigen::Quaterniond from_dis_euler_angles(const EulerAngles& angles) {
    return Eigen::Quaterniond(Eigen::AngleAxisd(angles.psi, Eigen::Vector3d::UnitZ()) *
                              Eigen::AngleAxisd(angles.theta, Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(angles.phi, Eigen::Vector3d::UnitX()));
}

}  // namespace lpss::dis
