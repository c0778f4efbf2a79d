// The engine's API and its cost rules: bad input is refused with the world unchanged; sectors come and
// go with their bodies; a scene needing no cloning or stepping gets none; threads change nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine_test_support.hpp"

namespace lpss {
namespace {

using testing::make_world;
using testing::run;

BodyDesc ball(BodyId id, const Eigen::Vector3d& at, double radius = 0.5) {
    BodyDesc b;
    b.id = id;
    b.name = "ball" + std::to_string(id);
    b.shape = Sphere{radius};
    b.mass = 1;
    b.position = at;
    return b;
}

bool same_state(const std::vector<BodySnapshot>& a, const std::vector<BodySnapshot>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t n = 0; n < a.size(); ++n) {
        if (a[n].id != b[n].id || a[n].position.sector != b[n].position.sector ||
            a[n].position.local != b[n].position.local ||
            a[n].orientation.coeffs() != b[n].orientation.coeffs() ||
            a[n].linear_velocity != b[n].linear_velocity || a[n].angular_velocity != b[n].angular_velocity) {
            return false;
        }
    }
    return true;
}

World empty_world(double sector_size = 128.0, const EngineOptions& options = {}) {
    WorldSettings s;
    s.sector_size = sector_size;
    s.gravity = {0, -9.81, 0};
    Expected<World> w = World::create(s, options);
    EXPECT_TRUE(w.ok());
    return std::move(w).value();
}

TEST(World, RefusesBadSettings) {
    WorldSettings s;
    s.sector_size = 1024;
    s.precision_radius = 1000;
    Expected<World> w = World::create(s);
    ASSERT_FALSE(w.ok());
    EXPECT_NE(w.error().message.find("largest sector_size allowed"), std::string::npos);
    s = WorldSettings{};
    s.dt = std::nan("");
    EXPECT_FALSE(World::create(s).ok());
    EngineOptions no_threads;
    no_threads.threads = 0;
    EXPECT_FALSE(World::create(WorldSettings{}, no_threads).ok());
}

TEST(World, BadBodiesAreRefusedAndTheWorldIsUnchanged) {
    World world = empty_world();
    ASSERT_TRUE(world.add_body(ball(1, {0, 5, 0})).ok());
    ASSERT_TRUE(world.add_body(ball(2, {100, 5, 0})).ok());
    run(world, 3);
    const std::vector<BodySnapshot> before = world.snapshot();
    const std::vector<SectorKey> sectors_before = world.sectors();

    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<std::pair<BodyDesc, std::string>> bad;
    bad.push_back({ball(3, {nan, 0, 0}), "position.global is not finite"});
    bad.push_back({ball(3, {0, 0, 0}, 70.0), "more than sector_size 128"});
    bad.push_back({ball(1, {0, 0, 0}), "id is used by another body"});
    BodyDesc heavy_plane;
    heavy_plane.id = 4;
    heavy_plane.shape = Plane{};
    heavy_plane.mass = 1;
    bad.push_back({heavy_plane, "a plane must be static"});
    BodyDesc negative = ball(5, {0, 0, 0});
    negative.mass = -1;
    bad.push_back({negative, "mass must be >= 0"});
    for (const auto& [body, message] : bad) {
        Status st = world.add_body(body);
        ASSERT_FALSE(st.ok()) << message;
        EXPECT_NE(st.error().message.find(message), std::string::npos) << st.error().message;
    }
    // All or nothing: one bad body among good ones adds none of them.
    Status st = world.add_bodies({ball(6, {1, 1, 1}), ball(7, {2, nan, 2}), ball(8, {500, 1, 1})});
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().message.find("body 'ball7' (id 7): position.global is not finite"),
              std::string::npos);
    EXPECT_FALSE(world.add_bodies({ball(6, {1, 1, 1}), ball(6, {3, 1, 1})}).ok())
        << "duplicate within the batch";

    // Commands on unknown bodies or with bad numbers.
    EXPECT_NE(world.remove_body(99).error().message.find("unknown body id 99"), std::string::npos);
    EXPECT_FALSE(world.apply_impulse(99, {1, 0, 0}).ok());
    EXPECT_NE(world.apply_impulse(1, {nan, 0, 0}).error().message.find("must be finite"), std::string::npos);
    EXPECT_NE(world.set_velocity(2, {0, 0, 0}, {0, INFINITY, 0}).error().message.find("must be finite"),
              std::string::npos);
    // Finite but beyond what a step can simulate: refused with the limit, whichever call brings it.
    EXPECT_NE(world.set_velocity(2, {0, 1e25, 0}, {0, 0, 0}).error().message.find("linear speed 1e+25"),
              std::string::npos);
    EXPECT_NE(world.set_velocity(2, {0, 0, 0}, {1e15, 0, 0}).error().message.find("angular speed 1e+15"),
              std::string::npos);
    EXPECT_NE(world.apply_impulse(2, {1e300, 0, 0}).error().message.find("the impulse is too large"),
              std::string::npos);
    EXPECT_NE(world.apply_impulse(2, {0, 1e4, 0}, {100, 0, 0}).error().message.find("angular speed"),
              std::string::npos);
    BodySnapshot too_fast = *world.body(2);
    too_fast.linear_velocity = {7e6, 0, 0};
    EXPECT_NE(world.set_state(too_fast).error().message.find("is above the 6000000 units/s"),
              std::string::npos);

    EXPECT_TRUE(same_state(world.snapshot(), before));
    EXPECT_EQ(world.sectors(), sectors_before);
    EXPECT_EQ(world.body_count(), 2u);
}

TEST(World, BodiesAtTheSpeedLimitAreSimulatedNotDropped) {
    // Just below the limits: Bullet must still move the body (it stops simulating one whose box swept
    // in a step passes 10^6 units) and keep its state finite.
    World world = empty_world();
    ASSERT_TRUE(world.add_body(ball(1, {0, 0, 0})).ok());
    const double v = 0.99 * WorldSettings{}.max_linear_speed();
    const double spin = 0.99 * WorldSettings{}.max_angular_speed();
    ASSERT_TRUE(world.set_velocity(1, {v, 0, 0}, {0, spin, 0}).ok());
    run(world, 3);
    const BodySnapshot after = *world.body(1);
    const SectorGrid grid(WorldSettings{}.sector_size);
    const double travelled = grid.to_global(after.position).x();
    EXPECT_NEAR(travelled, 3 * v / 60.0, 1.0) << "it moved three frames at its speed";
    EXPECT_TRUE(after.awake);
    EXPECT_TRUE(after.angular_velocity.allFinite());
    EXPECT_TRUE(after.orientation.coeffs().allFinite());
    const Status consistent = world.check_consistency();
    EXPECT_TRUE(consistent.ok()) << consistent.error().message;
}

TEST(World, SectorsAreCreatedOnFirstUseAndDestroyedWhenEmpty) {
    World world = empty_world();
    EXPECT_TRUE(world.sectors().empty());
    ASSERT_TRUE(world.add_body(ball(1, {0, 0, 0})).ok());
    ASSERT_TRUE(world.add_body(ball(2, {1000, -300, 5e9})).ok());
    std::vector<SectorKey> sectors = world.sectors();
    ASSERT_EQ(sectors.size(), 2u);
    EXPECT_EQ(sectors[0], (SectorKey{0, 0, 0}));
    ASSERT_TRUE(world.remove_body(1).ok());
    EXPECT_EQ(world.sectors().size(), 1u);
    // A body flying across sectors leaves no empty sector behind.
    ASSERT_TRUE(world.set_velocity(2, {600, 0, 0}, {0, 0, 0}).ok());
    run(world, 60);
    EXPECT_EQ(world.sectors().size(), 1u);
    EXPECT_EQ(world.sectors()[0], world.body(2)->position.sector);
    EXPECT_GE(world.body(2)->position.sector.i - 8, 3) << "it crossed several sectors";
}

TEST(World, AFastBodyCrossesSeveralSectorsInOneFrame) {
    WorldSettings s;
    s.sector_size = 16;
    World world = World::create(s).value();
    BodyDesc b = ball(1, {0, 0, 0});
    b.linear_velocity = {3000, 0, -1500};  // 50 and 25 units per frame: 3 and 1.5 sectors
    ASSERT_TRUE(world.add_body(b).ok());
    run(world, 10);
    BodySnapshot after = *world.body(1);
    Eigen::Vector3d global = world.grid().to_global(after.position);
    EXPECT_NEAR(global.x(), 500.0, 1e-3);
    EXPECT_NEAR(global.z(), -250.0, 1e-3);
    EXPECT_LE(after.position.local.cwiseAbs().maxCoeff(), 8.0 + 1.0 + 50.0);
    EXPECT_EQ(world.sectors().size(), 1u);
}

TEST(World, NoBordersNoCloningWork) {
    World world = empty_world();
    for (int n = 0; n < 20; ++n)
        ASSERT_TRUE(world.add_body(ball(n + 1, {n * 384.0 + 7, 0, -n * 640.0 - 3})).ok());
    run(world, 30);
    EXPECT_EQ(world.last_frame_stats().border_bodies, 0u);
    EXPECT_EQ(world.last_frame_stats().clones, 0u);
    EXPECT_EQ(world.last_frame_stats().stepped_sectors, 20u);
}

TEST(World, EverythingAsleepNothingStepped) {
    Scene scene = scenes::box_stack(Eigen::Vector3d(5e8, 0, 0), 3, 128.0);
    World world = make_world(scene);
    int frames = 0;
    while (world.last_frame_stats().stepped_sectors != 0 || frames == 0) {
        world.step();
        ASSERT_LT(++frames, 1200) << "the stack never fell asleep";
    }
    Eigen::Vector3d top = scenes::relative_position(world.grid(), *world.body(3), Eigen::Vector3d(5e8, 0, 0));
    EXPECT_NEAR(top.y(), 2.5, 0.05);
    run(world, 10);
    EXPECT_EQ(world.last_frame_stats().stepped_sectors, 0u);
    EXPECT_FALSE(world.body(3)->awake);
    // An impulse wakes the stack's sector again.
    ASSERT_TRUE(world.apply_impulse(3, {0, 3, 0}).ok());
    world.step();
    EXPECT_EQ(world.last_frame_stats().stepped_sectors, 1u);
    EXPECT_GT(world.body(3)->linear_velocity.y(), 1.0);
}

TEST(World, BodiesStartingAsleepCostNothingUntilSomethingHitsThem) {
    // A row of boxes resting on a plane, loaded asleep: nothing is stepped, nothing moves. A ball rolled
    // into the first wakes it and only the sector it is in; the far sector's boxes stay asleep.
    Scene scene;
    scene.settings.sector_size = 32;
    scene.settings.gravity = {0, -9.81, 0};
    scene.bodies.push_back(scenes::ground_plane(1, Eigen::Vector3d::Zero().eval()));
    for (int n = 0; n < 4; ++n) {
        BodyDesc box = scenes::box_body(10 + n, Eigen::Vector3d::Constant(0.5), 1.0,
                                        Eigen::Vector3d(n < 2 ? 3.0 * n : 64.0 + 3.0 * n, 0.5, 0));
        box.asleep = true;
        scene.bodies.push_back(box);
    }
    World world = make_world(scene);
    run(world, 30);
    EXPECT_EQ(world.last_frame_stats().stepped_sectors, 0u);
    for (BodyId id : {10, 11, 12, 13}) {
        EXPECT_FALSE(world.body(id)->awake) << id;
        EXPECT_EQ(world.body(id)->position.local.y(), 0.5) << "an asleep body does not settle: " << id;
    }
    BodyDesc ball = scenes::sphere_body(2, 0.5, 5.0, Eigen::Vector3d(-4, 0.5, 0));
    ball.linear_velocity = {8, 0, 0};
    ASSERT_TRUE(world.add_body(ball).ok());
    run(world, 60);
    EXPECT_GT(scenes::relative_position(world.grid(), *world.body(10), Eigen::Vector3d::Zero().eval()).x(),
              0.1)
        << "the ball pushed the first box";
    EXPECT_FALSE(world.body(12)->awake);
    EXPECT_EQ(world.body(12)->position.local, world.body(13)->position.local - Eigen::Vector3d(3, 0, 0));
}

TEST(World, ChangedSectorsNameExactlyWhereSomethingHappened) {
    // Three balls asleep in three sectors, no gravity; one is set rolling across a border.
    WorldSettings settings;
    settings.sector_size = 16;
    World world = World::create(settings).value();
    for (int n = 0; n < 3; ++n) {
        BodyDesc b = ball(n + 1, Eigen::Vector3d(32.0 * n, 0, 0));
        b.asleep = true;
        ASSERT_TRUE(world.add_body(b).ok());
    }
    world.step();
    EXPECT_EQ(world.changed_sectors(), (std::vector<SectorKey>{{0, 0, 0}, {2, 0, 0}, {4, 0, 0}}))
        << "added bodies are news";
    world.step();
    EXPECT_TRUE(world.changed_sectors().empty()) << "nothing moves, nothing changed";
    ASSERT_TRUE(world.set_velocity(1, {60, 0, 0}, {0, 0, 0}).ok());
    world.step();
    EXPECT_EQ(world.changed_sectors(), (std::vector<SectorKey>{{0, 0, 0}}));
    int frames = 0;
    while (world.body(1)->position.sector == SectorKey{0, 0, 0}) {
        world.step();
        ASSERT_LT(++frames, 60);
    }
    EXPECT_EQ(world.changed_sectors(), (std::vector<SectorKey>{{0, 0, 0}, {1, 0, 0}})) << "left and entered";
    ASSERT_TRUE(world.remove_body(3).ok());
    world.step();
    EXPECT_EQ(world.changed_sectors(), (std::vector<SectorKey>{{1, 0, 0}, {4, 0, 0}}))
        << "the moving ball's sector, and the one a body was removed from (now gone)";
}

TEST(World, DeparturesListBodiesPastABorderIntoSectorsNotOwned) {
    WorldSettings settings;
    settings.sector_size = 16;
    EngineOptions options;
    options.owns = [](const SectorKey& key) { return key.i <= 0; };
    World world = World::create(settings, options).value();
    ASSERT_TRUE(world.add_body(ball(1, Eigen::Vector3d(0, 0, 0))).ok());
    ASSERT_TRUE(world.add_body(ball(2, Eigen::Vector3d(-16, 0, 0))).ok());
    ASSERT_TRUE(world.set_velocity(1, {60, 0, 0}, {0, 0, 0}).ok());
    int frames = 0;
    while (world.departures().empty()) {
        world.step();
        ASSERT_LT(++frames, 60);
    }
    const std::vector<Departure> out = world.departures();
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].id, 1u);
    EXPECT_EQ(out[0].to.sector, (SectorKey{1, 0, 0}));
    EXPECT_EQ(world.body(1)->position.sector, (SectorKey{0, 0, 0})) << "kept until handed off";
    // Handed off: the body's new owner has it; here it is a ghost in the sector it entered.
    BodySnapshot state = *world.body(1);
    state.position = out[0].to;
    ASSERT_TRUE(world.set_state(state).ok());
    world.step();
    EXPECT_TRUE(world.departures().empty());
    EXPECT_TRUE(world.is_ghost(1));
}

TEST(World, RemovingABodyEndsItsContactsAndFreesItsSector) {
    Scene scene = scenes::box_stack(Eigen::Vector3d::Zero().eval(), 2, 128.0);
    World world = make_world(scene);
    run(world, 30);
    ASSERT_TRUE(world.remove_body(2).ok());
    world.step();
    bool ended = false;
    for (const ContactEvent& e : world.contact_events()) {
        if (e.kind == ContactEvent::Kind::End && e.a == 1 && e.b == 2) ended = true;
    }
    EXPECT_TRUE(ended);
    EXPECT_FALSE(world.contains(2));
    EXPECT_EQ(world.body_count(), 2u);
    // A body alone in its sector: removed, its sector goes too (the stack's sector stays).
    const SectorKey lone{3, 0, 0};
    ASSERT_TRUE(
        world.add_body(scenes::sphere_body(99, 0.5, 1.0, Eigen::Vector3d(3 * 128.0 + 10, 0, 0))).ok());
    world.step();
    ASSERT_TRUE(world.has_sector(lone));
    ASSERT_TRUE(world.remove_body(99).ok());
    world.step();
    EXPECT_FALSE(world.has_sector(lone)) << "the emptied sector is freed";
    EXPECT_TRUE(world.has_sector(SectorKey{0, 0, 0})) << "the stack's sector holds box 1";
    EXPECT_TRUE(world.check_consistency().ok());
}

TEST(World, ThreadsDoNotChangeTheResult) {
    // A pile straddling eight sectors, stepped on one and on two threads: identical, bit for bit.
    Scene scene;
    scene.settings.sector_size = 16;
    scene.settings.gravity = {0, -9.81, 0};
    BodyDesc ground;
    ground.id = 1000;
    ground.shape = Plane{};
    ground.position = Eigen::Vector3d(0, -4, 0);
    scene.bodies.push_back(ground);
    BodyId id = 1;
    for (int i = 0; i < 6; ++i) {
        for (int j = 0; j < 4; ++j) {
            for (int k = 0; k < 6; ++k) {
                BodyDesc b =
                    ball(id++, {8.0 - 3.0 + i * 1.1, -3.0 + j * 1.1, 8.0 - 3.0 + k * 1.1 + 0.05 * j});
                if (id % 3 == 0) b.shape = Box{{0.4, 0.4, 0.4}};
                scene.bodies.push_back(b);
            }
        }
    }
    EngineOptions one, two;
    two.threads = 2;
    World a = make_world(scene, one);
    World b = make_world(scene, two);
    std::size_t max_stepped = 0;
    for (int f = 0; f < 240; ++f) {
        a.step();
        b.step();
        max_stepped = std::max(max_stepped, b.last_frame_stats().stepped_sectors);
    }
    EXPECT_GE(max_stepped, 4u);
    EXPECT_TRUE(same_state(a.snapshot(), b.snapshot()));
}

TEST(World, SmallSectorsSteppedTogetherGiveWhatEachSteppedAloneGives) {
    // Balls and boxes rolling and colliding on a ground plane over a grid of small sectors, one to three
    // bodies in each, many crossing borders: stepped with small sectors grouped for the solver (the
    // default), and each sector alone. Identical, bit for bit, in every compared frame, on one thread
    // and on two.
    Scene scene;
    scene.settings.sector_size = 8;
    scene.settings.gravity = {0, -9.81, 0};
    BodyDesc ground;
    ground.id = 10000;
    ground.shape = Plane{};
    ground.position = Eigen::Vector3d(0, -0.5, 0);
    scene.bodies.push_back(ground);
    BodyId id = 1;
    for (int i = 0; i < 12; ++i) {
        for (int k = 0; k < 12; ++k) {
            const int count = 1 + (i * 7 + k * 3) % 3;
            for (int n = 0; n < count; ++n) {
                BodyDesc b = ball(id, {i * 8.0 + 1.5 + n * 2.2, 0.05 + 0.3 * n, k * 8.0 + 2.0 + n * 1.7});
                if (id % 4 == 0) b.shape = Box{{0.4, 0.4, 0.4}};
                // Neighbours roll at each other across the border between their sectors.
                b.linear_velocity = {(i % 2 == 0 ? 3.0 : -3.0) + 0.1 * n, 0.0, (k % 2 == 0 ? 1.5 : -1.5)};
                scene.bodies.push_back(b);
                ++id;
            }
        }
    }
    EngineOptions alone;
    alone.group_small_sectors = false;
    EngineOptions grouped_two;
    grouped_two.threads = 2;
    World grouped = make_world(scene);
    World separate = make_world(scene, alone);
    World grouped_on_two = make_world(scene, grouped_two);
    std::size_t max_grouped = 0, crossings = 0;
    for (int f = 1; f <= 240; ++f) {
        grouped.step();
        separate.step();
        grouped_on_two.step();
        max_grouped = std::max(max_grouped, grouped.last_frame_stats().grouped_sectors);
        crossings += grouped.last_frame_stats().sector_changes;
        ASSERT_EQ(separate.last_frame_stats().grouped_sectors, 0u);
        if (f % 20 == 0) {
            ASSERT_TRUE(same_state(grouped.snapshot(), separate.snapshot())) << "frame " << f;
            ASSERT_TRUE(same_state(grouped_on_two.snapshot(), separate.snapshot())) << "frame " << f;
        }
    }
    EXPECT_GE(max_grouped, 100u) << "most sectors were stepped in groups";
    EXPECT_GE(crossings, 100u) << "bodies crossed borders";
    EXPECT_TRUE(grouped.check_consistency().ok());
}

TEST(World, PlanesAreInEverySectorNearThem) {
    // Balls dropped onto one ground plane in sectors far apart along x all land on it.
    WorldSettings s;
    s.sector_size = 64;
    s.gravity = {0, -9.81, 0};
    World world = World::create(s).value();
    BodyDesc ground;
    ground.id = 100;
    ground.shape = Plane{{0, 1, 0}, -2.0};
    ASSERT_TRUE(world.add_body(ground).ok());
    for (int n = 0; n < 5; ++n)
        ASSERT_TRUE(world.add_body(ball(n + 1, {n * 1e7 - 3e7, 3.0, n * 77.0})).ok());
    run(world, 180);
    for (int n = 0; n < 5; ++n) {
        double y = world.grid().to_global(world.body(n + 1)->position).y();
        EXPECT_NEAR(y, -1.5, 0.02) << "ball " << n + 1;
    }
}

}  // namespace
}  // namespace lpss
