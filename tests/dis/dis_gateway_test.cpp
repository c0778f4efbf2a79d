// The gateway's decisions, on frames made here: what it sends, when, and as which entity.
#include <gtest/gtest.h>

#include <cmath>

#include "dis/dis_gateway.hpp"
#include "dis/geodesy.hpp"

namespace lpss::dis {
namespace {

WorldSettings ecef_world() {
    WorldSettings s;
    s.sector_size = 64.0;
    s.geo.frame = GeoReference::Frame::ecef;
    return s;
}

BodyView body(BodyId id, const Eigen::Vector3d& at, const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero(),
              bool awake = true) {
    BodyView b;
    b.id = id;
    b.global = at;
    b.linear_velocity = velocity;
    b.awake = awake;
    return b;
}

DisGateway::Describe boxes() {
    return [](const BodyView& b) {
        BodyDesc d;
        d.id = b.id;
        d.name = "box-" + std::to_string(b.id);
        d.shape = Box{};
        d.mass = 1.0;
        return std::optional<BodyDesc>(d);
    };
}

WorldFrame frame(std::uint64_t n, std::vector<BodyView> bodies, bool every_body = false) {
    WorldFrame f;
    f.frame = n;
    f.bodies = std::move(bodies);
    f.every_body = every_body;
    return f;
}

TEST(DisGateway, AWorldNotPlacedOnTheEarthIsRefusedWithWhatToWrite) {
    WorldSettings s;
    auto g = DisGateway::create(s, {});
    ASSERT_FALSE(g);
    EXPECT_NE(g.error().message.find("geo { ecef {} }"), std::string::npos) << g.error().message;
}

TEST(DisGateway, ABodyAtRestCostsAHeartbeatNotAFrame) {
    auto made = DisGateway::create(ecef_world(), {});
    ASSERT_TRUE(made);
    DisGateway& g = made.value();
    const Eigen::Vector3d at(6.4e6, 1.0, 2.0);
    std::vector<std::uint64_t> sent_at;
    for (std::uint64_t n = 1; n <= 1200; ++n) {
        // Frames of changes: a resting body is only in the first.
        std::vector<BodyView> bodies;
        if (n == 1) bodies.push_back(body(7, at, Eigen::Vector3d::Zero(), false));
        const auto pdus = g.take(frame(n, bodies, n == 1), boxes());
        for (const EntityStatePdu& p : pdus) {
            EXPECT_EQ(p.entity_id.entity, 7);
            EXPECT_EQ(p.location, at);
            sent_at.push_back(n);
        }
    }
    // 60 frames a second: the first frame, then every 5 s (300 frames).
    EXPECT_EQ(sent_at, (std::vector<std::uint64_t>{1, 301, 601, 901}));
    EXPECT_EQ(g.counts().heartbeats, 3u);
    EXPECT_EQ(g.counts().body_frames, 1200u);
}

TEST(DisGateway, SteadyMotionIsDeadReckonedAndATurnIsSentOnceItIsOffByTheThreshold) {
    GatewayOptions options;
    options.thresholds.heartbeat_s = 1000.0;
    auto made = DisGateway::create(ecef_world(), options);
    ASSERT_TRUE(made);
    DisGateway& g = made.value();
    const double dt = 1.0 / 60.0;
    Eigen::Vector3d at(6.4e6, 0.0, 0.0);
    Eigen::Vector3d v(10.0, 0.0, 0.0);
    std::vector<std::uint64_t> sent_at;
    for (std::uint64_t n = 1; n <= 600; ++n) {
        if (n == 301) v = Eigen::Vector3d(10.0, 3.0, 0.0);  // turns: receivers go on straight
        if (n > 1) at += v * dt;
        if (!g.take(frame(n, {body(9, at, v)}, n == 1), boxes()).empty()) sent_at.push_back(n);
    }
    ASSERT_GE(sent_at.size(), 2u);
    EXPECT_EQ(sent_at[0], 1u);
    // Off sideways by 3 m/s * t: past 1 m after a third of a second (20 frames), plus the acceleration
    // the turn shows for one frame, which the next PDU corrects.
    EXPECT_GE(sent_at[1], 301u);
    EXPECT_LE(sent_at[1], 325u);
    EXPECT_LE(sent_at.size(), 5u)
        << "steady motion after the turn should need no more than a correction or two";
}

TEST(DisGateway, ABodyThatLeavesIsDeactivatedAndItsNumberFreed) {
    auto made = DisGateway::create(ecef_world(), {});
    ASSERT_TRUE(made);
    DisGateway& g = made.value();
    g.take(frame(1, {body(5, Eigen::Vector3d(6.4e6, 0, 0))}, true), boxes());
    WorldFrame gone = frame(2, {});
    gone.departed = {5};
    const auto pdus = g.take(gone, boxes());
    ASSERT_EQ(pdus.size(), 1u);
    EXPECT_EQ(pdus[0].entity_id.entity, 5);
    EXPECT_NE(pdus[0].appearance & kAppearanceDeactivated, 0u);
    EXPECT_FALSE(g.entity_of(5));
    EXPECT_EQ(g.counts().deactivations, 1u);
    // And nothing more of it afterwards, heartbeat or not.
    for (std::uint64_t n = 3; n < 700; ++n)
        EXPECT_TRUE(g.take(frame(n, {}), boxes()).empty()) << n;
}

TEST(DisGateway, IdsThatDoNotFitSixteenBitsGetNumbersNoOtherBodyHolds) {
    auto made = DisGateway::create(ecef_world(), {});
    ASSERT_TRUE(made);
    DisGateway& g = made.value();
    const Eigen::Vector3d at(6.4e6, 0, 0);
    g.take(frame(1, {body(1, at), body(2, at), body(70000, at), body(1ull << 40, at)}, true), boxes());
    EXPECT_EQ(g.entity_of(1), 1);
    EXPECT_EQ(g.entity_of(2), 2);
    const auto big = g.entity_of(70000), bigger = g.entity_of(1ull << 40);
    ASSERT_TRUE(big && bigger);
    EXPECT_NE(*big, 1);
    EXPECT_NE(*big, 2);
    EXPECT_NE(*big, *bigger);
    EXPECT_NE(*big, 0);
}

TEST(DisGateway, PlanesAreNotEntities) {
    auto made = DisGateway::create(ecef_world(), {});
    ASSERT_TRUE(made);
    DisGateway& g = made.value();
    auto with_plane = [](const BodyView& b) {
        BodyDesc d;
        d.id = b.id;
        d.shape = b.id == 1 ? Shape{Plane{}} : Shape{Box{}};
        return std::optional<BodyDesc>(d);
    };
    const auto pdus =
        g.take(frame(1, {body(1, Eigen::Vector3d(6.4e6, 0, 0)), body(2, Eigen::Vector3d(6.4e6, 0, 3))}, true),
               with_plane);
    ASSERT_EQ(pdus.size(), 1u);
    EXPECT_EQ(pdus[0].entity_id.entity, 2);
}

TEST(DisGateway, ALocalTangentWorldIsSentInEcefWithItsOriginAtTheReferencePoint) {
    WorldSettings s;
    s.sector_size = 64.0;
    s.geo = GeoReference{GeoReference::Frame::local_tangent, 51.195, -1.85, 130.0};
    GatewayOptions options;
    options.site = 12;
    options.application = 34;
    options.exercise = 3;
    auto made = DisGateway::create(s, options);
    ASSERT_TRUE(made);
    const Eigen::Vector3d up = made.value().frame().direction(Eigen::Vector3d::UnitZ());
    const auto pdus = made.value().take(
        frame(1, {body(3, Eigen::Vector3d(0, 0, 10), Eigen::Vector3d(0, 0, 2))}, true), boxes());
    ASSERT_EQ(pdus.size(), 1u);
    const Eigen::Vector3d expected = geodetic_to_ecef(51.195, -1.85, 140.0);
    EXPECT_LT((pdus[0].location - expected).norm(), 1e-6);
    EXPECT_LT((pdus[0].linear_velocity.cast<double>() - 2.0 * up).norm(), 1e-6);
    EXPECT_EQ(pdus[0].entity_id.site, 12);
    EXPECT_EQ(pdus[0].entity_id.application, 34);
    EXPECT_EQ(pdus[0].exercise_id, 3);
    EXPECT_EQ(marking_text(pdus[0].marking), "box-3");
}

}  // namespace
}  // namespace lpss::dis
