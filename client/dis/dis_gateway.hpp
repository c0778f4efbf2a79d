// What lpss-dis sends: for each frame of the world, the Entity State PDUs a DIS federation needs, and no
// more. Each body is an entity; the gateway runs the receivers' dead reckoning for it and sends a PDU when
// their picture is off by more than the thresholds, or on the heartbeat: a body at rest costs a heartbeat,
// not a frame. A body that leaves the world (or the region followed) gets a last PDU with the deactivated
// appearance bit, as receivers expect. Planes are not entities (a DIS entity has a place; a plane is
// everywhere).
//
// Time is the world's: frame * dt, plus (with absolute timestamps) the time a --realtime cluster has let go
// in its pauses, which makes it wall time for such a cluster whatever the delay before frames reach this
// client. A cluster not run in real time moves faster than the receivers' clocks, and lpss-dis says so.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "dead_reckoning.hpp"
#include "entity_state_pdu.hpp"
#include "geodesy.hpp"
#include "lpss/client/client.hpp"

namespace lpss::dis {

struct GatewayOptions {
    std::uint8_t exercise = 1;
    std::uint16_t site = 1;
    std::uint16_t application = 1;
    std::uint8_t algorithm = dead_reckoning_algorithm::kRvw;
    DeadReckoningThresholds thresholds;
    /// Timestamps from the world's time (relative, frame * dt past the hour) instead of the wall clock at
    /// the frame's start (absolute, for hosts whose clocks are synchronised).
    bool relative_timestamps = false;
    EntityType entity_type;  ///< given to every entity (kind 0, "other", by default)
};

/// Counts since the gateway started.
struct GatewayCounts {
    std::uint64_t frames = 0;
    std::uint64_t body_frames = 0;  ///< bodies times frames: what one PDU per body per frame would send
    std::uint64_t pdus = 0;
    std::uint64_t heartbeats = 0;  ///< PDUs sent only because the heartbeat was due
    std::uint64_t deactivations = 0;
};

class DisGateway {
public:
    /// Refused when the world is not placed on the Earth (its scene has no geo reference).
    static Expected<DisGateway> create(const WorldSettings& settings, const GatewayOptions& options);

    /// Takes a frame (every body, or changes) and returns the PDUs to send for it. `describe` names a body
    /// new to the gateway (its marking) and tells planes apart.
    using Describe = std::function<std::optional<BodyDesc>(const BodyView&)>;
    std::vector<EntityStatePdu> take(const WorldFrame& frame, const Describe& describe);

    /// Last PDUs for every entity, deactivated, for a gateway that stops (receivers drop the entities
    /// at once instead of at their timeout). The gateway holds no entity afterwards.
    std::vector<EntityStatePdu> deactivate_all(const WorldFrame& last);

    /// The DIS entity number of a body: its id where that fits in 1..65534, otherwise one given in order
    /// of appearance from the numbers no body id uses (logged when given).
    std::optional<std::uint16_t> entity_of(BodyId id) const;
    const GatewayCounts& counts() const { return counts_; }
    const GeocentricFrame& frame() const { return geocentric_; }

private:
    DisGateway(const WorldSettings& settings, const GatewayOptions& options, GeocentricFrame geocentric);

    struct Entity {
        std::uint16_t number = 0;
        EntityMarking marking;
        DeadReckoningFilter filter;
        BodyView last;                                     ///< the newest state seen
        std::optional<Eigen::Vector3d> previous_velocity;  ///< ECEF, at previous_time: for the acceleration
        double previous_time = 0.0;
        Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();
    };

    std::uint16_t number_for(BodyId id);
    DeadReckoningState truth(const Entity& entity) const;
    EntityStatePdu pdu(const Entity& entity, const DeadReckoningState& state, std::uint32_t timestamp) const;
    std::uint32_t timestamp(const WorldFrame& frame) const;

    WorldSettings settings_;
    GatewayOptions options_;
    GeocentricFrame geocentric_;
    std::map<BodyId, Entity> entities_;
    std::unordered_map<BodyId, bool> planes_;  ///< bodies known not to be entities
    std::unordered_map<std::uint16_t, BodyId> numbers_;
    std::uint16_t next_free_number_ = 1;
    GatewayCounts counts_;
};

}  // namespace lpss::dis
