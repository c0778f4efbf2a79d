// DIS dead reckoning (IEEE 1278.1-2012, Annex E): how receivers move an entity between Entity State PDUs,
// and the sender-side rule that sends a PDU when their picture drifts too far from the truth.
#pragma once

#include <cstdint>
#include <optional>

#include <Eigen/Geometry>

namespace lpss::dis {

/// An entity's kinematic state as a PDU carries it, all in ECEF: location in metres, velocity and
/// acceleration in ECEF axes, orientation body -> ECEF, angular velocity in the entity's body axes
/// (as the PDU's dead reckoning angular velocity is).
struct DeadReckoningState {
    Eigen::Vector3d location = Eigen::Vector3d::Zero();
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d angular_velocity_body = Eigen::Vector3d::Zero();
};

/// The state a receiver computes dt seconds after `sent`, with the world-axes algorithms of Annex E:
///   Static (1): nothing moves.
///   DRM(F,P,W) (2): location + velocity dt; orientation fixed.
///   DRM(R,P,W) (3): as FPW, and the orientation turns by the body angular velocity for dt.
///   DRM(R,V,W) (4): location + velocity dt + acceleration dt^2 / 2, velocity + acceleration dt; turns.
///   DRM(F,V,W) (5): as RVW with a fixed orientation.
/// The rotation is exact for a constant body-axes angular velocity (the quaternion exponential
/// q(t) = q0 * exp(w dt / 2), which is Annex E's DR matrix). Other algorithms (Other, the body-axes ones)
/// are not implemented here and extrapolate as Static: lpss sends only world-axes algorithms.
DeadReckoningState extrapolate(const DeadReckoningState& sent, std::uint8_t algorithm, double dt);

/// When to send. The defaults are the DIS ones (the parameters table of IEEE 1278.1-2012):
/// DRA_POS_THRSH 1 m, DRA_ORIENT_THRSH 3 degrees, HBT_ESPDU_TIMER 5 s.
struct DeadReckoningThresholds {
    double position_m = 1.0;
    double orientation_rad = 3.0 * 3.14159265358979323846 / 180.0;
    double heartbeat_s = 5.0;
};

/// The sender's copy of what receivers believe of one entity. Each frame the gateway asks should_send
/// with the true state; when it sends, it tells sent() what it sent (ideally as the receivers decode it,
/// float32 velocities included, so that both sides extrapolate the same thing).
class DeadReckoningFilter {
public:
    explicit DeadReckoningFilter(std::uint8_t algorithm, DeadReckoningThresholds thresholds = {});

    /// True before the first send, when the extrapolated location is more than position_m from the
    /// truth, when the extrapolated orientation is more than orientation_rad from it, or when
    /// heartbeat_s or more passed since the last send.
    bool should_send(const DeadReckoningState& truth, double now) const;
    void sent(const DeadReckoningState& state, double now);

    /// What receivers show at `now`; empty before the first send.
    std::optional<DeadReckoningState> receivers_estimate(double now) const;

    std::uint8_t algorithm() const { return algorithm_; }
    const DeadReckoningThresholds& thresholds() const { return thresholds_; }

private:
    std::uint8_t algorithm_;
    DeadReckoningThresholds thresholds_;
    std::optional<DeadReckoningState> last_sent_;
    double last_sent_time_ = 0;
};

}  // namespace lpss::dis
