// The engine under any order of calls: random interleavings of adding, removing, moving, pushing and
// stepping bodies, and of changing which sectors the engine owns, over a few small sectors where bodies
// cross borders, empty sectors and refill them all the time (what a worker's ghost updates, remove
// commands and halo drops do). After every call the engine's invariants must hold (World::check_consistency:
// every body in exactly one live sector that lists it, clones only in live sectors next to their
// originals, pools bounded, no destroyed sector still listed), and every cloning stage must have made each
// clone a stepped body needs (EngineOptions::check_clones). Run under -DLPSS_SANITIZE=address,undefined
// to turn any use of freed memory into a failure. A failing run prints its seed; rerun one seed with
// LPSS_RANDOM_SEED=N, or more seeds with LPSS_RANDOM_SEEDS=N.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

#include "engine_test_support.hpp"

namespace lpss {
namespace {

constexpr double kL = 8.0;

/// One random session against one world. Every call is logged, so that a failure shows how it came about.
class RandomSession {
public:
    explicit RandomSession(std::uint64_t seed) : rng_(seed) {
        WorldSettings settings;
        settings.sector_size = kL;
        settings.gravity = {0, -9.81, 0};
        settings.sleeping = coin(0.5);
        EngineOptions options;
        options.threads = coin(0.3) ? 2 : 1;
        options.max_spare_clones = static_cast<std::size_t>(pick(0, 3));
        options.check_clones = true;
        options.owns = [this](const SectorKey& key) { return owns(key); };
        world_.emplace(World::create(settings, options).value());
        if (coin(0.5)) {
            BodyDesc ground;
            ground.id = 1;
            ground.name = "ground";
            ground.shape = Plane{Eigen::Vector3d::UnitY(), 0.0};
            ground.position = Eigen::Vector3d(0, -kL, 0);
            check(world_->add_body(ground), true, "add plane");
        }
    }

    /// Runs `calls` random calls; stops at the first broken invariant. With `nudges`, most moves turn a
    /// body and shift it a little where it is (so that it keeps its fat box while its broadphase box
    /// shrinks or grows), rather than put it anywhere.
    void run(int calls, bool nudges = false) {
        for (int n = 0; n < calls && !::testing::Test::HasFailure(); ++n) {
            const double r = uniform(0, 1);
            if (r < 0.18)
                add();
            else if (r < 0.28)
                remove();
            else if (r < 0.48)
                nudges&& coin(0.8) ? nudge() : move();
            else if (r < 0.56)
                push();
            else if (r < 0.62)
                change_ownership();
            else
                step();
            if (Status st = world_->check_consistency(); !st) {
                ADD_FAILURE() << "after call " << n << ": " << st.error().message << "\ncalls:\n"
                              << log_.str();
                return;
            }
        }
    }

private:
    bool coin(double p) { return uniform(0, 1) < p; }
    double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
    int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

    bool owns(const SectorKey& key) const {
        // Split along x as two workers would; some sessions own everything.
        return split_ == std::numeric_limits<std::int64_t>::max() || key.i <= split_;
    }

    /// Sector-local positions near borders and in a 3 x 2 x 2 block of sectors around the origin.
    SectorPosition somewhere() {
        SectorPosition p;
        p.sector = SectorKey{pick(-1, 1), pick(-1, 0), pick(0, 1)};
        for (int a = 0; a < 3; ++a) {
            const double edge = kL / 2 * (coin(0.5) ? 1 : -1);
            p.local[a] = coin(0.6) ? edge + uniform(-1.0, 1.0) : uniform(-kL / 2, kL / 2);
        }
        return p;
    }
    Eigen::Vector3d velocity() { return Eigen::Vector3d(uniform(-8, 8), uniform(-8, 8), uniform(-8, 8)); }

    BodyId any_id() {
        // Mostly bodies that exist; now and then one that never did, or one removed before.
        if (!ids_.empty() && coin(0.85)) return ids_[static_cast<std::size_t>(pick(0, int(ids_.size()) - 1))];
        return static_cast<BodyId>(pick(2, next_id_ + 3));
    }
    bool exists(BodyId id) const { return std::find(ids_.begin(), ids_.end(), id) != ids_.end(); }

    void check(const Status& st, bool expect_ok, const std::string& what) {
        log_ << what << (st ? "" : " -> refused: " + st.error().message) << "\n";
        if (st.ok() != expect_ok) {
            ADD_FAILURE() << what << (expect_ok ? " was refused: " + st.error().message : " was accepted")
                          << "\ncalls:\n"
                          << log_.str();
        }
    }

    void add() {
        BodyDesc b;
        const bool duplicate = !ids_.empty() && coin(0.05);
        b.id = duplicate ? ids_.front() : static_cast<BodyId>(next_id_++);
        b.name = "body" + std::to_string(b.id);
        const double size = uniform(0.2, 1.5);
        if (coin(0.5))
            b.shape = Sphere{size};
        else
            b.shape = Box{Eigen::Vector3d(size, uniform(0.2, 1.5), uniform(0.2, 1.5))};
        b.mass = coin(0.15) ? 0.0 : uniform(0.5, 3);
        b.position = somewhere();
        b.linear_velocity = b.mass > 0 ? velocity() : Eigen::Vector3d::Zero();
        std::ostringstream what;
        what << "add " << b.id << (b.mass > 0 ? " dynamic" : " static");
        check(world_->add_body(b), !duplicate, what.str());
        if (!duplicate) ids_.push_back(b.id);
    }

    void remove() {
        const BodyId id = any_id();
        const bool known = exists(id);
        check(world_->remove_body(id), known, "remove " + std::to_string(id));
        if (known) ids_.erase(std::find(ids_.begin(), ids_.end(), id));
    }

    void move() {
        const BodyId id = any_id();
        BodySnapshot state;
        state.id = id;
        state.position = somewhere();
        // Sometimes an offset beyond the sector (brought back into its cell), sometimes a bad one.
        if (coin(0.05)) state.position.local.x() += 3 * kL;
        const bool bad = coin(0.05);
        if (bad) state.position.local.y() = std::numeric_limits<double>::quiet_NaN();
        state.orientation =
            Eigen::Quaterniond(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), 1).normalized();
        state.linear_velocity = velocity();
        state.awake = coin(0.7);
        const std::optional<BodyDesc> desc = world_->description(id);
        const bool movable = desc && desc->mass > 0 && !bad;
        check(world_->set_state(state), movable, "set_state " + std::to_string(id));
    }

    void nudge() {
        const BodyId id = any_id();
        const std::optional<BodySnapshot> now = world_->body(id);
        if (!now) return move();
        BodySnapshot state = *now;
        for (int a = 0; a < 3; ++a)
            state.position.local[a] += uniform(-0.15, 0.15);
        // Any orientation: a box turned from 45 degrees to flat shrinks its broadphase box by more than
        // a fat box's slack, and stays inside that fat box.
        state.orientation =
            Eigen::Quaterniond(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)).normalized();
        state.linear_velocity = coin(0.5) ? Eigen::Vector3d::Zero().eval() : (velocity() * 0.1).eval();
        state.angular_velocity = Eigen::Vector3d::Zero();
        state.awake = coin(0.3);
        const std::optional<BodyDesc> desc = world_->description(id);
        check(world_->set_state(state), desc && desc->mass > 0, "nudge " + std::to_string(id));
    }

    void push() {
        const BodyId id = any_id();
        const std::optional<BodyDesc> desc = world_->description(id);
        const bool pushable = desc && desc->mass > 0 && !world_->is_ghost(id);
        if (coin(0.5))
            check(world_->apply_impulse(id, velocity()), pushable, "impulse " + std::to_string(id));
        else
            check(world_->set_velocity(id, velocity(), velocity()), pushable,
                  "velocity " + std::to_string(id));
    }

    void change_ownership() {
        split_ = coin(0.3) ? std::numeric_limits<std::int64_t>::max() : pick(-2, 1);
        world_->set_ownership([this](const SectorKey& key) { return owns(key); });
        log_ << "own i <= " << split_ << "\n";
    }

    void step() {
        world_->step();
        log_ << "step\n";
    }

    std::mt19937_64 rng_;
    std::optional<World> world_;
    std::int64_t split_ = std::numeric_limits<std::int64_t>::max();
    std::vector<BodyId> ids_;
    int next_id_ = 2;
    std::ostringstream log_;
};

std::uint64_t env_or(const char* name, std::uint64_t fallback) {
    const char* value = std::getenv(name);
    return value ? std::strtoull(value, nullptr, 10) : fallback;
}

TEST(RandomCalls, InvariantsHoldAfterEveryCall) {
    // 150 sessions of 400 calls: 60,000 calls, thousands of each kind of interleaving that empties,
    // refills and destroys sectors. Then seeds that once failed, found in longer runs (LPSS_RANDOM_SEEDS):
    // 2015, a body at rest moved into a sector holding its clone kept the clone's broadphase box there;
    // 2488, a static body's broadphase box outgrew its fat box by Bullet's contact threshold.
    const std::vector<std::uint64_t> failed_once = {2015, 2488};
    const std::uint64_t one = env_or("LPSS_RANDOM_SEED", 0);
    const std::uint64_t random = env_or("LPSS_RANDOM_SEEDS", 150);
    const std::uint64_t sessions = one ? 1 : random + failed_once.size();
    for (std::uint64_t n = 0; n < sessions && !HasFailure(); ++n) {
        const std::uint64_t seed = one ? one : n < random ? 1000 + n : failed_once[n - random];
        SCOPED_TRACE("seed " + std::to_string(seed) +
                     " (rerun with LPSS_RANDOM_SEED=" + std::to_string(seed) + ")");
        RandomSession(seed).run(400);
    }
}

TEST(RandomCalls, BodiesTurnedWhereTheyAreKeepEveryCloneTheyNeed) {
    // Bodies turned and shifted a little where they are, near borders: their broadphase boxes shrink and
    // grow inside fat boxes they keep, and a query of their sector must still find them by fat box (a
    // sector's overhangs, border_index.hpp). 100 sessions of 400 calls.
    const std::uint64_t one = env_or("LPSS_RANDOM_SEED", 0);
    const std::uint64_t sessions = one ? 1 : env_or("LPSS_RANDOM_SEEDS", 100);
    for (std::uint64_t n = 0; n < sessions && !HasFailure(); ++n) {
        const std::uint64_t seed = one ? one : 5000 + n;
        SCOPED_TRACE("seed " + std::to_string(seed) +
                     " (rerun with LPSS_RANDOM_SEED=" + std::to_string(seed) + ")");
        RandomSession(seed).run(400, true);
    }
}

TEST(RandomCalls, ABoxTurnedFlatWhereItIsIsStillFoundByItsFatBox) {
    // A box at 45 degrees next to a border gets its fat box; turned flat and shifted where it is, it keeps
    // that fat box while its broadphase box shrinks (its fat box then overhangs it by as much as 0.58 in
    // this sweep, where the bound once computed from the fat box's growth said 0.5). A body across the border
    // then gets a fat box of its own that may overlap the box's only at its edge, and the box comes back
    // towards it within its own fat box. Swept over where the box stands, how far it shifts, where the other
    // body goes and where the box ends. (The old bound passed this too: Bullet's broadphase tree keeps a
    // leaf's box until the body leaves it, so the query still met the box as it stood at 45 degrees. The
    // bound is now measured, and holds without leaning on that.)
    int worlds = 0;
    int cloned = 0;
    for (double box_x = 4.8; box_x <= 5.61 && !HasFailure(); box_x += 0.1) {
        for (double shift = 0.0; shift <= 0.36 && !HasFailure(); shift += 0.06) {
            for (double other_x = 3.0; other_x <= 4.21 && !HasFailure(); other_x += 0.05) {
                for (double back = 0.0; back <= 0.31 && !HasFailure(); back += 0.1) {
                    WorldSettings settings;
                    settings.sector_size = kL;
                    settings.gravity = Eigen::Vector3d::Zero();
                    settings.sleeping = false;
                    EngineOptions options;
                    options.check_clones = true;
                    World world = World::create(settings, options).value();
                    BodyDesc box = scenes::box_body(2, Eigen::Vector3d::Constant(0.5), 1.0,
                                                    Eigen::Vector3d(box_x, 0, 0).eval());
                    box.orientation =
                        Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitY()));
                    const BodyDesc ball = scenes::sphere_body(3, 0.5, 1.0, Eigen::Vector3d(2.0, 0, 0).eval());
                    ASSERT_TRUE(world.add_body(box));
                    ASSERT_TRUE(world.add_body(ball));
                    auto place = [&](BodyId id, double x, const Eigen::Quaterniond& q) {
                        BodySnapshot s;
                        s.id = id;
                        s.position = world.grid().from_global(Eigen::Vector3d(x, 0, 0)).value();
                        s.orientation = q;
                        s.awake = true;
                        ASSERT_TRUE(world.set_state(s));
                    };
                    auto step = [&](const char* after) {
                        world.step();
                        const Status st = world.check_consistency();
                        EXPECT_TRUE(st) << after << " (box at " << box_x << ", shifted " << shift
                                        << ", other body at " << other_x << "): " << st.error().message;
                    };
                    step("the first step");
                    place(2, box_x + shift, Eigen::Quaterniond::Identity());
                    step("the box turned flat");
                    place(3, other_x, Eigen::Quaterniond::Identity());
                    step("the other body moved");
                    place(2, box_x - back, Eigen::Quaterniond::Identity());
                    step("the box back towards it");
                    ++worlds;
                    if (world.last_frame_stats().clones > 0) ++cloned;
                }
            }
        }
    }
    EXPECT_GT(worlds, 1000);
    // Many end with the two near enough across the border to need clones: the case is there.
    EXPECT_GT(cloned, worlds / 10);
    std::printf("%d worlds, %d with clones at the end\n", worlds, cloned);
}

TEST(RandomCalls, ARemovalDestroysASectorStillQueuedForDestruction) {
    // The interleaving that once read freed memory: moving a body out of its sector queues the emptied
    // sector for destruction at the next step; moving it back and removing it destroys that sector at once;
    // the step must then not touch it.
    WorldSettings settings;
    settings.sector_size = kL;
    World world = World::create(settings).value();
    BodyDesc a;
    a.id = 7;
    a.name = "a";
    a.shape = Sphere{0.5};
    a.mass = 1;
    a.position = Eigen::Vector3d(0, 0, 0);
    ASSERT_TRUE(world.add_body(a).ok());
    BodySnapshot state = *world.body(7);
    state.position.sector = SectorKey{1, 0, 0};
    ASSERT_TRUE(world.set_state(state).ok());
    EXPECT_TRUE(world.check_consistency().ok()) << world.check_consistency().error().message;
    state.position.sector = SectorKey{0, 0, 0};
    ASSERT_TRUE(world.set_state(state).ok());
    ASSERT_TRUE(world.remove_body(7).ok());
    EXPECT_TRUE(world.check_consistency().ok()) << world.check_consistency().error().message;
    world.step();
    EXPECT_TRUE(world.check_consistency().ok()) << world.check_consistency().error().message;
    EXPECT_TRUE(world.sectors().empty());
}

}  // namespace
}  // namespace lpss
