#include "dis_gateway.hpp"

#include <spdlog/spdlog.h>

#include <cmath>

namespace lpss::dis {

namespace {

/// DIS reserves entity number 0 (no entity) and 65535 (all entities).
constexpr std::uint64_t kLastEntityNumber = 65534;

bool moves(const DeadReckoningState& s) {
    return !s.velocity.isZero(0.0) || !s.acceleration.isZero(0.0) || !s.angular_velocity_body.isZero(0.0);
}

/// What receivers decode from a PDU: float32 velocities and angles. The filter extrapolates exactly that.
DeadReckoningState as_received(const EntityStatePdu& pdu) {
    DeadReckoningState s;
    s.location = pdu.location;
    s.velocity = pdu.linear_velocity.cast<double>();
    s.acceleration = pdu.dead_reckoning.linear_acceleration.cast<double>();
    s.orientation =
        from_dis_euler_angles(EulerAngles{pdu.orientation.psi, pdu.orientation.theta, pdu.orientation.phi});
    s.angular_velocity_body = pdu.dead_reckoning.angular_velocity.cast<double>();
    return s;
}

}  // namespace

Expected<DisGateway> DisGateway::create(const WorldSettings& settings, const GatewayOptions& options) {
    switch (settings.geo.frame) {
        case GeoReference::Frame::ecef:
            return DisGateway(settings, options, GeocentricFrame::identity());
        case GeoReference::Frame::local_tangent:
            return DisGateway(
                settings, options,
                GeocentricFrame::local_tangent(settings.geo.latitude_deg, settings.geo.longitude_deg,
                                               settings.geo.height_m));
        case GeoReference::Frame::none:
            break;
    }
    return Error{
        "the world is not placed on the Earth: its scene needs a geo reference (geo { ecef {} } for a world "
        "in "
        "ECEF metres, or geo { local_tangent { latitude_deg: ... longitude_deg: ... height_m: ... } })"};
}

DisGateway::DisGateway(const WorldSettings& settings, const GatewayOptions& options,
                       GeocentricFrame geocentric)
    : settings_(settings), options_(options), geocentric_(std::move(geocentric)) {}

std::optional<std::uint16_t> DisGateway::entity_of(BodyId id) const {
    auto it = entities_.find(id);
    if (it == entities_.end()) return std::nullopt;
    return it->second.number;
}

std::uint16_t DisGateway::number_for(BodyId id) {
    if (id >= 1 && id <= kLastEntityNumber && !numbers_.count(static_cast<std::uint16_t>(id))) {
        numbers_[static_cast<std::uint16_t>(id)] = id;
        return static_cast<std::uint16_t>(id);
    }
    // Numbers are taken by ids that fit first come; an id that does not fit, or whose number a bigger id
    // took, gets the next number no one holds. 65,534 entities is DIS's limit per site and application.
    for (std::uint32_t tries = 0; tries < kLastEntityNumber; ++tries) {
        const std::uint16_t n = next_free_number_;
        next_free_number_ = next_free_number_ == kLastEntityNumber ? 1 : next_free_number_ + 1;
        if (!numbers_.count(n)) {
            numbers_[n] = id;
            spdlog::info("lpss-dis: body {} is DIS entity {} (its id does not fit in 16 bits or is taken)",
                         id, n);
            return n;
        }
    }
    return 0;
}

DeadReckoningState DisGateway::truth(const Entity& e) const {
    DeadReckoningState s;
    s.location = geocentric_.position(e.last.global);
    s.velocity = geocentric_.direction(e.last.linear_velocity);
    s.acceleration = e.acceleration;
    s.orientation = geocentric_.orientation(e.last.orientation);
    // DIS carries angular velocity in body axes.
    s.angular_velocity_body = e.last.orientation.conjugate() * e.last.angular_velocity;
    return s;
}

std::vector<EntityStatePdu> DisGateway::deactivate_all(const WorldFrame& last) {
    std::vector<EntityStatePdu> out;
    const std::uint32_t stamp = timestamp(last);
    for (const auto& [id, e] : entities_) {
        EntityStatePdu p = pdu(e, truth(e), stamp);
        p.appearance |= kAppearanceDeactivated;
        out.push_back(p);
    }
    counts_.deactivations += out.size();
    counts_.pdus += out.size();
    entities_.clear();
    numbers_.clear();
    return out;
}

std::uint32_t DisGateway::timestamp(const WorldFrame& frame) const {
    if (options_.relative_timestamps)
        return dis_timestamp(std::fmod(static_cast<double>(frame.frame) * settings_.dt, 3600.0), false);
    const auto ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(frame.started.time_since_epoch()).count();
    return dis_timestamp(static_cast<double>(ms % 3600000) / 1000.0, true);
}

EntityStatePdu DisGateway::pdu(const Entity& e, const DeadReckoningState& s, std::uint32_t stamp) const {
    EntityStatePdu p;
    p.exercise_id = options_.exercise;
    p.timestamp = stamp;
    p.entity_id = EntityIdentifier{options_.site, options_.application, e.number};
    p.entity_type = options_.entity_type;
    p.linear_velocity = s.velocity.cast<float>();
    p.location = s.location;
    const EulerAngles angles = dis_euler_angles(s.orientation);
    p.orientation = EulerAnglesFloat{static_cast<float>(angles.psi), static_cast<float>(angles.theta),
                                     static_cast<float>(angles.phi)};
    p.dead_reckoning.algorithm = options_.algorithm;
    p.dead_reckoning.linear_acceleration = s.acceleration.cast<float>();
    p.dead_reckoning.angular_velocity = s.angular_velocity_body.cast<float>();
    p.marking = e.marking;
    return p;
}

std::vector<EntityStatePdu> DisGateway::take(const WorldFrame& frame, const Describe& describe) {
    std::vector<EntityStatePdu> out;
    // On the wall clock (absolute timestamps), receivers go on extrapolating through a pause: the jump in
    // time makes the gateway correct them. On the world's clock (relative timestamps) nothing passes.
    const double now = static_cast<double>(frame.frame) * settings_.dt +
                       (options_.relative_timestamps ? 0.0 : frame.time_lost_s);
    const std::uint32_t stamp = timestamp(frame);
    ++counts_.frames;
    auto deactivate = [&](std::map<BodyId, Entity>::iterator it) {
        EntityStatePdu last = pdu(it->second, truth(it->second), stamp);
        last.appearance |= kAppearanceDeactivated;
        out.push_back(last);
        ++counts_.deactivations;
        numbers_.erase(it->second.number);
        entities_.erase(it);
    };
    std::vector<BodyId> seen;
    if (frame.every_body) seen.reserve(frame.bodies.size());
    for (const BodyView& b : frame.bodies) {
        if (planes_.count(b.id)) continue;
        auto it = entities_.find(b.id);
        if (it == entities_.end()) {
            const std::optional<BodyDesc> desc = describe(b);
            if (desc && is_plane(desc->shape)) {
                planes_[b.id] = true;
                continue;
            }
            Entity e{number_for(b.id),
                     ascii_marking(desc && !desc->name.empty() ? desc->name : std::to_string(b.id)),
                     DeadReckoningFilter(options_.algorithm, options_.thresholds),
                     b,
                     std::nullopt,
                     0.0,
                     Eigen::Vector3d::Zero()};
            if (e.number == 0) {
                spdlog::warn("lpss-dis: body {} not sent: every DIS entity number is taken", b.id);
                continue;
            }
            it = entities_.emplace(b.id, std::move(e)).first;
        }
        Entity& e = it->second;
        e.last = b;
        // The acceleration receivers extrapolate with (the V algorithms): the velocity's change over the
        // last frames the gateway saw, in the world's time.
        const Eigen::Vector3d velocity = geocentric_.direction(b.linear_velocity);
        if (e.previous_velocity && now > e.previous_time)
            e.acceleration = (velocity - *e.previous_velocity) / (now - e.previous_time);
        if (!b.awake) e.acceleration.setZero();
        e.previous_velocity = velocity;
        e.previous_time = now;
        if (frame.every_body) seen.push_back(b.id);
    }
    if (frame.every_body) {
        // Bodies not in a frame of every body have left the region followed.
        std::sort(seen.begin(), seen.end());
        for (auto it = entities_.begin(); it != entities_.end();) {
            auto next = std::next(it);
            if (!std::binary_search(seen.begin(), seen.end(), it->first)) deactivate(it);
            it = next;
        }
    }
    for (BodyId id : frame.departed) {
        if (auto it = entities_.find(id); it != entities_.end()) deactivate(it);
        planes_.erase(id);
    }
    for (auto& [id, e] : entities_) {
        counts_.body_frames += 1;
        // Every entity, not only the bodies of this frame: a body that stopped is in no frame of changes,
        // while receivers still move it with the velocity they were sent.
        const std::optional<DeadReckoningState> believed = e.filter.receivers_estimate(now);
        const DeadReckoningState state = truth(e);
        if (!e.filter.should_send(state, now)) continue;
        const EntityStatePdu p = pdu(e, state, stamp);
        const bool only_heartbeat =
            believed && !moves(*believed) && (believed->location - state.location).norm() <= 1e-9;
        counts_.heartbeats += only_heartbeat ? 1 : 0;
        e.filter.sent(as_received(p), now);
        out.push_back(p);
    }
    counts_.pdus += out.size();
    return out;
}

}  // namespace lpss::dis
