// Collisions across sector borders and corners match the same collisions inside one sector; clones
// come and go with the bodies' reach, from bounded pools.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "engine_test_support.hpp"

namespace lpss {
namespace {

using testing::make_world;
using testing::relative_positions;
using testing::run;
using testing::summed_error;

constexpr double kL = 128.0;

// Runs a scene made by `make` at `centre` and at the origin (inside sector 0) and returns the summed
// error between the two runs' positions relative to their centres.
template <class Make>
double error_against_origin(Make make, const scenes::Centre& centre, int frames,
                            std::size_t* max_clones = nullptr) {
    World reference = make_world(make(scenes::Centre(Eigen::Vector3d::Zero().eval())));
    World moved = make_world(make(centre));
    std::size_t clones = 0;
    for (int f = 0; f < frames; ++f) {
        reference.step();
        moved.step();
        clones = std::max(clones, moved.last_frame_stats().clones);
        EXPECT_EQ(reference.last_frame_stats().clones, 0u) << "the reference must not touch a border";
    }
    if (max_clones) *max_clones = clones;
    return summed_error(relative_positions(moved, centre),
                        relative_positions(reference, Eigen::Vector3d::Zero().eval()));
}

TEST(Borders, CollisionOnAFaceMatchesTheOneInsideASector) {
    for (int axis = 0; axis < 3; ++axis) {
        Eigen::Vector3d dir = Eigen::Vector3d::Unit(axis);
        Eigen::Vector3d border = 0.5 * kL * dir;  // the spheres meet exactly on the face x_axis = L/2
        std::size_t clones = 0;
        double error = error_against_origin(
            [&](const scenes::Centre& c) { return scenes::sphere_pair(c, kL, dir); }, border, 180, &clones);
        EXPECT_LE(error, 2e-3) << "axis " << axis;
        EXPECT_GE(clones, 2u) << "the collision must have been simulated through clones";
    }
}

TEST(Borders, CollisionOnAFaceFarFromTheOriginMatches) {
    // The same face crossing at sector indices near 2^60.
    const std::int64_t far = (std::int64_t{1} << 60) + 11;
    SectorPosition border{{far, 3, -far}, {0.5 * kL, 0, 0}};
    double error = error_against_origin([&](const scenes::Centre& c) { return scenes::sphere_pair(c, kL); },
                                        border, 180);
    EXPECT_LE(error, 2e-3);
}

TEST(Borders, MomentumAndSpeedsAcrossABorderMatchOneSector) {
    World inside = make_world(scenes::sphere_pair(Eigen::Vector3d::Zero().eval(), kL));
    World across = make_world(scenes::sphere_pair(Eigen::Vector3d(0.5 * kL, 0, 0), kL));
    run(inside, 180);
    run(across, 180);
    for (BodyId id : {BodyId{1}, BodyId{2}}) {
        EXPECT_NEAR(across.body(id)->linear_velocity.x(), inside.body(id)->linear_velocity.x(), 1e-4);
    }
    Eigen::Vector3d momentum = across.body(1)->linear_velocity + across.body(2)->linear_velocity;
    EXPECT_LE(momentum.norm(), 1e-5);
    // After the bounce the spheres live in two different sectors.
    EXPECT_NE(across.body(1)->position.sector, across.body(2)->position.sector);
}

TEST(Borders, DiagonalCollisionThroughACornerOfEightSectors) {
    Eigen::Vector3d corner = Eigen::Vector3d::Constant(0.5 * kL);
    Eigen::Vector3d diagonal = Eigen::Vector3d::Ones().normalized();
    double error = error_against_origin(
        [&](const scenes::Centre& c) { return scenes::sphere_pair(c, kL, diagonal); }, corner, 180);
    EXPECT_LE(error, 2e-3);
}

TEST(Borders, EightSpheresMeetingAtACornerOfEightSectors) {
    Eigen::Vector3d corner = Eigen::Vector3d::Constant(0.5 * kL);
    std::size_t clones = 0;
    double error = error_against_origin([&](const scenes::Centre& c) { return scenes::sphere_octet(c, kL); },
                                        corner, 120, &clones);
    EXPECT_LE(error, 8 * 2e-3);
    EXPECT_GE(clones, 8u * 3u) << "each sphere meets three neighbours in three other sectors";
}

TEST(Borders, ContactEventsCarryTheOriginalIds) {
    World world = make_world(scenes::sphere_pair(Eigen::Vector3d(0.5 * kL, 0, 0), kL));
    int begun = 0, ended = 0;
    for (int f = 0; f < 180; ++f) {
        world.step();
        for (const ContactEvent& e : world.contact_events()) {
            EXPECT_EQ(e.a, 1u);
            EXPECT_EQ(e.b, 2u);
            if (e.kind == ContactEvent::Kind::Begin) {
                ++begun;
                Eigen::Vector3d point = world.grid().to_global(e.point);
                EXPECT_NEAR(point.x(), 0.5 * kL, 0.1) << "where the spheres meet, on the border";
                EXPECT_NEAR(e.normal.x(), -1.0, 1e-3) << "from b (right) to a (left)";
                EXPECT_GT(e.impulse, 0.0);
            } else {
                ++ended;
            }
        }
    }
    EXPECT_EQ(begun, 1) << "seen by both sectors, reported once";
    EXPECT_EQ(ended, 1);
}

// Two spheres side by side across the border x = L/2, 1.05 apart in y: within reach, not touching.
Scene two_spheres_within_reach_across_a_border() {
    Scene scene;
    scene.settings.sector_size = kL;
    for (int n = 0; n < 2; ++n) {
        BodyDesc b;
        b.id = static_cast<BodyId>(n + 1);
        b.shape = Sphere{0.5};
        b.mass = 1;
        b.position = Eigen::Vector3d(0.5 * kL + (n ? 0.3 : -0.3), n * 1.05, 0);
        scene.bodies.push_back(b);
    }
    return scene;
}

TEST(Clones, ABodyLeavingTheBorderBandLosesItsClones) {
    World world = make_world(two_spheres_within_reach_across_a_border());
    world.step();
    EXPECT_EQ(world.clone_counts(1)->active, 1u);
    EXPECT_EQ(world.clone_counts(2)->active, 1u);
    // Body 1 leaves towards -x; body 2 stays (awake, at rest). 45 frames: body 1's fat box, stretched
    // 10 units ahead of it, is refreshed once it has gone through (about 32 frames), away from the border.
    ASSERT_TRUE(world.set_velocity(1, {-20, 0, 0}, {0, 0, 0}).ok());
    run(world, 45);
    EXPECT_EQ(world.clone_counts(1)->active, 0u);
    EXPECT_EQ(world.clone_counts(2)->active, 0u);
    EXPECT_EQ(world.clone_counts(1)->spare, 1u) << "the clone went back to the pool";
    EXPECT_EQ(world.last_frame_stats().clones, 0u);
    EXPECT_EQ(world.last_frame_stats().border_bodies, 1u) << "body 2 still reaches across, alone";
}

TEST(Clones, FrameStatsCountTheClonesMadeAndLetGoAndTheFatBoxesRefreshed) {
    World world = make_world(two_spheres_within_reach_across_a_border());
    world.step();
    EXPECT_EQ(world.last_frame_stats().fat_box_refreshes, 2u) << "each body's first fat box";
    EXPECT_EQ(world.last_frame_stats().clones_made, 2u) << "each body into the other's sector";
    EXPECT_EQ(world.last_frame_stats().clones_released, 0u);
    // Resting where they are: nothing made, let go or refreshed.
    world.step();
    EXPECT_EQ(world.last_frame_stats().fat_box_refreshes, 0u);
    EXPECT_EQ(world.last_frame_stats().clones_made, 0u);
    // Body 1 leaves: its fat box is refreshed once it has gone through it, and both clones go a few frames
    // after their reaches part (kCloneLinger), each once.
    ASSERT_TRUE(world.set_velocity(1, {-20, 0, 0}, {0, 0, 0}).ok());
    std::size_t refreshed = 0, made = 0, released = 0;
    for (int f = 0; f < 45; ++f) {
        world.step();
        refreshed += world.last_frame_stats().fat_box_refreshes;
        made += world.last_frame_stats().clones_made;
        released += world.last_frame_stats().clones_released;
    }
    EXPECT_GE(refreshed, 1u);
    EXPECT_LE(refreshed, 3u) << "a fat box stretched ahead lasts most of the way";
    EXPECT_EQ(made, 0u);
    EXPECT_EQ(released, 2u);
    EXPECT_EQ(world.last_frame_stats().clones, 0u);
}

TEST(Clones, ABodyWokenNextToASectorJustFallenAsleepHasThatSectorStepped) {
    // Two boxes at rest either side of the border x = L/2, 0.04 apart (their reaches meet), fall asleep
    // together; the one on the right (the lower slot, from whose side the cloning stage checks a pair of
    // two awake sectors) is then pushed towards the other. The sector on the left must be stepped from
    // that frame on, so that its box is pushed: what was found of the pair while both sectors were awake,
    // frames before, must not decide it. (A pair check skipped for a few frames after the pair was found
    // meeting was tried on 2026-12-05 and failed this test until it asked whether the other sector was
    // still awake; dropped, as it made cloning slower.)
    Scene scene;
    scene.settings.sector_size = kL;
    scene.bodies.push_back(
        scenes::box_body(1, Eigen::Vector3d::Constant(0.5), 1.0, Eigen::Vector3d(0.5 * kL + 0.52, 0, 0)));
    scene.bodies.push_back(
        scenes::box_body(2, Eigen::Vector3d::Constant(0.5), 1.0, Eigen::Vector3d(0.5 * kL - 0.52, 0, 0)));
    World world = make_world(scene);
    const SectorKey left = world.body(2)->position.sector;
    ASSERT_NE(left, world.body(1)->position.sector);
    auto stepped = [&](const SectorKey& key) {
        const std::vector<SectorKey> keys = world.stepped_sectors();
        return std::find(keys.begin(), keys.end(), key) != keys.end();
    };
    int frames = 0;
    do {
        world.step();
    } while (stepped(left) && ++frames < 600);
    ASSERT_LT(frames, 600) << "the boxes never fell asleep";
    ASSERT_TRUE(world.set_velocity(1, {-1, 0, 0}, {0, 0, 0}).ok());
    // Every frame of the push, not only the first.
    for (int f = 0; f < 6; ++f) {
        world.step();
        EXPECT_TRUE(stepped(left)) << f << " frames after the push";
    }
    EXPECT_LT(world.body(2)->linear_velocity.x(), -0.1) << "the box on the left was pushed";
}

TEST(Clones, PoolsStayBoundedOver10000FramesOfOscillation) {
    // Two spheres bounce between static walls on either side of the border x = L/2, on parallel tracks
    // 1.05 apart, at different speeds: they cross the border over and over, cloned into each other's
    // sector whenever they are on different sides, and the walls are cloned to meet them.
    Scene scene;
    scene.settings.sector_size = kL;
    scene.settings.sleeping = false;
    const double border = 0.5 * kL;
    for (int n = 0; n < 2; ++n) {
        BodyDesc wall;
        wall.id = static_cast<BodyId>(10 + n);
        wall.shape = Box{{0.5, 4, 4}};
        wall.position = Eigen::Vector3d(border + (n ? 14.0 : -14.0), 0, 0);
        wall.material = Material{0, 1};
        scene.bodies.push_back(wall);
        BodyDesc ball;
        ball.id = static_cast<BodyId>(1 + n);
        ball.shape = Sphere{0.5};
        ball.mass = 1;
        ball.position = Eigen::Vector3d(border - 5 + 3 * n, n * 1.05, 0);
        ball.linear_velocity = Eigen::Vector3d(n ? 9.0 : 13.0, 0, 0);
        ball.material = Material{0, 1};
        scene.bodies.push_back(ball);
    }
    World world = make_world(scene);
    std::size_t changes = 0, max_clones = 0, max_spare = 0;
    for (int f = 0; f < 10000; ++f) {
        world.step();
        const FrameStats& s = world.last_frame_stats();
        changes += s.sector_changes;
        max_clones = std::max(max_clones, s.clones);
        max_spare = std::max(max_spare, s.spare_clones);
        for (BodyId id : {1, 2, 10, 11}) {
            CloneCounts c = *world.clone_counts(id);
            ASSERT_LE(c.active, 3u) << "frame " << f << " body " << id;
            ASSERT_LE(c.spare, world.options().max_spare_clones);
        }
    }
    // Round trips of 52 units at 13 and 9 units/s over 166 s, two sector changes each: about 140.
    EXPECT_GT(changes, 100u) << "the spheres must really have crossed the border many times";
    EXPECT_GE(max_clones, 2u);
    EXPECT_LE(max_clones, 8u);
    EXPECT_LE(max_spare, 4u * world.options().max_spare_clones);
    // They still bounce between the walls: nothing lost, nothing tunnelled.
    for (BodyId id : {1, 2}) {
        double x = world.grid().to_global(world.body(id)->position).x();
        EXPECT_GT(x, border - 14.0);
        EXPECT_LT(x, border + 14.0);
        EXPECT_GT(world.body(id)->linear_velocity.norm(), id == 1 ? 10.0 : 7.0) << "still bouncing";
    }
}

TEST(Borders, BodiesDriftingWithinTheirSlackCostNothingSerially) {
    // 200 balls drifting slowly in the middle of one sector, one fast ball among them. The slow ones
    // stay inside their fat reach boxes (slack 0.1 at 0.05 units/s: 120 frames) and their sector's
    // hysteresis band: after the first frame the serial stages look at the fast one only, though every
    // ball moves every frame.
    Scene scene;
    scene.settings.sector_size = 64.0;
    scene.settings.gravity = Eigen::Vector3d::Zero();
    scene.settings.sleeping = false;
    for (int n = 0; n < 200; ++n) {
        const Eigen::Vector3d at(2.0 * (n % 10) - 9.0, 2.0 * (n / 10 % 10) - 9.0, 2.0 * (n / 100) - 1.0);
        BodyDesc ball = scenes::sphere_body(static_cast<BodyId>(n + 1), 0.3, 1.0, at);
        ball.linear_velocity = Eigen::Vector3d(0.05, -0.03, 0.02);
        scene.bodies.push_back(ball);
    }
    // Above the others: it meets nothing.
    BodyDesc fast = scenes::sphere_body(1000, 0.3, 1.0, Eigen::Vector3d(-10.0, 0.0, 10.0));
    fast.linear_velocity = Eigen::Vector3d(6.0, 0.0, 0.0);
    scene.bodies.push_back(fast);
    World world = make_world(scene);
    const Eigen::Vector3d first = world.body(1)->position.local;
    world.step();
    std::size_t fast_frames = 0;
    for (int f = 2; f <= 90; ++f) {
        world.step();
        const FrameStats& s = world.last_frame_stats();
        ASSERT_LE(s.visited_bodies, 1u) << "frame " << f;
        fast_frames += s.visited_bodies == 1;
    }
    // Going straight, it leaves its fat box (3 units ahead, kFatLookaheadFrames, and a slack of 0.2) every
    // 32 frames: in frames 2-90, two or three times (with no stretch it was every frame or two).
    EXPECT_GE(fast_frames, 2u) << "the fast ball leaves its fat box";
    EXPECT_LE(fast_frames, 3u) << "the fast ball's fat box is stretched along its way";
    // A slow ball moved all along (about 0.075 units in 90 frames), unvisited.
    EXPECT_NEAR((world.body(1)->position.local - first).x(), 0.05 * 90 / 60.0, 1e-3);
    EXPECT_EQ(world.last_frame_stats().sector_changes, 0u);
}

TEST(Borders, ABodyFallenAsleepKeepsNoFatBoxOfItsMotion) {
    // A ball 0.6 from its sector's border moving away from it at 30 units/s: its fat box has the slack of
    // that speed (an eighth of the sector) and reaches into the next cell. Stopped where it is, it stays
    // inside that box; once asleep it is given a box as tight as a resting body's, which keeps to its own
    // cell (a box kept from its motion would have kept it a border body, with partners and a wider query
    // growth for its sector, for as long as it slept).
    Scene scene;
    scene.settings.sector_size = 8.0;
    scene.settings.gravity = Eigen::Vector3d::Zero();
    scene.settings.sleeping = true;
    BodyDesc ball = scenes::sphere_body(1, 0.3, 1.0, Eigen::Vector3d(3.4, 0.0, 0.0));
    ball.linear_velocity = Eigen::Vector3d(-30.0, 0.0, 0.0);
    scene.bodies.push_back(ball);
    World world = make_world(scene);
    world.step();
    ASSERT_EQ(world.last_frame_stats().border_bodies, 1u) << "a fast body's box reaches 0.6 and more";
    BodySnapshot stopped = *world.body(1);
    stopped.position.local = Eigen::Vector3d(3.4, 0.0, 0.0);
    stopped.linear_velocity = Eigen::Vector3d::Zero();
    ASSERT_TRUE(world.set_state(stopped));
    int asleep_at = 0;
    for (int f = 2; f <= 400 && asleep_at == 0; ++f) {
        world.step();
        if (!world.body(1)->awake) {
            asleep_at = f;
        } else {
            ASSERT_EQ(world.last_frame_stats().border_bodies, 1u) << "frame " << f << ": awake in its box";
        }
    }
    ASSERT_GT(asleep_at, 0) << "the stopped ball must fall asleep";
    world.step();  // its new box is made in the frame after the step that put it to sleep
    EXPECT_EQ(world.last_frame_stats().border_bodies, 0u) << "asleep at frame " << asleep_at;
    EXPECT_FALSE(world.body(1)->awake);
    EXPECT_NEAR(world.body(1)->position.local.x(), 3.4, 1e-6);
}

TEST(Borders, AFastBodyGoneLeavesItsSectorsQueriesAsTheyWere) {
    // Two drifting lattices of 729 bodies in sectors of 8 (about half near a border); in one, a fast ball
    // flies under the bodies through two of their sectors (60 units/s: a fat box stretched and widened to
    // the most kFatLookaheadFrames and the slack allow, some 3 units beyond its broadphase box) and on into
    // empty sectors, touching none. A sector's bodies are found by fat box through its broadphase, grown by
    // how far its bodies' fat boxes overhang their boxes; that growth once only rose, and the queries there
    // found several times as many candidates long after the ball had gone. They must come back to those of
    // the world without it.
    const Scene scene = scenes::drifting_lattice(729, 8.0, 99);
    World without = make_world(scene);
    World with = make_world(scene);
    // Below the lattice, in the sectors of its lowest bodies (y in [-4, 4)), 2 units under their fat boxes.
    BodyDesc fast = scenes::sphere_body(5000, 0.3, 1.0, Eigen::Vector3d(-3.0, -3.5, 4.8));
    fast.linear_velocity = Eigen::Vector3d(60.0, 0.0, 0.0);
    run(without, 2);
    run(with, 2);
    ASSERT_TRUE(with.add_body(fast));
    std::uint64_t found_with = 0, found_without = 0;
    for (int f = 3; f <= 90; ++f) {
        without.step();
        with.step();
        ASSERT_EQ(with.last_frame_stats().clones, without.last_frame_stats().clones)
            << "frame " << f << ": the fast ball must touch nothing";
        if (f < 30) continue;  // by frame 30 the ball is 24 units on, 2 sectors past the lattice
        found_with += with.last_frame_stats().border_candidates;
        found_without += without.last_frame_stats().border_candidates;
    }
    ASSERT_GT(with.body(5000)->position.sector.i, 3) << "the fast ball must have left the lattice's sectors";
    ASSERT_GT(found_without, 1000u) << "the lattice's bodies must keep leaving their fat boxes";
    const double ratio = static_cast<double>(found_with) / static_cast<double>(found_without);
    EXPECT_GT(ratio, 0.8) << found_with << " against " << found_without;
    EXPECT_LT(ratio, 1.25) << found_with << " against " << found_without;
}

}  // namespace
}  // namespace lpss
