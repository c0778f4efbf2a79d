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

/// Worker 2 holding ghosts of worker 1's sectors.
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
    Ghosts() {
        SectorAssignment all_to_worker_1;
        all_to_worker_1.epoch = 1;
        all_to_worker_1.workers = {1};
        all_to_worker_1.starts = {MortonCode{}};
        halo.follow(all_to_worker_1, all_to_worker_1, 1.0);
        world.set_ownership([](const SectorKey&) { return false; });
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
