// Accuracy: the engine against analytic truth, not against Bullet's own output. Each case runs at the
// origin and 10^12 units out (a sector position, so that the input itself is exact), with two-sided limits:
// no energy gained, none lost beyond what the case allows, and the far run as the origin's.
// Figures at dt = 1/60 s, defaults (one step a frame, 10 solver iterations), Bullet's product rule for
// friction and restitution unless a case says otherwise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "engine_test_support.hpp"

namespace lpss {
namespace {

using scenes::Centre;
using testing::make_world;
using Vec = Eigen::Vector3d;

constexpr double kL = 128.0;
constexpr double kDt = 1.0 / 60.0;
constexpr double kG = 9.81;

/// The origin, and 10^12 units out on x (with other axes far too), off any sector multiple.
std::vector<std::pair<const char*, Centre>> placements() {
    return {{"origin", Vec::Zero().eval()},
            {"far", SectorPosition{{7'812'500'000, -2'343'750'000, 15'625'000'000}, {3.25, -1.5, 7.75}}}};
}

Scene empty_scene(const Vec& gravity) {
    Scene s;
    s.settings.sector_size = kL;
    s.settings.dt = kDt;
    s.settings.gravity = gravity;
    s.settings.sleeping = false;
    return s;
}

/// Position of `id` relative to `centre`.
Vec at(const World& world, BodyId id, const Centre& centre) {
    return scenes::relative_position(world.grid(), *world.body(id), centre);
}

/// The heights of a ball's apexes over `frames` (frames where its centre is higher than on either side).
std::vector<double> apexes(World& world, BodyId id, const Centre& centre, int frames) {
    std::vector<double> heights, out;
    for (int f = 0; f < frames; ++f) {
        world.step();
        heights.push_back(at(world, id, centre).y());
    }
    for (std::size_t n = 1; n + 1 < heights.size(); ++n) {
        if (heights[n] >= heights[n - 1] && heights[n] > heights[n + 1]) out.push_back(heights[n]);
    }
    return out;
}

Scene ball_on_ground(const Centre& centre, double ball_restitution, double ground_restitution) {
    Scene s = empty_scene(Vec(0, -kG, 0));
    BodyDesc ground = scenes::ground_plane(1, centre);
    ground.material = Material{0, ground_restitution};
    s.bodies.push_back(ground);
    BodyDesc ball = scenes::sphere_body(2, 0.5, 1.0, scenes::shifted(centre, Vec(0, 2.5, 0)));
    ball.material = Material{0, ball_restitution};
    s.bodies.push_back(ball);
    return s;
}

TEST(Accuracy, AnElasticHeadOnCollisionOfEqualMassesSwapsTheirVelocities) {
    // Two spheres of radius 0.5, 4.1 apart, at 2 units/s each, restitution 1, no friction, no gravity:
    // they touch at t = 3.1 / 4 = 0.775 s and leave at 2 units/s each; at 3 s each is 0.5 + 2 (3 - 0.775)
    // = 4.95 from the middle. Discrete collision detection finds the contact up to a step late: each body
    // may be off by one step of its motion. Before lpss turned off Bullet's penetration push on bouncing
    // contacts, they left at 2.2 (21% more kinetic energy) and ended at 5.36.
    std::vector<double> ends;
    for (const auto& [name, centre] : placements()) {
        Scene s = empty_scene(Vec::Zero());
        for (int side : {-1, 1}) {
            BodyDesc b = scenes::sphere_body(side < 0 ? 1 : 2, 0.5, 1.0,
                                             scenes::shifted(centre, Vec(side * 2.05, 0, 0)));
            b.linear_velocity = Vec(-side * 2.0, 0, 0);
            b.material = Material{0, 1};
            s.bodies.push_back(b);
        }
        World world = make_world(s);
        testing::run(world, 180);
        const double energy = 0.5 * (world.body(1)->linear_velocity.squaredNorm() +
                                     world.body(2)->linear_velocity.squaredNorm());
        const double x = at(world, 2, centre).x();
        std::printf("%s: sphere 2 at x = %.4f (analytic 4.95), speed %.5f, kinetic energy %.5f of 4\n", name,
                    x, world.body(2)->linear_velocity.x(), energy);
        EXPECT_NEAR(world.body(2)->linear_velocity.x(), 2.0, 0.005) << name;
        EXPECT_NEAR(world.body(1)->linear_velocity.x(), -2.0, 0.005) << name;
        EXPECT_NEAR(energy, 4.0, 0.01 * 4.0) << name << ": kinetic energy neither gained nor lost";
        EXPECT_NEAR(x, 4.95, 2.0 * kDt + 1e-3) << name;
        EXPECT_NEAR(at(world, 1, centre).x(), -4.95, 2.0 * kDt + 1e-3) << name;
        ends.push_back(x);
    }
    EXPECT_NEAR(ends[1], ends[0], 1e-4) << "far as at the origin";
}

TEST(Accuracy, ABallOfRestitutionOneReturnsToItsDropHeightTenTimes) {
    // Dropped with its centre at 2.5 on a plane, restitution 1 on both, no friction: every apex is 2.5.
    // Limit: 2% of the 2.0 fall either way over the first ten bounces. (Bullet's penetration push made
    // them 2.65, 2.97, ... 3.45.) An apex is read at a frame, at most g dt^2 / 2 = 1.4e-3 below the true one.
    std::vector<std::vector<double>> runs;
    for (const auto& [name, centre] : placements()) {
        World world = make_world(ball_on_ground(centre, 1.0, 1.0));
        const std::vector<double> found = apexes(world, 2, centre, 900);
        ASSERT_GE(found.size(), 10u) << name << ": ten bounces in 15 s";
        for (std::size_t n = 0; n < 10; ++n)
            EXPECT_NEAR(found[n], 2.5, 0.02 * 2.0) << name << ", apex " << n + 1;
        std::printf("%s: apexes %.4f %.4f %.4f ... %.4f (analytic 2.5)\n", name, found[0], found[1], found[2],
                    found[9]);
        runs.push_back(found);
    }
    for (std::size_t n = 0; n < 10; ++n)
        EXPECT_NEAR(runs[1][n], runs[0][n], 1e-4) << "far as at the origin, apex " << n + 1;
}

TEST(Accuracy, ABallOfRestitutionOneHalfLosesWhatRestitutionSays) {
    // Restitution 0.5 on the ball, 1 on the plane: Bullet multiplies them (0.5). Each bounce leaves with
    // half the speed, so a quarter of the height: apexes 0.5 + 2 / 4 = 1.0, then 0.5 + 2 / 16 = 0.625.
    // Limit: the rebound height (above the contact at 0.5) within 10% either way: discrete contact finds
    // the ball up to a step below the surface, at a speed up to g dt higher or lower than at contact.
    std::vector<double> firsts;
    for (const auto& [name, centre] : placements()) {
        World world = make_world(ball_on_ground(centre, 0.5, 1.0));
        const std::vector<double> found = apexes(world, 2, centre, 300);
        ASSERT_GE(found.size(), 2u) << name;
        std::printf("%s: apexes %.4f %.4f (analytic 1.0, 0.625)\n", name, found[0], found[1]);
        EXPECT_NEAR(found[0] - 0.5, 0.5, 0.05) << name;
        EXPECT_NEAR(found[1] - 0.5, 0.125, 0.0125) << name;
        firsts.push_back(found[0]);
    }
    EXPECT_NEAR(firsts[1], firsts[0], 1e-4) << "far as at the origin";
}

TEST(Accuracy, TheScenesRestitutionRuleSetsTheBounce) {
    // Restitution 0.5 on the ball and 1 on the plane, averaged (PhysX's default) instead of multiplied:
    // 0.75, so the first rebound rises 2 x 0.75^2 = 1.125 above the contact, to 1.625. Same limit as above.
    for (const auto& [name, centre] : placements()) {
        Scene s = ball_on_ground(centre, 0.5, 1.0);
        s.settings.restitution_combine = CombineRule::average;
        World world = make_world(s);
        const std::vector<double> found = apexes(world, 2, centre, 300);
        ASSERT_GE(found.size(), 1u) << name;
        std::printf("%s: first apex %.4f (analytic 1.625)\n", name, found[0]);
        EXPECT_NEAR(found[0] - 0.5, 1.125, 0.1125) << name;
    }
}

TEST(Accuracy, ABoxSlidesToRestWhereFrictionSays) {
    // A unit box at 5 units/s on a plane, friction 0.5 on both. It decelerates at mu g: stops after
    // v^2 / (2 mu g) units, at v / (mu g) s. Bullet's product rule makes mu 0.25 (5.097 units, 2.039 s); a
    // scene may ask for the geometric mean, as Jolt does, and mu stays 0.5 (2.548 units, 1.019 s).
    // Limits: 2% of the distance and two frames of the time, either way.
    const double v = 5.0;
    for (const auto& [rule, mu] :
         {std::pair{CombineRule::product, 0.25}, {CombineRule::geometric_mean, 0.5}}) {
        const double distance = v * v / (2 * mu * kG), time = v / (mu * kG);
        std::vector<double> slid;
        for (const auto& [name, centre] : placements()) {
            Scene s = empty_scene(Vec(0, -kG, 0));
            s.settings.friction_combine = rule;
            BodyDesc ground = scenes::ground_plane(1, centre);
            ground.material = Material{0.5, 0};
            s.bodies.push_back(ground);
            BodyDesc box =
                scenes::box_body(2, Vec::Constant(0.5), 1.0, scenes::shifted(centre, Vec(0, 0.5, 0)));
            box.material = Material{0.5, 0};
            box.linear_velocity = Vec(v, 0, 0);
            s.bodies.push_back(box);
            World world = make_world(s);
            int stopped_at = -1;
            for (int f = 1; f <= 240; ++f) {
                world.step();
                // Stopped sliding: the box's contact corners then rock it by millimetres a second a while.
                if (stopped_at < 0 && world.body(2)->linear_velocity.x() < 1e-3) stopped_at = f;
            }
            const double x = at(world, 2, centre).x();
            std::printf("%s, mu %.2f: slid %.4f units (analytic %.4f), stopped at %.3f s (analytic %.3f)\n",
                        name, mu, x, distance, stopped_at * kDt, time);
            EXPECT_NEAR(x, distance, 0.02 * distance) << name << ", mu " << mu;
            ASSERT_GT(stopped_at, 0) << name << ": it must stop within 4 s";
            EXPECT_NEAR(stopped_at * kDt, time, 2 * kDt) << name << ", mu " << mu;
            EXPECT_NEAR(at(world, 2, centre).y(), 0.5, 0.01) << name << ": it slides on the plane, not in it";
            slid.push_back(x);
        }
        EXPECT_NEAR(slid[1], slid[0], 1e-4) << "far as at the origin, mu " << mu;
    }
}

TEST(Accuracy, FreeFallHasTheIntegratorsStatedError) {
    // Bullet integrates with semi-implicit Euler: after n steps from rest the velocity is exact (-g n dt)
    // and the fall is g dt^2 n (n + 1) / 2, the analytic g t^2 / 2 plus g t dt / 2: an O(dt) error of
    // 0.0818 units after 1 s at dt = 1/60. The test holds the engine to that figure, both ways.
    for (const auto& [name, centre] : placements()) {
        Scene s = empty_scene(Vec(0, -kG, 0));
        s.bodies.push_back(scenes::sphere_body(1, 0.5, 1.0, centre));
        World world = make_world(s);
        testing::run(world, 60);
        const double fall = -at(world, 1, centre).y();
        const double analytic = 0.5 * kG, stated = 0.5 * kG * kDt;
        std::printf("%s: fell %.5f in 1 s (analytic %.5f, integrator's error %.5f)\n", name, fall, analytic,
                    fall - analytic);
        EXPECT_NEAR(fall - analytic, stated, 1e-4) << name;
        EXPECT_NEAR(world.body(1)->linear_velocity.y(), -kG, 1e-4) << name;
    }
}

TEST(Accuracy, AStackAtRestCreatesNoEnergy) {
    // Five unit boxes stacked on a plane, 10 s: contact resolution must not pump energy in. The potential
    // energy may only fall by the boxes settling into their contacts (millimetres), never rise, and
    // the boxes stay still.
    for (const auto& [name, centre] : placements()) {
        Scene s = scenes::box_stack(centre, 5, kL);
        s.settings.sleeping = false;
        World world = make_world(s);
        auto heights = [&] {
            double sum = 0.0;
            for (BodyId id = 1; id <= 5; ++id)
                sum += at(world, id, centre).y();
            return sum;
        };
        const double start = heights();
        // Energy per unit mass: kinetic at most what the fall into the contacts released, at every frame.
        double created = -1e9, highest = start, kinetic_after_settling = 0.0;
        for (int f = 1; f <= 600; ++f) {
            world.step();
            double kinetic = 0.0;
            for (BodyId id = 1; id <= 5; ++id)
                kinetic += 0.5 * world.body(id)->linear_velocity.squaredNorm();
            created = std::max(created, kinetic - kG * (start - heights()));
            highest = std::max(highest, heights());
            if (f > 60) kinetic_after_settling = std::max(kinetic_after_settling, kinetic);
        }
        std::printf(
            "%s: stack of 5: heights summed %.5f -> %.5f (highest %.5f); kinetic minus potential released "
            "%.2e at most; kinetic after 1 s %.2e at most\n",
            name, start, heights(), highest, created, kinetic_after_settling);
        EXPECT_LE(highest - start, 1e-3) << name << ": no box rose";
        EXPECT_LE(start - heights(), 0.05) << name << ": settled by millimetres a box, no more";
        EXPECT_LE(created, 1e-3) << name << ": no kinetic energy beyond what settling released";
        // Measured 2.1e-4 at the origin and 1.4e-3 far out (other float offsets in the sector): the
        // solver's jitter, under 0.045 units/s a box.
        EXPECT_LE(kinetic_after_settling, 5e-3) << name << ": still once settled";
    }
}

}  // namespace
}  // namespace lpss
