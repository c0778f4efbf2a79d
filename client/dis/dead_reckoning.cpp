#include "dead_reckoning.hpp"

#include "entity_state_pdu.hpp"

namespace lpss::dis {
namespace {

// Orientation after turning for dt at a constant angular velocity given in body axes: the turn is about
// a body axis, so it composes on the right of body -> ECEF.
Eigen::Quaterniond rotate_in_body_axes(const Eigen::Quaterniond& body_to_ecef,
                                       const Eigen::Vector3d& angular_velocity_body, double dt) {
    const double rate = angular_velocity_body.norm();
    if (rate == 0.0 || dt == 0.0) return body_to_ecef;
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(rate * dt, angular_velocity_body / rate));
    return (body_to_ecef * turn).normalized();
}

}  // namespace

DeadReckoningState extrapolate(const DeadReckoningState& sent, std::uint8_t algorithm, double dt) {
    namespace drm = dead_reckoning_algorithm;
    DeadReckoningState state = sent;
    const bool first_order = algorithm == drm::kFpw || algorithm == drm::kRpw;
    const bool second_order = algorithm == drm::kRvw || algorithm == drm::kFvw;
    const bool rotating = algorithm == drm::kRpw || algorithm == drm::kRvw;
    if (first_order) state.location = sent.location + sent.velocity * dt;
    if (second_order) {
        state.location = sent.location + sent.velocity * dt + 0.5 * sent.acceleration * dt * dt;
        state.velocity = sent.velocity + sent.acceleration * dt;
    }
    if (rotating) state.orientation = rotate_in_body_axes(sent.orientation, sent.angular_velocity_body, dt);
    return state;
}

DeadReckoningFilter::DeadReckoningFilter(std::uint8_t algorithm, DeadReckoningThresholds thresholds)
    : algorithm_(algorithm), thresholds_(thresholds) {}

std::optional<DeadReckoningState> DeadReckoningFilter::receivers_estimate(double now) const {
    if (!last_sent_) return std::nullopt;
    return extrapolate(*last_sent_, algorithm_, now - last_sent_time_);
}

bool DeadReckoningFilter::should_send(const DeadReckoningState& truth, double now) const {
    const auto estimate = receivers_estimate(now);
    if (!estimate) return true;
    // Times are sums of frame steps: 601/60 - 301/60 comes out a hair under 5. A nanosecond of slack keeps
    // the heartbeat on the frame it is due at.
    if (now - last_sent_time_ >= thresholds_.heartbeat_s - 1e-9) return true;
    if ((estimate->location - truth.location).norm() > thresholds_.position_m) return true;
    return estimate->orientation.angularDistance(truth.orientation) > thresholds_.orientation_rad;
}

void DeadReckoningFilter::sent(const DeadReckoningState& state, double now) {
    last_sent_ = state;
    last_sent_time_ = now;
}

}  // namespace lpss::dis
