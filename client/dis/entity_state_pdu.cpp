#include "entity_state_pdu.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

namespace lpss::dis {
namespace {

// DIS puts every field in network byte order (IEEE 1278.1-2012, 5.2.3 / 6.1.4); floats are IEEE 754
// written as their bit patterns in that order.
class BigEndianWriter {
public:
    explicit BigEndianWriter(std::array<std::uint8_t, kEntityStatePduSize>& bytes) : bytes_(bytes) {}

    void u8(std::uint8_t value) { bytes_[offset_++] = value; }
    void u16(std::uint16_t value) { unsigned_of_size(value, 2); }
    void u32(std::uint32_t value) { unsigned_of_size(value, 4); }
    void f32(float value) {
        std::uint32_t bits;
        std::memcpy(&bits, &value, sizeof bits);
        u32(bits);
    }
    void f64(double value) {
        std::uint64_t bits;
        std::memcpy(&bits, &value, sizeof bits);
        unsigned_of_size(bits, 8);
    }
    std::size_t offset() const { return offset_; }

private:
    void unsigned_of_size(std::uint64_t value, int size) {
        for (int i = size - 1; i >= 0; --i)
            bytes_[offset_++] = static_cast<std::uint8_t>(value >> (8 * i));
    }

    std::array<std::uint8_t, kEntityStatePduSize>& bytes_;
    std::size_t offset_ = 0;
};

// Reads a buffer whose size the caller checked first.
class BigEndianReader {
public:
    explicit BigEndianReader(const std::uint8_t* data) : data_(data) {}

    std::uint8_t u8() { return data_[offset_++]; }
    std::uint16_t u16() { return static_cast<std::uint16_t>(unsigned_of_size(2)); }
    std::uint32_t u32() { return static_cast<std::uint32_t>(unsigned_of_size(4)); }
    float f32() {
        const std::uint32_t bits = u32();
        float value;
        std::memcpy(&value, &bits, sizeof value);
        return value;
    }
    double f64() {
        const std::uint64_t bits = unsigned_of_size(8);
        double value;
        std::memcpy(&value, &bits, sizeof value);
        return value;
    }
    std::size_t offset() const { return offset_; }

private:
    std::uint64_t unsigned_of_size(int size) {
        std::uint64_t value = 0;
        for (int i = 0; i < size; ++i)
            value = (value << 8) | data_[offset_++];
        return value;
    }

    const std::uint8_t* data_;
    std::size_t offset_ = 0;
};

void write_entity_type(BigEndianWriter& out, const EntityType& type) {
    out.u8(type.kind);
    out.u8(type.domain);
    out.u16(type.country);
    out.u8(type.category);
    out.u8(type.subcategory);
    out.u8(type.specific);
    out.u8(type.extra);
}

EntityType read_entity_type(BigEndianReader& in) {
    EntityType type;
    type.kind = in.u8();
    type.domain = in.u8();
    type.country = in.u16();
    type.category = in.u8();
    type.subcategory = in.u8();
    type.specific = in.u8();
    type.extra = in.u8();
    return type;
}

void write_vector(BigEndianWriter& out, const Eigen::Vector3f& v) {
    for (int i = 0; i < 3; ++i)
        out.f32(v[i]);
}

Eigen::Vector3f read_vector_float(BigEndianReader& in) {
    Eigen::Vector3f v;
    for (int i = 0; i < 3; ++i)
        v[i] = in.f32();
    return v;
}

}  // namespace

EntityMarking ascii_marking(std::string_view text) {
    EntityMarking marking;
    marking.character_set = kMarkingCharacterSetAscii;
    const std::size_t count = std::min(text.size(), marking.characters.size());
    // Character set 1 is ASCII: anything else (a byte of a UTF-8 name, a control character) becomes '?'.
    std::transform(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(count),
                   marking.characters.begin(), [](char c) {
                       const auto u = static_cast<unsigned char>(c);
                       return static_cast<std::uint8_t>(u >= 0x20 && u < 0x7f ? u : '?');
                   });
    return marking;
}

std::string marking_text(const EntityMarking& marking) {
    const auto end = std::find(marking.characters.begin(), marking.characters.end(), std::uint8_t{0});
    return std::string(marking.characters.begin(), end);
}

std::array<std::uint8_t, kEntityStatePduSize> encode(const EntityStatePdu& pdu) {
    std::array<std::uint8_t, kEntityStatePduSize> bytes{};
    BigEndianWriter out(bytes);
    out.u8(pdu.protocol_version);
    out.u8(pdu.exercise_id);
    out.u8(pdu.pdu_type);
    out.u8(pdu.protocol_family);
    out.u32(pdu.timestamp);
    out.u16(pdu.length);
    out.u8(pdu.pdu_status);
    out.u8(pdu.padding);

    out.u16(pdu.entity_id.site);
    out.u16(pdu.entity_id.application);
    out.u16(pdu.entity_id.entity);
    out.u8(pdu.force_id);
    out.u8(pdu.number_of_variable_parameters);
    write_entity_type(out, pdu.entity_type);
    write_entity_type(out, pdu.alternative_entity_type);
    write_vector(out, pdu.linear_velocity);
    for (int i = 0; i < 3; ++i)
        out.f64(pdu.location[i]);
    out.f32(pdu.orientation.psi);
    out.f32(pdu.orientation.theta);
    out.f32(pdu.orientation.phi);
    out.u32(pdu.appearance);

    out.u8(pdu.dead_reckoning.algorithm);
    for (std::uint8_t byte : pdu.dead_reckoning.other_parameters)
        out.u8(byte);
    write_vector(out, pdu.dead_reckoning.linear_acceleration);
    write_vector(out, pdu.dead_reckoning.angular_velocity);

    out.u8(pdu.marking.character_set);
    for (std::uint8_t character : pdu.marking.characters)
        out.u8(character);
    out.u32(pdu.capabilities);
    assert(out.offset() == kEntityStatePduSize);
    return bytes;
}

Expected<EntityStatePdu> decode(const std::uint8_t* data, std::size_t size) {
    using std::to_string;
    if (size < 12) {
        return Error{"DIS datagram of " + to_string(size) + " bytes is shorter than a PDU header (12)"};
    }
    BigEndianReader in(data);
    EntityStatePdu pdu;
    pdu.protocol_version = in.u8();
    pdu.exercise_id = in.u8();
    pdu.pdu_type = in.u8();
    pdu.protocol_family = in.u8();
    pdu.timestamp = in.u32();
    pdu.length = in.u16();
    pdu.pdu_status = in.u8();
    pdu.padding = in.u8();

    if (pdu.protocol_version != kProtocolVersionDis7) {
        return Error{"DIS protocol version " + to_string(pdu.protocol_version) + ", expected " +
                     to_string(kProtocolVersionDis7) + " (IEEE 1278.1-2012)"};
    }
    if (pdu.pdu_type != kPduTypeEntityState) {
        return Error{"DIS PDU type " + to_string(pdu.pdu_type) + " is not an Entity State PDU (type " +
                     to_string(kPduTypeEntityState) + ")"};
    }
    if (pdu.protocol_family != kProtocolFamilyEntityInformation) {
        return Error{"Entity State PDU with protocol family " + to_string(pdu.protocol_family) +
                     ", expected " + to_string(kProtocolFamilyEntityInformation) +
                     " (Entity Information/Interaction)"};
    }
    if (size != kEntityStatePduSize) {
        return Error{"Entity State PDU datagram of " + to_string(size) + " bytes, expected " +
                     to_string(kEntityStatePduSize) + " (no variable parameters)"};
    }
    if (pdu.length != size) {
        return Error{"Entity State PDU length field says " + to_string(pdu.length) +
                     " bytes, the datagram has " + to_string(size)};
    }

    pdu.entity_id.site = in.u16();
    pdu.entity_id.application = in.u16();
    pdu.entity_id.entity = in.u16();
    pdu.force_id = in.u8();
    pdu.number_of_variable_parameters = in.u8();
    if (pdu.number_of_variable_parameters != 0) {
        return Error{"Entity State PDU announces " + to_string(pdu.number_of_variable_parameters) +
                     " variable parameter records in 144 bytes, which have room for none"};
    }
    pdu.entity_type = read_entity_type(in);
    pdu.alternative_entity_type = read_entity_type(in);
    pdu.linear_velocity = read_vector_float(in);
    for (int i = 0; i < 3; ++i)
        pdu.location[i] = in.f64();
    pdu.orientation.psi = in.f32();
    pdu.orientation.theta = in.f32();
    pdu.orientation.phi = in.f32();
    pdu.appearance = in.u32();

    pdu.dead_reckoning.algorithm = in.u8();
    for (std::uint8_t& byte : pdu.dead_reckoning.other_parameters)
        byte = in.u8();
    pdu.dead_reckoning.linear_acceleration = read_vector_float(in);
    pdu.dead_reckoning.angular_velocity = read_vector_float(in);

    pdu.marking.character_set = in.u8();
    for (std::uint8_t& character : pdu.marking.characters)
        character = in.u8();
    pdu.capabilities = in.u32();
    assert(in.offset() == kEntityStatePduSize);
    return pdu;
}

std::uint32_t dis_timestamp(double seconds_past_hour, bool absolute) {
    constexpr double kSecondsPerHour = 3600.0;
    constexpr std::uint32_t kUnitsPerHour = 0x7fffffffu;  // 2^31 - 1
    double seconds = std::fmod(seconds_past_hour, kSecondsPerHour);
    if (!(seconds >= 0.0)) seconds = std::isnan(seconds) ? 0.0 : seconds + kSecondsPerHour;
    const double units = std::floor(seconds * (kUnitsPerHour / kSecondsPerHour));
    const auto clamped = static_cast<std::uint32_t>(std::min(units, static_cast<double>(kUnitsPerHour)));
    return (clamped << 1) | (absolute ? 1u : 0u);
}

}  // namespace lpss::dis
