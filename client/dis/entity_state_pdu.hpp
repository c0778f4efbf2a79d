// The DIS 7 Entity State PDU (IEEE 1278.1-2012, 7.2.2) without variable parameters, as a plain struct of
// its wire fields, and its 144-byte big-endian encoding.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "lpss/common/expected.hpp"

namespace lpss::dis {

inline constexpr std::uint8_t kProtocolVersionDis7 = 7;
inline constexpr std::uint8_t kPduTypeEntityState = 1;
inline constexpr std::uint8_t kProtocolFamilyEntityInformation = 1;
/// Bytes of an Entity State PDU with no variable parameter records (each record adds 16).
inline constexpr std::size_t kEntityStatePduSize = 144;

/// Dead Reckoning Algorithm field (SISO-REF-010, "Dead Reckoning Algorithm"). F/R: fixed or rotating
/// orientation; P/V: constant velocity or constant acceleration; W/B: world or body axes.
namespace dead_reckoning_algorithm {
inline constexpr std::uint8_t kOther = 0;
inline constexpr std::uint8_t kStatic = 1;
inline constexpr std::uint8_t kFpw = 2;  // DRM(F, P, W)
inline constexpr std::uint8_t kRpw = 3;  // DRM(R, P, W)
inline constexpr std::uint8_t kRvw = 4;  // DRM(R, V, W)
inline constexpr std::uint8_t kFvw = 5;  // DRM(F, V, W)
inline constexpr std::uint8_t kFpb = 6;  // DRM(F, P, B)
inline constexpr std::uint8_t kRpb = 7;  // DRM(R, P, B)
inline constexpr std::uint8_t kRvb = 8;  // DRM(R, V, B)
inline constexpr std::uint8_t kFvb = 9;  // DRM(F, V, B)
}  // namespace dead_reckoning_algorithm

/// Entity Appearance bit 23, "State": 0 active, 1 deactivated. From SISO-REF-010 (the DIS enumerations),
/// the appearance records of platforms of every domain (land 4.3.1.1 in the R35 numbering, air,
/// surface, subsurface, space) and of life forms, which all put State at bit 23; IEEE 1278.1-2012
/// has an entity that leaves the exercise send a last Entity State PDU with it set.
inline constexpr std::uint32_t kAppearanceDeactivated = 1u << 23;

/// Entity Marking character set 1: ASCII.
inline constexpr std::uint8_t kMarkingCharacterSetAscii = 1;

struct EntityIdentifier {
    std::uint16_t site = 0;
    std::uint16_t application = 0;
    std::uint16_t entity = 0;
};

struct EntityType {
    std::uint8_t kind = 0;
    std::uint8_t domain = 0;
    std::uint16_t country = 0;
    std::uint8_t category = 0;
    std::uint8_t subcategory = 0;
    std::uint8_t specific = 0;
    std::uint8_t extra = 0;
};

/// The wire form of DIS Euler angles: float32 radians (see EulerAngles in geodesy.hpp for the convention).
struct EulerAnglesFloat {
    float psi = 0;
    float theta = 0;
    float phi = 0;
};

struct DeadReckoningParameters {
    std::uint8_t algorithm = dead_reckoning_algorithm::kFpw;
    /// Algorithm-specific (e.g. quaternion rotation data), zero for the W algorithms.
    std::array<std::uint8_t, 15> other_parameters{};
    /// m/s^2, ECEF axes for the W algorithms.
    Eigen::Vector3f linear_acceleration = Eigen::Vector3f::Zero();
    /// rad/s, in the entity's body axes.
    Eigen::Vector3f angular_velocity = Eigen::Vector3f::Zero();
};

struct EntityMarking {
    std::uint8_t character_set = kMarkingCharacterSetAscii;
    /// Unused characters are 0.
    std::array<std::uint8_t, 11> characters{};
};

/// An ASCII marking of the first 11 characters of text.
EntityMarking ascii_marking(std::string_view text);
/// The characters of a marking up to the first 0.
std::string marking_text(const EntityMarking& marking);

/// Every field, in wire order. The defaults make a valid header; encode writes the fields as they are,
/// so a caller that changes length, protocol version or the variable parameter count gets what it set.
struct EntityStatePdu {
    // PDU header.
    std::uint8_t protocol_version = kProtocolVersionDis7;
    std::uint8_t exercise_id = 1;
    std::uint8_t pdu_type = kPduTypeEntityState;
    std::uint8_t protocol_family = kProtocolFamilyEntityInformation;
    std::uint32_t timestamp = 0;  // see dis_timestamp
    std::uint16_t length = kEntityStatePduSize;
    std::uint8_t pdu_status = 0;
    std::uint8_t padding = 0;

    EntityIdentifier entity_id;
    std::uint8_t force_id = 0;
    std::uint8_t number_of_variable_parameters = 0;
    EntityType entity_type;
    EntityType alternative_entity_type;
    /// m/s, ECEF axes.
    Eigen::Vector3f linear_velocity = Eigen::Vector3f::Zero();
    /// ECEF metres.
    Eigen::Vector3d location = Eigen::Vector3d::Zero();
    EulerAnglesFloat orientation;
    std::uint32_t appearance = 0;
    DeadReckoningParameters dead_reckoning;
    EntityMarking marking;
    std::uint32_t capabilities = 0;
};

/// Byte offsets of the fields the tests and readers of raw captures look at.
namespace entity_state_offset {
inline constexpr std::size_t kLength = 8;
inline constexpr std::size_t kEntityId = 12;
inline constexpr std::size_t kEntityType = 20;
inline constexpr std::size_t kLinearVelocity = 36;
inline constexpr std::size_t kLocation = 48;
inline constexpr std::size_t kOrientation = 72;
inline constexpr std::size_t kAppearance = 84;
inline constexpr std::size_t kDeadReckoning = 88;
inline constexpr std::size_t kMarking = 128;
inline constexpr std::size_t kCapabilities = 140;
}  // namespace entity_state_offset

std::array<std::uint8_t, kEntityStatePduSize> encode(const EntityStatePdu& pdu);

/// Refuses anything but a whole DIS 7 Entity State PDU without variable parameters: a datagram of
/// another size, a length field that disagrees with it, another protocol version, PDU type or family.
Expected<EntityStatePdu> decode(const std::uint8_t* data, std::size_t size);

/// The header Timestamp (IEEE 1278.1-2012, 6.2.88): time past the hour in the upper 31 bits, in units of
/// 3600 s / (2^31 - 1) (about 1.68 microseconds; the scale open-dis and the standard's "2^31 - 1 units
/// per hour" use), and in the low bit 1 for absolute time (host clocks synchronised to UTC) or 0 for
/// relative time. seconds_past_hour is taken modulo 3600, since the field rolls over every hour.
std::uint32_t dis_timestamp(double seconds_past_hour, bool absolute);

}  // namespace lpss::dis
