// The delta encoding of sector frames end to end: what SectorPublisher writes from what changed, read by
// SectorChain and SectorMirror, gives the sector as it is, whatever the changes; kinds travel with the
// bodies that arrive and are shared in the mirror; the neighbours bodies come near are counted per sector.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>

#include "lpss_dds/convert.hpp"
#include "lpss_dds/sector_chain.hpp"
#include "lpss_dds/sector_mirror.hpp"
#include "lpss_dds/sector_publisher.hpp"

namespace lpss::dds {
namespace {

const SectorKey kSector{-2, 5, 9};

BodySnapshot body(BodyId id, double x, bool awake = true) {
    BodySnapshot b;
    b.id = id;
    b.position = SectorPosition{kSector, Eigen::Vector3d(x, 0.25, -1)};
    b.awake = awake;
    return b;
}

wire::BodyKind kind_of_id(BodyId id) {
    BodyDesc d;
    d.id = id;
    d.name = id % 7 == 0 ? "named" + std::to_string(id) : "";
    d.shape = id % 2 ? Shape{Sphere{0.5}} : Shape{Box{Eigen::Vector3d(0.5, 1, 2)}};
    d.mass = 1;
    return kind_of(d);
}

TEST(SectorPublisher, PartialSamplesCarryWhatChangedAndArrivalsTheirKinds) {
    SectorPublisher publisher;
    const wire::SectorFrame first =
        publisher.whole(kSector, {body(1, 1), body(2, 2), body(3, 3)}, {0, 0, 0}, 10, kind_of_id);
    EXPECT_TRUE(first.complete());
    EXPECT_EQ(first.kinds().size(), 3u);
    EXPECT_EQ(first.offsets().size(), 3u);
    // Body 2 moved, body 4 arrived, body 3 left; body 1 was looked at but is unchanged.
    auto second =
        publisher.update(kSector, {body(1, 1), body(2, 2.5), body(4, 4)}, {0, 0, 0}, {3}, 11, kind_of_id);
    ASSERT_TRUE(second);
    EXPECT_FALSE(second->complete());
    EXPECT_EQ(second->base(), 10u);
    ASSERT_EQ(second->bodies().size(), 2u);
    EXPECT_EQ(second->bodies()[0].id(), 2u);
    EXPECT_EQ(second->bodies()[1].id(), 4u);
    ASSERT_EQ(second->kinds().size(), 1u) << "only the arrival is described";
    EXPECT_EQ(second->kinds()[0].id(), 4u);
    EXPECT_EQ(second->departed(), std::vector<std::uint64_t>{3});
    EXPECT_FALSE(publisher.update(kSector, {body(1, 1)}, {0}, {3}, 12, kind_of_id))
        << "nothing new: no sample";
    EXPECT_EQ(publisher.counts(kSector).bodies, 3u);
    EXPECT_EQ(publisher.stamp(kSector), 11u);
}

TEST(SectorPublisher, ASectorThatEmptiesSaysSoInASampleAReaderThatJoinsLaterCanUse) {
    // A reader that joins after the sector emptied finds in the writer's durable history only the last
    // samples of it: the one that empties it must be of use without the samples before.
    SectorPublisher publisher;
    publisher.whole(kSector, {body(1, 1), body(2, 2)}, {0, 0}, 10, kind_of_id);
    auto moved = publisher.update(kSector, {body(1, 1.5)}, {0}, {2}, 11, kind_of_id);
    ASSERT_TRUE(moved);
    EXPECT_FALSE(moved->complete()) << "a body left, one stays: partial";
    auto emptied = publisher.update(kSector, {}, {}, {1}, 12, kind_of_id);
    ASSERT_TRUE(emptied);
    EXPECT_TRUE(emptied->complete());
    EXPECT_EQ(emptied->base(), 12u);
    EXPECT_TRUE(emptied->bodies().empty());
    EXPECT_FALSE(publisher.publishes(kSector)) << "forgotten once empty";

    SectorChain late;
    EXPECT_FALSE(late.accept(*moved)) << "the partial sample is of no use alone";
    EXPECT_TRUE(late.accept(*emptied));
    SectorMirror mirror;
    mirror.apply({&*emptied}, nullptr);
    EXPECT_EQ(mirror.sectors().count(kSector), 0u);

    // A reader that held the sector sees both bodies leave.
    SectorMirror follower;
    const wire::SectorFrame first =
        SectorPublisher{}.whole(kSector, {body(1, 1), body(2, 2)}, {0, 0}, 10, kind_of_id);
    std::vector<BodyId> left;
    follower.apply({&first}, &left);
    follower.apply({&*moved, &*emptied}, &left);
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<BodyId>{1, 2}));
    EXPECT_EQ(follower.sectors().count(kSector), 0u);
}

TEST(SectorPublisher, CountsTheNeighboursItsBodiesComeNear) {
    SectorPublisher publisher;
    const std::uint32_t east = 1u << 22, up = 1u << 16;
    publisher.whole(kSector, {body(1, 1), body(2, 2)}, {east, east | up}, 1, kind_of_id);
    EXPECT_EQ(publisher.near(kSector), east | up);
    ASSERT_TRUE(publisher.update(kSector, {body(2, 2.5)}, {0}, {}, 2, kind_of_id));
    EXPECT_EQ(publisher.near(kSector), east) << "body 1 still comes near the east";
    ASSERT_TRUE(publisher.update(kSector, {}, {}, {1}, 3, kind_of_id));
    EXPECT_EQ(publisher.near(kSector), 0u);
}

TEST(SectorPublisher, WhatItWritesRebuildsTheSectorWhateverTheChanges) {
    // 2,000 frames of random moves, arrivals, departures and sleep, and now and then a sector sent whole,
    // read by a mirror through a chain: the mirror always holds exactly the sector as it is.
    std::mt19937_64 random(11);
    std::map<BodyId, BodySnapshot> truth;
    SectorPublisher publisher;
    SectorChain chain;
    SectorMirror mirror;
    auto sorted = [](const std::map<BodyId, BodySnapshot>& bodies) {
        std::vector<BodySnapshot> out;
        for (const auto& [id, b] : bodies)
            out.push_back(b);
        return out;
    };
    for (BodyId id = 1; id <= 20; ++id)
        truth[id] = body(id, double(id));
    wire::SectorFrame sample =
        publisher.whole(kSector, sorted(truth), std::vector<std::uint32_t>(truth.size()), 1, kind_of_id);
    ASSERT_TRUE(chain.accept(sample));
    mirror.apply({&sample});
    BodyId next_id = 21;
    for (std::uint64_t frame = 2; frame <= 2000; ++frame) {
        std::map<BodyId, BodySnapshot> changed;
        std::vector<BodyId> left;
        const int events = std::uniform_int_distribution<int>(0, 6)(random);
        for (int e = 0; e < events; ++e) {
            const int what = std::uniform_int_distribution<int>(0, 9)(random);
            if (what < 6 && !truth.empty()) {  // a body moves, or falls asleep
                auto it = std::next(truth.begin(),
                                    std::uniform_int_distribution<int>(0, int(truth.size()) - 1)(random));
                it->second.position.local.x() += 0.25;
                it->second.awake = what != 0;
                changed[it->first] = it->second;
            } else if (what < 8) {  // a body arrives
                truth[next_id] = body(next_id, 0.5);
                changed[next_id] = truth[next_id];
                ++next_id;
            } else if (!truth.empty()) {  // a body leaves
                auto it = std::next(truth.begin(),
                                    std::uniform_int_distribution<int>(0, int(truth.size()) - 1)(random));
                left.push_back(it->first);
                changed.erase(it->first);
                truth.erase(it);
            }
        }
        std::sort(left.begin(), left.end());
        std::optional<wire::SectorFrame> out;
        if (frame % 97 == 0 || !publisher.publishes(kSector)) {
            out = publisher.whole(kSector, sorted(truth), std::vector<std::uint32_t>(truth.size()), frame,
                                  kind_of_id);
        } else {
            const std::vector<BodySnapshot> changes = sorted(changed);
            out = publisher.update(kSector, changes, std::vector<std::uint32_t>(changes.size()), left, frame,
                                   kind_of_id);
        }
        if (out) {
            ASSERT_TRUE(chain.accept(*out)) << "frame " << frame;
            mirror.apply({&*out});
        }
        const auto it = mirror.sectors().find(kSector);
        const std::size_t held = it == mirror.sectors().end() ? 0 : it->second.size();
        ASSERT_EQ(held, truth.size()) << "frame " << frame;
        if (held == 0) continue;
        for (const SectorMirror::Body& b : it->second) {
            const BodySnapshot& want = truth.at(b.state.id);
            ASSERT_EQ(b.state.position[0], static_cast<float>(want.position.local.x())) << "frame " << frame;
            ASSERT_EQ(b.state.awake(), want.awake) << "frame " << frame;
            const wire::BodyKind k = mirror.kind(b);
            ASSERT_EQ(k.id(), b.state.id);
            ASSERT_EQ(k.name(), kind_of_id(b.state.id).name());
            ASSERT_EQ(k.shape(), kind_of_id(b.state.id).shape());
        }
    }
    EXPECT_EQ(mirror.distinct_kinds(), 2u) << "spheres and boxes: two kinds for hundreds of bodies";
}

}  // namespace
}  // namespace lpss::dds
