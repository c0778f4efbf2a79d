#include "lpss/common/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <string>

namespace lpss {
namespace {

const char* kGoodScene = R"(
sector_size: 128
precision_radius: 1000
gravity { y: -9.81 }
bodies {
  id: 1 name: "ground"
  shape { plane { normal { y: 2 } offset: 0 } }
}
bodies {
  id: 2 name: "ball"
  shape { sphere { radius: 0.5 } }
  mass: 1
  position { global { x: 1e12 y: 3 z: -1 } }
  orientation { w: 2 }
}
bodies {
  id: 3 name: "far crate"
  shape { box { half_extents { x: 1 y: 1 z: 1 } } }
  mass: 10
  position { sector { i: 4611686018427387000 j: 0 k: -7 local { x: 70 } } }
  material { friction: 0.2 restitution: 0.1 }
  ccd: true
}
)";

Scene good_scene() { return parse_scene(kGoodScene, "good").value(); }

// Parses the good scene with one body field replaced, and returns the error message ("" if accepted).
std::string refusal(const std::string& text) {
    Expected<Scene> scene = parse_scene(text, "test");
    return scene.ok() ? std::string() : scene.error().message;
}

TEST(Scene, ParsesFieldsAndDefaults) {
    Scene s = good_scene();
    EXPECT_EQ(s.settings.sector_size, 128);
    EXPECT_DOUBLE_EQ(s.settings.dt, 1.0 / 60.0);  // absent: 1/60
    EXPECT_EQ(s.settings.precision_radius, 1000);
    EXPECT_EQ(s.settings.gravity, Eigen::Vector3d(0, -9.81, 0));
    ASSERT_EQ(s.bodies.size(), 3u);
    const Plane& plane = std::get<Plane>(s.bodies[0].shape);
    EXPECT_EQ(plane.normal, Eigen::Vector3d::UnitY()) << "normal normalised";
    EXPECT_TRUE(s.bodies[0].is_static());
    const BodyDesc& ball = s.bodies[1];
    EXPECT_EQ(std::get<Eigen::Vector3d>(ball.position), Eigen::Vector3d(1e12, 3, -1));
    EXPECT_EQ(ball.orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs()) << "quaternion normalised";
    EXPECT_EQ(ball.material.friction, 0.5) << "absent material: defaults";
    const BodyDesc& crate = s.bodies[2];
    const auto& sp = std::get<SectorPosition>(crate.position);
    EXPECT_EQ(sp.sector, (SectorKey{4611686018427387000, 0, -7}));
    EXPECT_EQ(sp.local.x(), 70);
    EXPECT_EQ(crate.material.restitution, 0.1);
    EXPECT_TRUE(crate.ccd);
    EXPECT_EQ(s.bodies[0].orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs())
        << "absent: identity";
}

TEST(Scene, FormatThenParseGivesTheSameScene) {
    Scene s = good_scene();
    s.settings.substeps = 3;
    s.settings.solver_iterations = 17;
    s.settings.hysteresis = 0.125;
    s.settings.friction_combine = CombineRule::geometric_mean;
    s.settings.restitution_combine = CombineRule::max;
    Scene again = parse_scene(format_scene(s), "formatted").value();
    ASSERT_EQ(again.bodies.size(), s.bodies.size());
    EXPECT_EQ(again.settings.dt, s.settings.dt);
    EXPECT_EQ(again.settings.sector_size, s.settings.sector_size);
    EXPECT_EQ(again.settings.precision_radius, s.settings.precision_radius);
    EXPECT_EQ(again.settings.gravity, s.settings.gravity);
    EXPECT_EQ(again.settings.sleeping, s.settings.sleeping);
    EXPECT_EQ(again.settings.substeps, 3);
    EXPECT_EQ(again.settings.solver_iterations, 17);
    EXPECT_EQ(again.settings.hysteresis, 0.125);
    EXPECT_EQ(again.settings.friction_combine, CombineRule::geometric_mean);
    EXPECT_EQ(again.settings.restitution_combine, CombineRule::max);
    for (std::size_t n = 0; n < s.bodies.size(); ++n) {
        const BodyDesc& a = again.bodies[n];
        const BodyDesc& b = s.bodies[n];
        EXPECT_EQ(a.id, b.id);
        EXPECT_EQ(a.name, b.name);
        EXPECT_EQ(a.mass, b.mass);
        EXPECT_EQ(a.shape.index(), b.shape.index()) << "body " << b.id;
        EXPECT_EQ(bounding_radius(a.shape), bounding_radius(b.shape)) << "body " << b.id;
        ASSERT_EQ(a.position.index(), b.position.index());
        if (const auto* g = std::get_if<Eigen::Vector3d>(&b.position)) {
            EXPECT_EQ(std::get<Eigen::Vector3d>(a.position), *g) << "body " << b.id;
        } else {
            const auto& sp = std::get<SectorPosition>(b.position);
            EXPECT_EQ(std::get<SectorPosition>(a.position).sector, sp.sector) << "body " << b.id;
            EXPECT_EQ(std::get<SectorPosition>(a.position).local, sp.local) << "body " << b.id;
        }
        EXPECT_EQ(a.orientation.coeffs(), b.orientation.coeffs()) << "body " << b.id;
        EXPECT_EQ(a.linear_velocity, b.linear_velocity) << "body " << b.id;
        EXPECT_EQ(a.angular_velocity, b.angular_velocity) << "body " << b.id;
        EXPECT_EQ(a.material.friction, b.material.friction) << "body " << b.id;
        EXPECT_EQ(a.material.restitution, b.material.restitution) << "body " << b.id;
        EXPECT_EQ(a.ccd, b.ccd) << "body " << b.id;
        EXPECT_EQ(a.asleep, b.asleep) << "body " << b.id;
    }
    EXPECT_EQ(format_scene(again), format_scene(s)) << "formatting is a fixed point";
    EXPECT_EQ(std::get<SectorPosition>(again.bodies[2].position).sector.i, 4611686018427387000);
    EXPECT_EQ(std::get<Eigen::Vector3d>(again.bodies[1].position).x(), 1e12);
}

TEST(Scene, AsleepNeedsAWorldThatSleepsAndRoundTrips) {
    const std::string body =
        "bodies { id: 1 name: \"crate\" shape { sphere { radius: 1 } } mass: 1 asleep: true }";
    EXPECT_NE(
        refusal("sector_size: 128 sleeping: false " + body).find("asleep needs a scene that allows sleeping"),
        std::string::npos);
    Scene s = parse_scene("sector_size: 128 " + body, "test").value();
    EXPECT_TRUE(s.bodies[0].asleep);
    EXPECT_TRUE(parse_scene(format_scene(s), "formatted").value().bodies[0].asleep);
    s.bodies[0].asleep = false;
    EXPECT_FALSE(parse_scene(format_scene(s), "formatted").value().bodies[0].asleep);
}

TEST(Scene, CombineRulesDefaultToBulletsProductAndAreNamedInTheFile) {
    const Scene plain = parse_scene("sector_size: 64", "plain").value();
    EXPECT_EQ(plain.settings.friction_combine, CombineRule::product);
    EXPECT_EQ(plain.settings.restitution_combine, CombineRule::product);
    const Scene jolt =
        parse_scene("sector_size: 64 friction_combine: GEOMETRIC_MEAN restitution_combine: MAX", "j").value();
    EXPECT_EQ(jolt.settings.friction_combine, CombineRule::geometric_mean);
    EXPECT_EQ(jolt.settings.restitution_combine, CombineRule::max);
    auto bad = parse_scene("sector_size: 64 friction_combine: HARMONIC", "bad");
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.error().message.find("HARMONIC"), std::string::npos) << bad.error().message;
    WorldSettings settings;
    settings.restitution_combine = static_cast<CombineRule>(9);  // e.g. from a newer peer on the wire
    Status refused = validate(settings);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("restitution_combine"), std::string::npos)
        << refused.error().message;
    // The rules themselves: two coefficients 0.5 and 0.2.
    EXPECT_DOUBLE_EQ(combine(CombineRule::product, 0.5, 0.2), 0.1);
    EXPECT_DOUBLE_EQ(combine(CombineRule::geometric_mean, 0.5, 0.2), std::sqrt(0.1));
    EXPECT_DOUBLE_EQ(combine(CombineRule::average, 0.5, 0.2), 0.35);
    EXPECT_DOUBLE_EQ(combine(CombineRule::min, 0.5, 0.2), 0.2);
    EXPECT_DOUBLE_EQ(combine(CombineRule::max, 0.5, 0.2), 0.5);
}

TEST(Scene, SyntaxErrorsGiveLineAndColumn) {
    std::string e = refusal("sector_size: 128\nbodies { id: 1 shape { sphere { radius: } } }\n");
    EXPECT_NE(e.find("test:2:"), std::string::npos) << e;
    e = refusal("sector_size: 128\nbodys { }\n");
    EXPECT_NE(e.find("bodys"), std::string::npos) << e;
}

TEST(Scene, RefusesBadSettings) {
    EXPECT_NE(refusal("dt: 0.01").find("sector_size"), std::string::npos);
    EXPECT_NE(refusal("sector_size: -5").find("sector_size must be a finite number > 0, got -5"),
              std::string::npos);
    EXPECT_NE(refusal("sector_size: 128 dt: 0").find("dt"), std::string::npos);
    EXPECT_NE(refusal("sector_size: inf").find("sector_size"), std::string::npos);
    std::string e = refusal("sector_size: 1024 precision_radius: 1000");
    EXPECT_NE(e.find("largest sector_size allowed is 384.9"), std::string::npos) << e;
    EXPECT_NE(refusal("sector_size: 128 gravity { y: nan }").find("gravity"), std::string::npos);
    EXPECT_NE(refusal("sector_size: 128 hysteresis: 0.6").find("hysteresis"), std::string::npos);
}

struct BadBody {
    const char* body;      // the body's fields
    const char* expected;  // text the error must contain (body name and field)
};

class RefusesBadBody : public ::testing::TestWithParam<BadBody> {};

TEST_P(RefusesBadBody, WithAnErrorNamingBodyAndField) {
    std::string text =
        std::string(
            "sector_size: 128\nbodies { id: 1 name: \"ok\" shape { sphere { radius: 1 } } mass: 1 }\n"
            "bodies { name: \"bad\" ") +
        GetParam().body + " }\n";
    std::string e = refusal(text);
    ASSERT_FALSE(e.empty()) << "accepted: " << GetParam().body;
    EXPECT_NE(e.find(GetParam().expected), std::string::npos) << e;
    EXPECT_NE(e.find("body 'bad'"), std::string::npos) << e;
}

INSTANTIATE_TEST_SUITE_P(
    Scene, RefusesBadBody,
    ::testing::Values(
        BadBody{"id: 2 shape { sphere { radius: nan } } mass: 1", "shape.sphere.radius is not finite"},
        BadBody{"id: 2 shape { sphere { radius: 0 } } mass: 1", "shape.sphere.radius must be > 0"},
        BadBody{"id: 2 shape { box { half_extents { x: 1 y: -1 z: 1 } } } mass: 1",
                "shape.box.half_extents.y must be > 0"},
        BadBody{"id: 2 shape { capsule { radius: 1 height: -2 } } mass: 1",
                "shape.capsule.height must be >= 0"},
        BadBody{"id: 2 shape { convex_hull { points { x: 1 } points { y: 1 } points { z: 1 } } } mass: 1",
                "shape.convex_hull.points needs at least 4 points"},
        BadBody{"id: 2 shape { convex_hull { points { x: 1 } points { y: 1 } points { x: 1 y: 1 } points { } "
                "} } mass: 1",
                "flat or collinear"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: -1", "mass must be >= 0, got -1"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: inf", "mass is not finite"},
        BadBody{"id: 1 shape { sphere { radius: 1 } } mass: 1", "id is used by another body"},
        BadBody{"shape { sphere { radius: 1 } } mass: 1", "id must be non-zero"},
        BadBody{"id: 2 shape { box { half_extents { x: 50 y: 50 z: 10 } } } mass: 1",
                "more than sector_size 128"},
        BadBody{"id: 2 shape { sphere { radius: 64.5 } }", "more than sector_size 128"},
        BadBody{"id: 2 shape { plane { normal { y: 1 } } } mass: 3", "a plane must be static"},
        BadBody{"id: 2 shape { plane { normal { } } }",
                "shape.plane.normal must be a finite non-zero vector"},
        BadBody{"id: 2 mass: 1", "shape is missing"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 position { global { x: nan } }",
                "position.global is not finite"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 position { global { x: 1e300 } }",
                "beyond sector index 2^62"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 position { sector { i: 4611686018427387905 } }",
                "position.sector has an index beyond 2^62"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 position { sector { local { z: -inf } } }",
                "position.sector.local is not finite"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 orientation { w: 0 }",
                "orientation is a zero quaternion"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 orientation { x: nan w: 1 }",
                "orientation is not finite"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 linear_velocity { y: nan }",
                "linear_velocity is not finite"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 angular_velocity { y: inf }",
                "angular_velocity is not finite"},
        // Bullet silently stops simulating a body this fast (1e10) or turns it NaN (spin 1e20).
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 linear_velocity { x: 1e10 }",
                "linear_velocity is too fast: linear speed 1e+10 units/s is above the 6000000 units/s"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 angular_velocity { z: -1e20 }",
                "angular_velocity is too fast: angular speed 1e+20 rad/s is above the 6000 rad/s"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } asleep: true", "asleep applies to dynamic bodies only"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 asleep: true linear_velocity { x: 1 }",
                "asleep is at rest: a body starting asleep cannot have a velocity"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 material { friction: -1 }",
                "material.friction must be >= 0"},
        BadBody{"id: 2 shape { sphere { radius: 1 } } mass: 1 material { restitution: 1.5 }",
                "material.restitution must be <= 1"}));

TEST(Scene, MonolithicScenesMayHoldBodiesLargerThanASector) {
    const char* text = "sector_size: 128 bodies { id: 1 shape { sphere { radius: 100 } } mass: 1 }";
    EXPECT_FALSE(parse_scene(text, "t", true).ok());
    EXPECT_TRUE(parse_scene(text, "t", false).ok());
}

TEST(Scene, ListsEveryProblemFound) {
    std::string e = refusal(
        "sector_size: 128 bodies { id: 1 name: \"a\" shape { sphere { radius: -1 } } mass: -2 }"
        " bodies { id: 1 name: \"b\" shape { sphere { radius: 1 } } }");
    EXPECT_NE(e.find("body 'a' (id 1): shape.sphere.radius"), std::string::npos) << e;
    EXPECT_NE(e.find("body 'a' (id 1): mass"), std::string::npos) << e;
    EXPECT_NE(e.find("body 'b' (id 1): id is used"), std::string::npos) << e;
}

TEST(Scene, LoadReportsAMissingFile) {
    Expected<Scene> s = load_scene("/nonexistent/scene.textproto");
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace lpss

namespace lpss {
namespace {

TEST(Scene, SaysWhereItIsOnTheEarthAndRefusesAPlaceOffIt) {
    const std::string base = "sector_size: 64\n";
    Expected<Scene> ecef = parse_scene(base + "geo { ecef {} }", "ecef");
    ASSERT_TRUE(ecef) << ecef.error().message;
    EXPECT_EQ(ecef->settings.geo.frame, GeoReference::Frame::ecef);
    Expected<Scene> tangent = parse_scene(
        base + "geo { local_tangent { latitude_deg: 51.195 longitude_deg: -1.85 height_m: 130 } }",
        "tangent");
    ASSERT_TRUE(tangent) << tangent.error().message;
    EXPECT_EQ(tangent->settings.geo.frame, GeoReference::Frame::local_tangent);
    EXPECT_EQ(tangent->settings.geo.latitude_deg, 51.195);
    EXPECT_EQ(tangent->settings.geo.longitude_deg, -1.85);
    EXPECT_EQ(tangent->settings.geo.height_m, 130.0);
    // Written and read back, it says the same.
    const Scene again = parse_scene(format_scene(*tangent), "again").value();
    EXPECT_EQ(again.settings.geo.frame, GeoReference::Frame::local_tangent);
    EXPECT_EQ(again.settings.geo.latitude_deg, 51.195);
    EXPECT_EQ(parse_scene(base, "none")->settings.geo.frame, GeoReference::Frame::none);
    Expected<Scene> off = parse_scene(base + "geo { local_tangent { latitude_deg: 91 } }", "off");
    ASSERT_FALSE(off);
    EXPECT_NE(off.error().message.find("latitude_deg in [-90, 90]"), std::string::npos)
        << off.error().message;
    Expected<Scene> nan = parse_scene(base + "geo { local_tangent { longitude_deg: nan } }", "nan");
    ASSERT_FALSE(nan);
    EXPECT_NE(nan.error().message.find("geo.local_tangent"), std::string::npos) << nan.error().message;
}

}  // namespace
}  // namespace lpss
