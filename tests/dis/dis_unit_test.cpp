// Unit tests of the DIS gateway's pieces: geodesy, Euler angles, the Entity State PDU's encoding and dead
// reckoning.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "dis/dead_reckoning.hpp"
#include "dis/entity_state_pdu.hpp"
#include "dis/geodesy.hpp"

namespace lpss::dis {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

double angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
    return a.normalized().angularDistance(b.normalized());
}

// ---------------------------------------------------------------------------------------------------
// Geodesy

TEST(Geodesy, EquatorAndPoleAreWhereWgs84PutsThem) {
    EXPECT_EQ(geodetic_to_ecef(0, 0, 0), Eigen::Vector3d(6378137.0, 0, 0));
    EXPECT_EQ(geodetic_to_ecef(0, 90, 0), Eigen::Vector3d(0, 6378137.0, 0));
    EXPECT_EQ(geodetic_to_ecef(0, 180, 10), Eigen::Vector3d(-6378147.0, 0, 0));
    const Eigen::Vector3d north_pole = geodetic_to_ecef(90, 0, 0);
    EXPECT_EQ(north_pole.x(), 0.0);
    EXPECT_EQ(north_pole.y(), 0.0);
    EXPECT_NEAR(north_pole.z(), 6356752.314245179, 1e-6);  // b = a (1 - f)
    EXPECT_NEAR(geodetic_to_ecef(-90, 0, 100).z(), -6356852.314245179, 1e-6);
}

TEST(Geodesy, MatchesThePublishedIogpExample) {
    // IOGP Guidance Note 7-2, geographic/geocentric conversion example on WGS84:
    // 53 deg 48' 33.820" N, 2 deg 07' 46.380" E, h = 73 m -> X 3771793.968, Y 140253.342, Z 5124304.349.
    const double latitude = 53.0 + 48.0 / 60.0 + 33.820 / 3600.0;
    const double longitude = 2.0 + 7.0 / 60.0 + 46.380 / 3600.0;
    const Eigen::Vector3d ecef = geodetic_to_ecef(latitude, longitude, 73.0);
    EXPECT_NEAR(ecef.x(), 3771793.968, 1e-3);
    EXPECT_NEAR(ecef.y(), 140253.342, 1e-3);
    EXPECT_NEAR(ecef.z(), 5124304.349, 1e-3);
    const Geodetic back = ecef_to_geodetic(Eigen::Vector3d(3771793.968, 140253.342, 5124304.349));
    EXPECT_NEAR(back.latitude_deg, latitude, 1e-8);
    EXPECT_NEAR(back.longitude_deg, longitude, 1e-8);
    EXPECT_NEAR(back.height_m, 73.0, 1e-3);
}

TEST(Geodesy, RoundTripIsBelowAMicrometre) {
    const std::vector<Geodetic> places = {
        {0, 0, 0},
        {45, 45, 0},
        {-33.8688, 151.2093, 58},
        {89.9999999, 12, 3},
        {-89.99, -170, -10},
        {27.9881, 86.925, 8848},
        {51.5, -0.12, -5000},
        {12, 179.999999, 400e3},
        {-60, -179.5, 35786e3},
        {0.0001, -0.0001, 1e6},
        {90, 0, 20},
        {-90, 0, 20},
    };
    for (const Geodetic& place : places) {
        const Eigen::Vector3d ecef =
            geodetic_to_ecef(place.latitude_deg, place.longitude_deg, place.height_m);
        const Geodetic back = ecef_to_geodetic(ecef);
        SCOPED_TRACE(::testing::Message()
                     << place.latitude_deg << ", " << place.longitude_deg << ", " << place.height_m);
        EXPECT_NEAR(back.latitude_deg, place.latitude_deg, 1e-11);
        if (std::abs(place.latitude_deg) < 90) {
            EXPECT_NEAR(back.longitude_deg, place.longitude_deg, 1e-11);
        }
        EXPECT_NEAR(back.height_m, place.height_m, 1e-6);
        const Eigen::Vector3d again = geodetic_to_ecef(back.latitude_deg, back.longitude_deg, back.height_m);
        EXPECT_LT((again - ecef).norm(), 1e-6);
    }
}

TEST(Geodesy, LocalTangentAxesAreEastNorthUp) {
    const auto frame = GeocentricFrame::local_tangent(0, 0, 0);
    EXPECT_EQ(frame.position(Eigen::Vector3d::Zero()), Eigen::Vector3d(6378137.0, 0, 0));
    EXPECT_TRUE(frame.direction(Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-15));
    EXPECT_TRUE(frame.direction(Eigen::Vector3d::UnitY()).isApprox(Eigen::Vector3d::UnitZ(), 1e-15));
    EXPECT_TRUE(frame.direction(Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-15));
    EXPECT_EQ(frame.position(Eigen::Vector3d(1, 0, 0)), Eigen::Vector3d(6378137.0, 1, 0));
    EXPECT_EQ(frame.position(Eigen::Vector3d(0, 0, 1)), Eigen::Vector3d(6378138.0, 0, 0));

    // At the north pole on the Greenwich meridian, north points away from it (-X) and up is +Z.
    const auto pole = GeocentricFrame::local_tangent(90, 0, 0);
    EXPECT_TRUE(pole.direction(Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitX(), 1e-15));
    EXPECT_TRUE(pole.direction(Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitZ(), 1e-15));

    // Up is the ellipsoid normal: a point straight above the origin has the origin's latitude.
    const auto paris = GeocentricFrame::local_tangent(48.8566, 2.3522, 35);
    const Geodetic above = ecef_to_geodetic(paris.position(Eigen::Vector3d(0, 0, 1000)));
    EXPECT_NEAR(above.latitude_deg, 48.8566, 1e-12);
    EXPECT_NEAR(above.longitude_deg, 2.3522, 1e-12);
    EXPECT_NEAR(above.height_m, 1035, 1e-6);
    EXPECT_NEAR(paris.rotation().determinant(), 1.0, 1e-15);
    EXPECT_TRUE((paris.rotation().transpose() * paris.rotation()).isIdentity(1e-15));
}

TEST(Geodesy, LocalTangentOrientationTurnsBodiesWithTheAxes) {
    const auto frame = GeocentricFrame::local_tangent(0, 0, 0);
    // A body at rest in the world's axes faces global x, which is east, which is ECEF +Y here.
    const Eigen::Quaterniond body_to_ecef = frame.orientation(Eigen::Quaterniond::Identity());
    EXPECT_TRUE((body_to_ecef * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-15));
    // A body turned 90 degrees about global up faces north, ECEF +Z.
    const Eigen::Quaterniond north(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()));
    EXPECT_TRUE(
        (frame.orientation(north) * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitZ(), 1e-15));
}

TEST(Geodesy, IdentityFrameChangesNothing) {
    const auto frame = GeocentricFrame::identity();
    const Eigen::Vector3d p(1.5e11, -2.25e10, 3.0);
    EXPECT_EQ(frame.position(p), p);
    EXPECT_EQ(frame.direction(p), p);
    const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
    EXPECT_LT(angle_between(frame.orientation(q), q), 1e-15);
}

// ---------------------------------------------------------------------------------------------------
// Euler angles

TEST(EulerAngles, SimpleCasesFollowTheZYXConvention) {
    const EulerAngles level = dis_euler_angles(Eigen::Quaterniond::Identity());
    EXPECT_EQ(level.psi, 0.0);
    EXPECT_EQ(level.theta, 0.0);
    EXPECT_EQ(level.phi, 0.0);

    // psi about Z: a body heading along ECEF +Y has psi = 90 degrees.
    const Eigen::Quaterniond facing_y(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()));
    EXPECT_NEAR(dis_euler_angles(facing_y).psi, kPi / 2, 1e-15);

    // theta is about the body's Y after the heading turn, phi about its X after both.
    const EulerAngles angles{kPi / 2, 30 * kDegree, 10 * kDegree};
    const Eigen::Quaterniond q = from_dis_euler_angles(angles);
    // Heading +Y, pitched by theta about the new Y (which is ECEF -X): forward = (0, cos, -sin).
    EXPECT_TRUE((q * Eigen::Vector3d::UnitX())
                    .isApprox(Eigen::Vector3d(0, std::cos(30 * kDegree), -std::sin(30 * kDegree)), 1e-15));
    // Rolling about the body's forward axis leaves forward alone and tilts the body's y axis.
    EXPECT_NEAR((q * Eigen::Vector3d::UnitY()).dot(Eigen::Vector3d(-1, 0, 0)), std::cos(10 * kDegree), 1e-15);
    const EulerAngles back = dis_euler_angles(q);
    EXPECT_NEAR(back.psi, angles.psi, 1e-14);
    EXPECT_NEAR(back.theta, angles.theta, 1e-14);
    EXPECT_NEAR(back.phi, angles.phi, 1e-14);
}

TEST(EulerAngles, RoundTripOverTheirRanges) {
    int checked = 0;
    for (double psi = -kPi + 0.01; psi < kPi; psi += 0.37) {
        for (double theta = -kPi / 2 + 0.001; theta < kPi / 2; theta += 0.29) {
            for (double phi = -kPi + 0.02; phi < kPi; phi += 0.41) {
                const EulerAngles angles{psi, theta, phi};
                const Eigen::Quaterniond q = from_dis_euler_angles(angles);
                const EulerAngles back = dis_euler_angles(q);
                ASSERT_NEAR(back.psi, psi, 1e-12) << psi << " " << theta << " " << phi;
                ASSERT_NEAR(back.theta, theta, 1e-12) << psi << " " << theta << " " << phi;
                ASSERT_NEAR(back.phi, phi, 1e-12) << psi << " " << theta << " " << phi;
                // A quaternion's sign and scale do not change the orientation.
                const Eigen::Quaterniond scaled_and_negated(-2 * q.w(), -2 * q.x(), -2 * q.y(), -2 * q.z());
                const EulerAngles same = dis_euler_angles(scaled_and_negated);
                ASSERT_NEAR(same.psi, psi, 1e-12);
                ASSERT_NEAR(same.theta, theta, 1e-12);
                ASSERT_NEAR(same.phi, phi, 1e-12);
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 1000);
}

TEST(EulerAngles, GimbalLockIsFiniteAndGivesTheOrientationBack) {
    for (double theta : {kPi / 2, -kPi / 2, kPi / 2 - 1e-13, -kPi / 2 + 1e-15}) {
        for (double psi : {0.0, 0.7, -2.5}) {
            for (double phi : {0.0, 0.4, 3.0}) {
                const Eigen::Quaterniond q = from_dis_euler_angles({psi, theta, phi});
                const EulerAngles angles = dis_euler_angles(q);
                ASSERT_TRUE(std::isfinite(angles.psi) && std::isfinite(angles.theta) &&
                            std::isfinite(angles.phi));
                EXPECT_NEAR(angles.theta, theta, 1e-6);
                EXPECT_LT(angle_between(from_dis_euler_angles(angles), q), 1e-9)
                    << psi << " " << theta << " " << phi;
            }
        }
    }
    // Exactly at the lock, phi is 0 and psi carries the turn about the vertical.
    const Eigen::Quaterniond nose_up = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                                       Eigen::AngleAxisd(-kPi / 2, Eigen::Vector3d::UnitY());
    const EulerAngles locked = dis_euler_angles(nose_up);
    EXPECT_NEAR(locked.theta, -kPi / 2, 1e-7);
    EXPECT_NEAR(locked.psi, 0.7, 1e-7);
    EXPECT_NEAR(locked.phi, 0.0, 1e-7);
}

// ---------------------------------------------------------------------------------------------------
// Entity State PDU

EntityStatePdu every_field_set() {
    EntityStatePdu pdu;
    pdu.exercise_id = 3;
    pdu.timestamp = 0x89abcdefu;
    pdu.pdu_status = 0x12;
    pdu.padding = 0;
    pdu.entity_id = {0x0102, 0x0304, 0xfffe};
    pdu.force_id = 2;
    pdu.entity_type = {1, 2, 225, 3, 4, 5, 6};
    pdu.alternative_entity_type = {7, 8, 0x1234, 9, 10, 11, 12};
    pdu.linear_velocity = Eigen::Vector3f(1.5f, -2.25f, 1e-3f);
    pdu.location = Eigen::Vector3d(6378137.123456789, -1234567.000000001, 4.5e-9);
    pdu.orientation = {3.0f, -1.5f, 0.1f};
    pdu.appearance = kAppearanceDeactivated | 0x5;
    pdu.dead_reckoning.algorithm = dead_reckoning_algorithm::kRvw;
    for (std::size_t i = 0; i < pdu.dead_reckoning.other_parameters.size(); ++i) {
        pdu.dead_reckoning.other_parameters[i] = static_cast<std::uint8_t>(0xa0 + i);
    }
    pdu.dead_reckoning.linear_acceleration = Eigen::Vector3f(0, 0, -9.81f);
    pdu.dead_reckoning.angular_velocity = Eigen::Vector3f(0.1f, -0.2f, 0.3f);
    pdu.marking = ascii_marking("lpss 42");
    pdu.capabilities = 0xdeadbeefu;
    return pdu;
}

std::uint64_t read_big_endian(const std::uint8_t* bytes, int size) {
    std::uint64_t value = 0;
    for (int i = 0; i < size; ++i)
        value = (value << 8) | bytes[i];
    return value;
}

double double_at(const std::array<std::uint8_t, kEntityStatePduSize>& bytes, std::size_t offset) {
    const std::uint64_t bits = read_big_endian(bytes.data() + offset, 8);
    double value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
}

float float_at(const std::array<std::uint8_t, kEntityStatePduSize>& bytes, std::size_t offset) {
    const auto bits = static_cast<std::uint32_t>(read_big_endian(bytes.data() + offset, 4));
    float value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
}

TEST(EntityStatePdu, EncodeDecodeRoundTripKeepsEveryField) {
    const EntityStatePdu pdu = every_field_set();
    const auto bytes = encode(pdu);
    const auto decoded = decode(bytes.data(), bytes.size());
    ASSERT_TRUE(decoded.ok()) << decoded.error().message;
    const EntityStatePdu& d = *decoded;
    EXPECT_EQ(d.protocol_version, 7);
    EXPECT_EQ(d.exercise_id, 3);
    EXPECT_EQ(d.pdu_type, 1);
    EXPECT_EQ(d.protocol_family, 1);
    EXPECT_EQ(d.timestamp, 0x89abcdefu);
    EXPECT_EQ(d.length, 144);
    EXPECT_EQ(d.pdu_status, 0x12);
    EXPECT_EQ(d.entity_id.site, 0x0102);
    EXPECT_EQ(d.entity_id.application, 0x0304);
    EXPECT_EQ(d.entity_id.entity, 0xfffe);
    EXPECT_EQ(d.force_id, 2);
    EXPECT_EQ(d.number_of_variable_parameters, 0);
    EXPECT_EQ(std::memcmp(&d.entity_type, &pdu.entity_type, sizeof(EntityType)), 0);
    EXPECT_EQ(d.alternative_entity_type.country, 0x1234);
    EXPECT_EQ(d.alternative_entity_type.extra, 12);
    EXPECT_EQ(d.linear_velocity, pdu.linear_velocity);
    EXPECT_EQ(d.location, pdu.location);  // bit for bit
    EXPECT_EQ(d.orientation.psi, 3.0f);
    EXPECT_EQ(d.orientation.theta, -1.5f);
    EXPECT_EQ(d.orientation.phi, 0.1f);
    EXPECT_EQ(d.appearance, kAppearanceDeactivated | 0x5);
    EXPECT_EQ(d.dead_reckoning.algorithm, dead_reckoning_algorithm::kRvw);
    EXPECT_EQ(d.dead_reckoning.other_parameters, pdu.dead_reckoning.other_parameters);
    EXPECT_EQ(d.dead_reckoning.linear_acceleration, pdu.dead_reckoning.linear_acceleration);
    EXPECT_EQ(d.dead_reckoning.angular_velocity, pdu.dead_reckoning.angular_velocity);
    EXPECT_EQ(d.marking.character_set, kMarkingCharacterSetAscii);
    EXPECT_EQ(marking_text(d.marking), "lpss 42");
    EXPECT_EQ(d.capabilities, 0xdeadbeefu);
    EXPECT_EQ(encode(d), bytes);
}

TEST(EntityStatePdu, FieldsSitAtTheStandardsByteOffsets) {
    const EntityStatePdu pdu = every_field_set();
    const auto bytes = encode(pdu);
    // Header (IEEE 1278.1-2012, 6.2.66): version, exercise, type, family, timestamp, length, status, pad.
    EXPECT_EQ(bytes[0], 7);
    EXPECT_EQ(bytes[1], 3);
    EXPECT_EQ(bytes[2], 1);
    EXPECT_EQ(bytes[3], 1);
    EXPECT_EQ(read_big_endian(&bytes[4], 4), 0x89abcdefu);
    EXPECT_EQ(bytes[entity_state_offset::kLength], 0x00);
    EXPECT_EQ(bytes[entity_state_offset::kLength + 1], 144);
    EXPECT_EQ(bytes[10], 0x12);
    EXPECT_EQ(bytes[11], 0);
    // Entity ID at 12, force at 18, variable parameter count at 19.
    EXPECT_EQ(read_big_endian(&bytes[12], 2), 0x0102u);
    EXPECT_EQ(read_big_endian(&bytes[14], 2), 0x0304u);
    EXPECT_EQ(read_big_endian(&bytes[16], 2), 0xfffeu);
    EXPECT_EQ(bytes[18], 2);
    EXPECT_EQ(bytes[19], 0);
    // Entity type at 20: kind, domain, country (16 bits), category, subcategory, specific, extra.
    EXPECT_EQ(bytes[20], 1);
    EXPECT_EQ(bytes[21], 2);
    EXPECT_EQ(read_big_endian(&bytes[22], 2), 225u);
    EXPECT_EQ(bytes[27], 6);
    EXPECT_EQ(read_big_endian(&bytes[30], 2), 0x1234u);  // alternative type at 28
    EXPECT_EQ(float_at(bytes, 36), 1.5f);
    EXPECT_EQ(float_at(bytes, 44), 1e-3f);
    EXPECT_EQ(entity_state_offset::kLocation, 48u);
    EXPECT_EQ(double_at(bytes, 48), 6378137.123456789);
    EXPECT_EQ(double_at(bytes, 56), -1234567.000000001);
    EXPECT_EQ(double_at(bytes, 64), 4.5e-9);
    EXPECT_EQ(float_at(bytes, 72), 3.0f);
    EXPECT_EQ(float_at(bytes, 80), 0.1f);
    EXPECT_EQ(read_big_endian(&bytes[84], 4), kAppearanceDeactivated | 0x5u);
    EXPECT_EQ(bytes[84], 0x00);
    EXPECT_EQ(bytes[85], 0x80);  // bit 23 is the top bit of the second byte on the wire
    // Dead reckoning at 88: algorithm, 15 other bytes, acceleration at 104, angular velocity at 116.
    EXPECT_EQ(bytes[88], 4);
    EXPECT_EQ(bytes[89], 0xa0);
    EXPECT_EQ(bytes[103], 0xae);
    EXPECT_EQ(float_at(bytes, 112), -9.81f);
    EXPECT_EQ(float_at(bytes, 116), 0.1f);
    EXPECT_EQ(float_at(bytes, 124), 0.3f);
    // Marking at 128: character set then 11 characters; capabilities at 140.
    EXPECT_EQ(bytes[128], 1);
    EXPECT_EQ(bytes[129], 'l');
    EXPECT_EQ(bytes[134], '4');
    EXPECT_EQ(bytes[135], '2');
    EXPECT_EQ(bytes[136], 0);
    EXPECT_EQ(bytes[139], 0);
    EXPECT_EQ(read_big_endian(&bytes[140], 4), 0xdeadbeefu);
}

TEST(EntityStatePdu, DecodeRefusesWhatIsNotADis7EntityStatePdu) {
    const auto good = encode(every_field_set());
    auto refused_because = [](std::vector<std::uint8_t> bytes) {
        const auto decoded = decode(bytes.data(), bytes.size());
        return decoded.ok() ? std::string("accepted") : decoded.error().message;
    };
    std::vector<std::uint8_t> bytes(good.begin(), good.end());
    EXPECT_EQ(refused_because(bytes), "accepted");

    EXPECT_NE(refused_because({bytes.begin(), bytes.begin() + 5}).find("shorter than a PDU header"),
              std::string::npos);
    EXPECT_NE(refused_because({bytes.begin(), bytes.end() - 1}).find("143 bytes"), std::string::npos);
    auto longer = bytes;
    longer.push_back(0);
    EXPECT_NE(refused_because(longer).find("145 bytes"), std::string::npos);

    auto dis6 = bytes;
    dis6[0] = 6;
    EXPECT_NE(refused_because(dis6).find("protocol version 6"), std::string::npos);
    auto fire = bytes;
    fire[2] = 2;
    EXPECT_NE(refused_because(fire).find("PDU type 2"), std::string::npos);
    auto family = bytes;
    family[3] = 2;
    EXPECT_NE(refused_because(family).find("protocol family 2"), std::string::npos);
    auto length = bytes;
    length[9] = 160;
    EXPECT_NE(refused_because(length).find("length field says 160"), std::string::npos);
    auto parameters = bytes;
    parameters[19] = 1;
    EXPECT_NE(refused_because(parameters).find("1 variable parameter"), std::string::npos);
}

TEST(EntityStatePdu, TimestampCountsPastTheHourWithTheAbsoluteBitLow) {
    EXPECT_EQ(dis_timestamp(0, false), 0u);
    EXPECT_EQ(dis_timestamp(0, true), 1u);
    // Half an hour is half of 2^31 - 1 units, shifted above the absolute bit.
    EXPECT_EQ(dis_timestamp(1800, false), 1073741823u << 1);
    EXPECT_EQ(dis_timestamp(1800, true), (1073741823u << 1) | 1u);
    // One unit is 3600 / (2^31 - 1) s, about 1.676 us.
    EXPECT_EQ(dis_timestamp(3600.0 / 2147483647.0 * 1.5, false), 1u << 1);
    EXPECT_EQ(dis_timestamp(std::nextafter(3600.0, 0.0), false) >> 1, 2147483646u);
    // The field rolls over with the hour.
    EXPECT_EQ(dis_timestamp(3600.0, true), 1u);
    EXPECT_EQ(dis_timestamp(3600.0 + 1800.0, false), dis_timestamp(1800, false));
    EXPECT_EQ(dis_timestamp(-1800.0, false), dis_timestamp(1800, false));
    EXPECT_EQ(dis_timestamp(std::numeric_limits<double>::quiet_NaN(), true), 1u);
}

TEST(EntityStatePdu, MarkingKeepsElevenAsciiCharacters) {
    const EntityMarking marking = ascii_marking("body 1234567890");
    EXPECT_EQ(marking.character_set, 1);
    EXPECT_EQ(marking_text(marking), "body 123456");
    EXPECT_EQ(marking_text(ascii_marking("")), "");
    EXPECT_EQ(marking_text(ascii_marking("caf\xc3\xa9\n")), "caf???") << "not ASCII: '?'";
}

// ---------------------------------------------------------------------------------------------------
// Dead reckoning

DeadReckoningState moving_state() {
    DeadReckoningState state;
    state.location = Eigen::Vector3d(6378137.0, 1000.0, -250.0);
    state.velocity = Eigen::Vector3d(12.0, -3.0, 0.5);
    state.acceleration = Eigen::Vector3d(0.25, 1.5, -9.81);
    state.orientation = from_dis_euler_angles({0.3, -0.2, 1.1});
    state.angular_velocity_body = Eigen::Vector3d(0.4, -0.7, 0.2);
    return state;
}

// q' = q (0, w) / 2 with w in body axes, integrated by classical Runge-Kutta: an independent check of
// the closed-form rotation.
Eigen::Quaterniond integrate_body_rotation(Eigen::Quaterniond q, const Eigen::Vector3d& w, double t,
                                           int steps) {
    const Eigen::Quaterniond omega(0, w.x(), w.y(), w.z());
    auto derivative = [&](const Eigen::Quaterniond& at) {
        Eigen::Quaterniond d = at * omega;
        d.coeffs() *= 0.5;
        return d;
    };
    const double h = t / steps;
    for (int i = 0; i < steps; ++i) {
        auto add = [](const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double s) {
            return Eigen::Quaterniond(a.coeffs() + s * b.coeffs());
        };
        const Eigen::Quaterniond k1 = derivative(q);
        const Eigen::Quaterniond k2 = derivative(add(q, k1, h / 2));
        const Eigen::Quaterniond k3 = derivative(add(q, k2, h / 2));
        const Eigen::Quaterniond k4 = derivative(add(q, k3, h));
        q.coeffs() += h / 6 * (k1.coeffs() + 2 * k2.coeffs() + 2 * k3.coeffs() + k4.coeffs());
    }
    return q.normalized();
}

TEST(DeadReckoning, VelocityAlgorithmsFollowConstantAccelerationExactly) {
    namespace drm = dead_reckoning_algorithm;
    const DeadReckoningState sent = moving_state();
    for (double dt : {0.0, 0.016, 1.0, 7.5, -0.5}) {
        const Eigen::Vector3d location =
            sent.location + sent.velocity * dt + 0.5 * sent.acceleration * dt * dt;
        const Eigen::Vector3d velocity = sent.velocity + sent.acceleration * dt;
        for (std::uint8_t algorithm : {drm::kRvw, drm::kFvw}) {
            const DeadReckoningState state = extrapolate(sent, algorithm, dt);
            EXPECT_LT((state.location - location).norm(), 1e-9) << int(algorithm) << " dt " << dt;
            EXPECT_LT((state.velocity - velocity).norm(), 1e-12) << int(algorithm) << " dt " << dt;
            EXPECT_EQ(state.acceleration, sent.acceleration);
        }
    }
}

TEST(DeadReckoning, PositionAlgorithmsKeepTheVelocityAndIgnoreAcceleration) {
    namespace drm = dead_reckoning_algorithm;
    const DeadReckoningState sent = moving_state();
    for (std::uint8_t algorithm : {drm::kFpw, drm::kRpw}) {
        const DeadReckoningState state = extrapolate(sent, algorithm, 2.0);
        EXPECT_LT((state.location - (sent.location + 2.0 * sent.velocity)).norm(), 1e-9);
        EXPECT_EQ(state.velocity, sent.velocity);
    }
    const DeadReckoningState still = extrapolate(sent, drm::kStatic, 2.0);
    EXPECT_EQ(still.location, sent.location);
    EXPECT_EQ(still.velocity, sent.velocity);
    EXPECT_LT(angle_between(still.orientation, sent.orientation), 1e-15);
}

TEST(DeadReckoning, RotatingAlgorithmsTurnAboutTheBodyAxes) {
    namespace drm = dead_reckoning_algorithm;
    const DeadReckoningState sent = moving_state();
    for (double dt : {0.016, 1.0, 4.0}) {
        const Eigen::Quaterniond expected =
            integrate_body_rotation(sent.orientation, sent.angular_velocity_body, dt, 20000);
        for (std::uint8_t algorithm : {drm::kRpw, drm::kRvw}) {
            EXPECT_LT(angle_between(extrapolate(sent, algorithm, dt).orientation, expected), 1e-9)
                << int(algorithm) << " dt " << dt;
        }
        for (std::uint8_t algorithm : {drm::kFpw, drm::kFvw}) {
            EXPECT_LT(angle_between(extrapolate(sent, algorithm, dt).orientation, sent.orientation), 1e-15);
        }
    }

    // Body axes, not ECEF axes: pitched nose down so the body's z axis is ECEF +X, a yaw rate about the
    // body's z swings the nose about ECEF X: forward goes from -Z to (0, sin wt, -cos wt).
    DeadReckoningState pitched;
    pitched.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY()));
    pitched.angular_velocity_body = Eigen::Vector3d(0, 0, 0.5);
    const double t = 1.3;
    const Eigen::Vector3d forward = extrapolate(pitched, drm::kRpw, t).orientation * Eigen::Vector3d::UnitX();
    EXPECT_LT((forward - Eigen::Vector3d(0, std::sin(0.5 * t), -std::cos(0.5 * t))).norm(), 1e-12);
}

TEST(DeadReckoning, FilterSendsFirstThenOnlyPastAThreshold) {
    namespace drm = dead_reckoning_algorithm;
    DeadReckoningFilter filter(drm::kFpw);
    EXPECT_DOUBLE_EQ(filter.thresholds().position_m, 1.0);
    EXPECT_DOUBLE_EQ(filter.thresholds().orientation_rad, 3 * kDegree);
    EXPECT_DOUBLE_EQ(filter.thresholds().heartbeat_s, 5.0);

    DeadReckoningState sent = moving_state();
    sent.acceleration.setZero();
    EXPECT_TRUE(filter.should_send(sent, 10.0));
    EXPECT_FALSE(filter.receivers_estimate(10.0).has_value());
    filter.sent(sent, 10.0);
    EXPECT_FALSE(filter.should_send(sent, 10.0));

    // One second later, on the extrapolated path but off by less, then more, than a metre.
    DeadReckoningState truth = extrapolate(sent, drm::kFpw, 1.0);
    EXPECT_FALSE(filter.should_send(truth, 11.0));
    truth.location += Eigen::Vector3d(0, 0.9, 0);
    EXPECT_FALSE(filter.should_send(truth, 11.0));
    truth.location += Eigen::Vector3d(0, 0.2, 0);
    EXPECT_TRUE(filter.should_send(truth, 11.0));

    // Turned by less, then more, than 3 degrees.
    truth = extrapolate(sent, drm::kFpw, 1.0);
    const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
    truth.orientation = sent.orientation * Eigen::Quaterniond(Eigen::AngleAxisd(2.9 * kDegree, axis));
    EXPECT_FALSE(filter.should_send(truth, 11.0));
    truth.orientation = sent.orientation * Eigen::Quaterniond(Eigen::AngleAxisd(3.1 * kDegree, axis));
    EXPECT_TRUE(filter.should_send(truth, 11.0));

    // Sending resets the reference.
    filter.sent(truth, 11.0);
    EXPECT_FALSE(filter.should_send(truth, 11.0));
    EXPECT_LT((filter.receivers_estimate(12.0)->location - (truth.location + truth.velocity)).norm(), 1e-9);
}

TEST(DeadReckoning, FilterSendsAHeartbeatEveryFiveSeconds) {
    namespace drm = dead_reckoning_algorithm;
    DeadReckoningFilter filter(drm::kRvw);
    const DeadReckoningState sent = moving_state();
    filter.sent(sent, 100.0);
    // The truth follows the dead reckoned path exactly: only the heartbeat sends.
    EXPECT_FALSE(filter.should_send(extrapolate(sent, drm::kRvw, 4.999), 104.999));
    EXPECT_TRUE(filter.should_send(extrapolate(sent, drm::kRvw, 5.0), 105.0));

    DeadReckoningFilter slow(drm::kRvw, {1.0, 3 * kDegree, 60.0});
    slow.sent(sent, 100.0);
    EXPECT_FALSE(slow.should_send(extrapolate(sent, drm::kRvw, 30.0), 130.0));
    EXPECT_TRUE(slow.should_send(extrapolate(sent, drm::kRvw, 60.0), 160.0));
}

}  // namespace
}  // namespace lpss::dis
