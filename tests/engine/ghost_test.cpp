// Two engines splitting the world at a sector border, as two workers do: each simulates its own
// sectors and keeps ghosts of the other's bodies, updated every frame from the other's state (rounded
// to float, as on the wire); a body crossing over is handed off. The result matches one engine.
#include <gtest/gtest.h>

#include "engine_test_support.hpp"

namespace lpss {
namespace {

using testing::make_world;

constexpr double kL = 128.0;

BodySnapshot as_on_the_wire(BodySnapshot b) {
    // Per component: Eigen folds cast<float>().cast<double>() into nothing.
    for (int a = 0; a < 3; ++a)
        b.position.local[a] = static_cast<double>(static_cast<float>(b.position.local[a]));
    return b;
}

struct Split {
    World a;
    World b;
};

Split split(const Scene& scene) {
    EngineOptions left, right;
    left.owns = [](const SectorKey& k) { return k.i <= 0; };
    right.owns = [](const SectorKey& k) { return k.i >= 1; };
    return {make_world(scene, left), make_world(scene, right)};
}

/// One frame of both workers, then what they tell each other: ghosts follow, crossers are handed off.
int step(Split& s) {
    s.a.step();
    s.b.step();
    int handoffs = 0;
    for (auto [from, to] : {std::pair<World*, World*>{&s.a, &s.b}, {&s.b, &s.a}}) {
        for (const Departure& d : from->departures()) {
            BodySnapshot state = *from->body(d.id);
            state.position = d.to;  // exact, as a handoff carries it
            EXPECT_TRUE(from->set_state(state).ok());
            EXPECT_TRUE(to->set_state(state).ok());
            EXPECT_TRUE(from->is_ghost(d.id));
            EXPECT_FALSE(to->is_ghost(d.id));
            ++handoffs;
        }
    }
    for (auto [from, to] : {std::pair<World*, World*>{&s.a, &s.b}, {&s.b, &s.a}}) {
        for (const SectorKey& key : from->stepped_sectors()) {
            for (const BodySnapshot& b : from->sector_bodies(key)) {
                if (to->is_ghost(b.id)) {
                    EXPECT_TRUE(to->set_state(as_on_the_wire(b)).ok());
                }
            }
        }
    }
    return handoffs;
}

Scene crossing_scene() {
    // Two spheres colliding on the border between the workers, and a third that travels from the left
    // worker's sectors deep into the right one's.
    Scene scene = scenes::sphere_pair(Eigen::Vector3d(0.5 * kL, 0, 0), kL);
    BodyDesc traveller = scenes::sphere_body(3, 0.5, 1.0, Eigen::Vector3d(40, 5, 0));
    traveller.linear_velocity = Eigen::Vector3d(20, 0, 0);
    scene.bodies.push_back(traveller);
    return scene;
}

TEST(Ghosts, TwoEnginesSplitAtABorderMatchOne) {
    const Scene scene = crossing_scene();
    World one = make_world(scene);
    Split two = split(scene);
    EXPECT_TRUE(two.a.is_ghost(2));
    EXPECT_FALSE(two.a.is_ghost(1));
    int handoffs = 0;
    for (int f = 0; f < 300; ++f) {
        one.step();
        handoffs += step(two);
        ASSERT_TRUE(two.a.check_consistency().ok()) << two.a.check_consistency().error().message;
        ASSERT_TRUE(two.b.check_consistency().ok());
    }
    EXPECT_GE(handoffs, 1) << "the traveller changed worker";
    for (BodyId id : {1, 2, 3}) {
        const World& owner = two.a.is_ghost(id) ? two.b : two.a;
        const Eigen::Vector3d got = owner.grid().to_global(owner.body(id)->position);
        const Eigen::Vector3d want = one.grid().to_global(one.body(id)->position);
        EXPECT_LE((got - want).norm(), 1e-3) << "body " << id;
        EXPECT_NE(two.a.is_ghost(id), two.b.is_ghost(id)) << "exactly one owner of body " << id;
    }
    EXPECT_TRUE(two.a.is_ghost(3)) << "the traveller ended on the right";
    EXPECT_LT(one.body(1)->linear_velocity.x(), 0.0) << "the spheres collided";
}

TEST(Ghosts, CommandsOnGhostsAreRefusedAndOwnershipCanMove) {
    Split two = split(crossing_scene());
    Status st = two.a.apply_impulse(2, {1, 0, 0});
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().message.find("another worker"), std::string::npos);
    // The left engine takes over everything: ghosts become its own bodies, and step.
    two.a.set_ownership([](const SectorKey&) { return true; });
    EXPECT_FALSE(two.a.is_ghost(2));
    EXPECT_TRUE(two.a.apply_impulse(2, {1, 0, 0}).ok());
    two.a.step();
    EXPECT_TRUE(two.a.check_consistency().ok());
}

}  // namespace
}  // namespace lpss
