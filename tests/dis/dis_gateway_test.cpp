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
    // Its number is free again: a big id arriving later may take it, and then body 5, back, gets another.
    g.take(frame(3, {body(70000, Eigen::Vector3d(6.4e6, 0, 0))}), boxes());
    g.take(frame(4, {body(5, Eigen::Vector3d(6.4e6, 0, 1))}), boxes());
    ASSERT_TRUE(g.entity_of(70000) && g.entity_of(5));
    EXPECT_NE(*g.entity_of(70000), *g.entity_of(5));
    // And nothing more of the entity that left: after the newcomers' first PDUs, only their heartbeats.
    for (std::uint64_t n = 5; n < 300; ++n)
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

TEST(DisGateway, ABigIdFirstDoesNotTakeTheNumberOfASmallIdForGood) {
    auto made = DisGateway::create(ecef_world(), {});
    ASSERT_TRUE(made);
    DisGateway& g = made.value();
    const Eigen::Vector3d at(6.4e6, 0, 0);
    g.take(frame(1, {body(1ull << 40, at)}, true), boxes());
    g.take(frame(2, {body(1, at)}), boxes());
    ASSERT_TRUE(g.entity_of(1ull << 40) && g.entity_of(1));
    EXPECT_NE(*g.entity_of(1ull << 40), *g.entity_of(1)) << "two entities with one number";
}

TEST(DisGateway, AngularVelocityGoesInBodyAxes) {
    auto made = DisGateway::create(ecef_world(), {});
    ASSERT_TRUE(made);
    BodyView b = body(3, Eigen::Vector3d(6.4e6, 0, 0));
    b.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
    b.angular_velocity = Eigen::Vector3d(1, 0, 0);  // world axes: about x, which is the body's -y
    const auto pdus = made.value().take(frame(1, {b}, true), boxes());
    ASSERT_EQ(pdus.size(), 1u);
    EXPECT_LT((pdus[0].dead_reckoning.angular_velocity - Eigen::Vector3f(0, -1, 0)).norm(), 1e-6)
        << pdus[0].dead_reckoning.angular_velocity.transpose();
}

TEST(DisGateway, StoppingDeactivatesEveryEntity) {
    auto made = DisGateway::create(ecef_world(), {});
    ASSERT_TRUE(made);
    DisGateway& g = made.value();
    const WorldFrame first =
        frame(1, {body(1, Eigen::Vector3d(6.4e6, 0, 0)), body(2, Eigen::Vector3d(6.4e6, 0, 3))}, true);
    g.take(first, boxes());
    const auto last = g.deactivate_all(first);
    ASSERT_EQ(last.size(), 2u);
    for (const EntityStatePdu& p : last)
        EXPECT_EQ(p.appearance & kAppearanceDeactivated, kAppearanceDeactivated);
    EXPECT_FALSE(g.entity_of(1));
    EXPECT_TRUE(g.take(frame(2, {}), boxes()).empty());
}

TEST(DisGateway, AfterAPauseOnTheWallClockMovingEntitiesAreCorrected) {
    GatewayOptions options;
    options.thresholds.heartbeat_s = 1000.0;
    auto made = DisGateway::create(ecef_world(), options);
    ASSERT_TRUE(made);
    DisGateway& g = made.value();
    const Eigen::Vector3d v(10, 0, 0);
    Eigen::Vector3d at(6.4e6, 0, 0);
    WorldFrame f = frame(1, {body(4, at, v)}, true);
    ASSERT_EQ(g.take(f, boxes()).size(), 1u);
    at += v / 60.0;
    f = frame(2, {body(4, at, v)}, false);
    EXPECT_TRUE(g.take(f, boxes()).empty()) << "on course";
    // The cluster paused 0.5 s: receivers moved it 5 m on; the world did not.
    at += v / 60.0;
    f = frame(3, {body(4, at, v)}, false);
    f.time_lost_s = 0.5;
    EXPECT_EQ(g.take(f, boxes()).size(), 1u) << "receivers are 5 m ahead after the pause";
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

namespace lpss {
namespace {

// The --region option of every client program.
TEST(ParseRegion, TakesSixIndicesAndRefusesAnythingElseQuotingIt) {
    const auto r = parse_region("-1,2,3,4,-5,-5");
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_EQ(r->lo, (SectorKey{-1, 3, -5}));
    EXPECT_EQ(r->hi, (SectorKey{2, 4, -5}));
    for (const std::string bad :
         {"0,1,0,1,0", "0,1,0,1,0,1,9", "0,1,0,1,0,1x", "a,b,c,d,e,f", "1,0,0,1,0,1"}) {
        const auto refused = parse_region(bad);
        ASSERT_FALSE(refused) << bad;
        EXPECT_NE(refused.error().message.find("'" + bad + "'"), std::string::npos)
            << refused.error().message;
    }
}

}  // namespace
}  // namespace lpss
