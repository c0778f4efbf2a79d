// What a worker's ghosts become when the samples of other workers' sectors are applied, alone and in
// batches that span several frames (a worker that fell behind applies them together).
#include <gtest/gtest.h>

#include "halo.hpp"
#include "lpss_dds/convert.hpp"
#include "lpss_dds/sector_publisher.hpp"

namespace lpss::worker {
namespace {

const SectorKey kHeld{0, 0, 0};
const SectorKey kAlsoHeld{1, 0, 0};

BodyDesc box(BodyId id) {
    BodyDesc d;
    d.id = id;
    d.shape = Shape{Box{Eigen::Vector3d(0.5, 0.5, 0.5)}};
    d.mass = 1;
    return d;
}

BodySnapshot at(BodyId id, const SectorKey& sector, double x) {
    BodySnapshot b;
    b.id = id;
    b.position = SectorPosition{sector, Eigen::Vector3d(x, 2, 3)};
    b.linear_velocity = Eigen::Vector3d(1, 0, 0);
    b.awake = true;
    return b;
}

const SectorKey kOwn{0, 1, 0};  ///< worker 2's: beside both held sectors (diagonally beside kAlsoHeld)

/// Worker 1 owns every sector but kOwn, which worker 2 owns (blocks of one sector; (0, 1, 1) follows
/// (0, 1, 0) on the Morton curve), from epoch `epoch` on.
SectorAssignment worker_2_owning_one(std::uint32_t epoch) {
    SectorAssignment a;
    a.epoch = epoch;
    a.block_size = 1;
    a.workers = {1, 2, 1};
    a.starts = {MortonCode{}, morton_code(kOwn), morton_code({0, 1, 1})};
    return a;
}

/// Worker 2 holding ghosts of worker 1's sectors. With a largest radius of a whole sector, every body of
/// the two held sectors comes near worker 2's sector, and so is a ghost in its engine.
struct Ghosts {
    World world = std::move(World::create(settings()).value());
    Halo halo{2};
    dds::SectorPublisher owner;  ///< worker 1's samples
    dds::SectorPublisher::Describe describe = [](BodyId id) { return dds::kind_of(box(id)); };

    static WorldSettings settings() {
        WorldSettings s;
        s.sector_size = 16;
        return s;
    }
    explicit Ghosts(double largest_radius = 16.0) {
        const SectorAssignment a = worker_2_owning_one(1);
        EXPECT_EQ(a.owner_of(kOwn), 2u);
        EXPECT_EQ(a.owner_of(kHeld), 1u);
        EXPECT_EQ(a.owner_of(kAlsoHeld), 1u);
        EXPECT_EQ(a.owner_of({0, 1, 1}), 1u);
        halo.follow(a, a, largest_radius);
        world.set_ownership([](const SectorKey& key) { return key == kOwn; });
    }
    void apply(const std::vector<wire::SectorFrame>& samples) {
        std::vector<const wire::SectorFrame*> batch;
        for (const wire::SectorFrame& s : samples)
            batch.push_back(&s);
        halo.apply(world, batch, {});
    }
};

TEST(Halo, ABodyMovedAndThenTakenOutOfItsSectorInOneBatchIsGone) {
    Ghosts g;
    g.apply({g.owner.whole(kHeld, {at(7, kHeld, 1), at(8, kHeld, 4)}, {0, 0}, 5, g.describe)});
    ASSERT_TRUE(g.world.contains(7));
    ASSERT_TRUE(g.world.is_ghost(7));
    // Frame 6 moves body 7; frame 7 takes it out (it went to a sector this worker does not hold).
    const auto moved = g.owner.update(kHeld, {at(7, kHeld, 1.5)}, {0}, {}, 6, g.describe);
    const auto left = g.owner.update(kHeld, {}, {}, {7}, 7, g.describe);
    ASSERT_TRUE(moved && left);
    g.apply({*moved, *left});
    EXPECT_FALSE(g.world.contains(7)) << "a ghost left behind would collide with what is really there";
    EXPECT_TRUE(g.world.contains(8));
}

TEST(Halo, ABodyCrossingBetweenHeldSectorsInOneBatchStays) {
    Ghosts g;
    dds::SectorPublisher& owner = g.owner;
    g.apply({owner.whole(kHeld, {at(7, kHeld, 15.9), at(8, kHeld, 4)}, {0, 0}, 5, g.describe)});
    // Frame 6 moves it to the east border; in frame 7 it crosses into the next sector, held here too.
    const auto moved = owner.update(kHeld, {at(7, kHeld, 15.95)}, {0}, {}, 6, g.describe);
    const auto left = owner.update(kHeld, {}, {}, {7}, 7, g.describe);
    const wire::SectorFrame arrived = owner.whole(kAlsoHeld, {at(7, kAlsoHeld, 0.01)}, {0}, 7, g.describe);
    ASSERT_TRUE(moved && left);
    g.apply({*moved, arrived, *left});  // in either order within frame 7
    ASSERT_TRUE(g.world.contains(7));
    EXPECT_EQ(g.world.body(7)->position.sector, kAlsoHeld);
    EXPECT_NEAR(g.world.body(7)->position.local.x(), 0.01, 1e-6);
}

/// A body at rest at (x, y, 3) in its sector (L = 16: offsets within 8 of the centre).
BodySnapshot resting(BodyId id, const SectorKey& sector, double x, double y) {
    BodySnapshot b;
    b.id = id;
    b.position = SectorPosition{sector, Eigen::Vector3d(x, y, 3)};
    return b;
}

TEST(Halo, OnlyTheBodiesThatComeNearItsSectorsAreGhostsTheRestAreBuiltWhenTheyDo) {
    Ghosts g(1.0);  // bodies of radius 0.87 reach about 2 units past a border
    // Body 7 rests half a unit from the border with worker 2's sector (+y), body 8 fourteen units from it.
    g.apply(
        {g.owner.whole(kHeld, {resting(7, kHeld, 1, 7.5), resting(8, kHeld, 1, -6)}, {0, 0}, 5, g.describe)});
    EXPECT_TRUE(g.world.contains(7));
    EXPECT_FALSE(g.world.contains(8)) << "a body far from every sector of this worker needs no ghost";
    EXPECT_EQ(g.halo.dormant(), 1u);
    EXPECT_TRUE(g.halo.holds(kHeld));
    // Frame 6: body 8 moves to the border; it is built where its owner has it.
    const auto moved = g.owner.update(kHeld, {at(8, kHeld, 1)}, {0}, {}, 6, g.describe);
    ASSERT_TRUE(moved);
    g.apply({*moved});
    EXPECT_FALSE(g.world.contains(8)) << "(2, 3) is still far";
    BodySnapshot near = resting(8, kHeld, 1.25, 7.75);
    near.linear_velocity = Eigen::Vector3d(0, 0.5, 0);
    near.awake = true;
    const auto arrived = g.owner.update(kHeld, {near}, {0}, {}, 7, g.describe);
    ASSERT_TRUE(arrived);
    g.apply({*arrived});
    ASSERT_TRUE(g.world.contains(8));
    EXPECT_TRUE(g.world.is_ghost(8));
    EXPECT_EQ(g.halo.dormant(), 0u);
    const BodySnapshot built = *g.world.body(8);
    EXPECT_EQ(built.position.sector, kHeld);
    EXPECT_NEAR(built.position.local.x(), 1.25, 1e-6);
    EXPECT_NEAR(built.position.local.y(), 7.75, 1e-6);
    EXPECT_NEAR(built.linear_velocity.y(), 0.5, 1e-6);
    EXPECT_TRUE(built.awake);
}

TEST(Halo, ADormantBodyThatLeavesOrWhoseSectorIsReleasedIsForgotten) {
    Ghosts g(1.0);
    g.apply(
        {g.owner.whole(kHeld, {resting(7, kHeld, 1, 7.5), resting(8, kHeld, 1, -6)}, {0, 0}, 5, g.describe)});
    ASSERT_EQ(g.halo.dormant(), 1u);
    const auto left = g.owner.update(kHeld, {}, {}, {8}, 6, g.describe);
    ASSERT_TRUE(left);
    g.apply({*left});
    EXPECT_EQ(g.halo.dormant(), 0u) << "a record of a body gone from every held sector";
    // It comes back; then the sector releases this worker: ghosts and records go together.
    const auto back = g.owner.update(kHeld, {resting(8, kHeld, 1, -6)}, {0}, {}, 7, g.describe);
    ASSERT_TRUE(back);
    g.apply({*back});
    EXPECT_EQ(g.halo.dormant(), 1u);
    auto release = g.owner.update(kHeld, {}, {}, {}, 8, g.describe);
    wire::SectorFrame released = release ? *release : g.owner.whole(kHeld, {}, {}, 8, g.describe);
    released.released({2});
    g.apply({released});
    EXPECT_FALSE(g.halo.holds(kHeld));
    EXPECT_FALSE(g.world.contains(7));
    EXPECT_EQ(g.halo.dormant(), 0u);
}

TEST(Halo, ABodyLeftOutOfACompleteSampleIsForgottenThoughDormant) {
    Ghosts g(1.0);
    g.apply(
        {g.owner.whole(kHeld, {resting(7, kHeld, 1, 7.5), resting(8, kHeld, 1, -6)}, {0, 0}, 5, g.describe)});
    ASSERT_EQ(g.halo.dormant(), 1u);
    dds::SectorPublisher again;  // a new owner: it sends the sector whole, without body 8
    g.apply({again.whole(kHeld, {resting(7, kHeld, 1, 7.5)}, {0}, 6, g.describe)});
    EXPECT_EQ(g.halo.dormant(), 0u);
    EXPECT_TRUE(g.world.contains(7));
}

TEST(Halo, DormantBodiesAreBuiltWhenTheAssignmentOrTheReachBringsThemNear) {
    Ghosts g(1.0);
    g.apply(
        {g.owner.whole(kHeld, {resting(7, kHeld, 1, 7.5), resting(8, kHeld, 1, -6)}, {0, 0}, 5, g.describe)});
    g.apply({g.owner.whole(kAlsoHeld, {resting(9, kAlsoHeld, 1, -6)}, {0}, 5, g.describe)});
    ASSERT_EQ(g.halo.dormant(), 2u);
    // Worker 2 is given kHeld from frame 11 (a block of one sector: (0, 0, 1) follows it on the curve): at
    // the frame before, every body of it must be a ghost, to be its own when the frame starts.
    SectorAssignment next = worker_2_owning_one(2);
    next.from_frame = 11;
    next.workers = {1, 2, 1};
    next.starts = {MortonCode{}, morton_code(kHeld), morton_code({0, 0, 1})};
    ASSERT_EQ(next.owner_of(kHeld), 2u);
    g.halo.follow(g.halo.current(), next, 1.0);
    g.apply({});
    EXPECT_TRUE(g.world.contains(8));
    EXPECT_FALSE(g.world.contains(9)) << "kAlsoHeld's body is far from kHeld too";
    // A larger body in the world: every body reaches further, body 9 included.
    g.halo.follow(g.halo.current(), next, 16.0);
    g.apply({});
    EXPECT_TRUE(g.world.contains(9));
    EXPECT_EQ(g.halo.dormant(), 0u);
}

TEST(Halo, AWorkerGoneAndBackUnderItsIdGetsTheSectorsItNeedsWhole) {
    // Worker 1 owns sector (0,0,0), worker 2 the sector east of it, near which a body of worker 1 rests.
    SectorAssignment both;
    both.epoch = 1;
    both.block_size = 1;
    both.workers = {1, 2};
    both.starts = {MortonCode{}, morton_code({1, 0, 0})};
    ASSERT_EQ(both.owner_of(kHeld), 1u);
    ASSERT_EQ(both.owner_of(kAlsoHeld), 2u);
    Halo halo(1);
    halo.follow(both, both, 1.0);
    const std::uint32_t east = 1u << (9 * 2 + 3 * 1 + 1);  // the neighbour at (+1, 0, 0)
    Halo::Addressing first = halo.address(kHeld, east, false, 10);
    EXPECT_TRUE(first.gained);
    EXPECT_EQ(first.recipients, std::vector<std::uint32_t>{2});
    // Worker 2 is gone: worker 1 takes everything. The sector is quiet, so it is not addressed again.
    SectorAssignment alone = both.without(2, {});
    alone.epoch = 2;
    halo.follow(alone, alone, 1.0);
    // Worker 2 comes back under its id and is given its sector again: at the frame before, worker 1 must
    // send the sector it rests beside whole, as to any worker that did not hold it.
    SectorAssignment again = both;
    again.epoch = 3;
    again.from_frame = 31;
    halo.follow(alone, again, 1.0);
    Halo::Addressing back = halo.address(kHeld, east, false, 30);
    EXPECT_TRUE(back.gained) << "the worker back under id 2 never held it";
    EXPECT_EQ(back.recipients, std::vector<std::uint32_t>{2});
}

}  // namespace
}  // namespace lpss::worker
