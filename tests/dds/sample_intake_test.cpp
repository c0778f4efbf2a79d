// What every reader of sector samples (worker, coordinator, client) does with one: refuse the implausible
// and the foreign, queue the usable by frame, drop the stale, and want whole a sector whose partial sample
// came without its base, until a usable sample of it comes.
#include "lpss_dds/sample_intake.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <optional>
#include <thread>

#include "lpss_dds/convert.hpp"
#include "two_sector_samples.hpp"

namespace lpss::dds {
namespace {

using testing::kEast;
using testing::kWest;
using Taken = SampleIntake::Taken;

SectorAssignment assignment(std::uint32_t epoch, std::uint64_t from_frame) {
    return testing::two_sector_assignment(epoch, from_frame);
}

/// A complete sample of `key` holding one sphere.
wire::SectorFrame whole(const SectorKey& key, std::uint64_t frame, std::uint32_t worker,
                        std::uint32_t epoch = 1) {
    wire::SectorFrame s = testing::empty_sample(key, frame, worker, epoch);
    BodySnapshot b;
    b.id = 100 + frame;
    b.position = SectorPosition{key, Eigen::Vector3d(1, 2, 3)};
    s.bodies().push_back(to_wire(b));
    BodyDesc d;
    d.id = b.id;
    d.mass = 1.0;
    d.shape = Sphere{0.5};
    s.kinds().push_back(kind_of(d));
    return s;
}

wire::SectorFrame partial(const SectorKey& key, std::uint64_t frame, std::uint64_t base,
                          std::uint32_t worker) {
    wire::SectorFrame s = whole(key, frame, worker);
    s.base(base);
    s.complete(false);
    return s;
}

std::vector<std::uint64_t> frames_of(const std::vector<const wire::SectorFrame*>& batch) {
    std::vector<std::uint64_t> out;
    for (const wire::SectorFrame* f : batch)
        out.push_back(f->frame());
    return out;
}

TEST(SampleIntake, APartialSampleWithoutItsBaseWantsItsSectorWholeUntilAWholeOneComes) {
    SampleIntake intake("test", "tester");
    intake.learn(assignment(1, 1));
    const std::uint32_t west = assignment(1, 1).owner_of(kWest);
    EXPECT_EQ(intake.take(whole(kWest, 10, west), 10, kFramesAhead), Taken::queued);
    EXPECT_TRUE(intake.whole_due().empty());
    // Frame 11's whole sample (the new base) was lost: 12 cannot be applied on 10.
    EXPECT_EQ(intake.take(partial(kWest, 12, 11, west), 12, kFramesAhead), Taken::without_base);
    EXPECT_TRUE(intake.wants_whole(kWest));
    EXPECT_FALSE(intake.wants_whole(kEast));
    const std::vector<wire::SectorKey> due = intake.whole_due();
    ASSERT_EQ(due.size(), 1u);
    EXPECT_EQ(from_wire(due[0]), kWest);
    EXPECT_TRUE(intake.whole_due().empty()) << "asked again only after 100 ms";
    EXPECT_EQ(frames_of(intake.through(20)), (std::vector<std::uint64_t>{10}));
    // The owner answers with the sector whole: it is no longer wanted.
    EXPECT_EQ(intake.take(whole(kWest, 13, west), 13, kFramesAhead), Taken::queued);
    EXPECT_FALSE(intake.wants_whole(kWest));
    intake.want_whole(kEast);  // and a sector wanted for a reason of the reader's own
    std::this_thread::sleep_for(std::chrono::milliseconds(110));
    const std::vector<wire::SectorKey> after = intake.whole_due();
    ASSERT_EQ(after.size(), 1u);
    EXPECT_EQ(from_wire(after[0]), kEast);
}

TEST(SampleIntake, TheImplausibleAndTheForeignAreRefusedAndTheStaleDropped) {
    SampleIntake intake("test", "tester");
    intake.learn(assignment(1, 1));
    const std::uint32_t west = assignment(1, 1).owner_of(kWest);
    const std::uint32_t east = assignment(1, 1).owner_of(kEast);
    wire::SectorFrame nan = whole(kWest, 5, west);
    nan.bodies()[0].position().x(std::numeric_limits<double>::quiet_NaN());
    EXPECT_EQ(intake.take(nan, 5, kFramesAhead), Taken::refused);
    EXPECT_EQ(intake.take(whole(kWest, 50, west), 5, kFramesAhead), Taken::refused) << "far in the future";
    EXPECT_EQ(intake.take(whole(kWest, 5, east), 5, kFramesAhead), Taken::refused) << "not its sector";
    EXPECT_EQ(intake.refused(), 3u);
    EXPECT_TRUE(intake.whole_due().empty()) << "a refused sample says nothing about the sector's chain";
    EXPECT_EQ(intake.take(whole(kWest, 6, west), 6, kFramesAhead), Taken::queued);
    intake.applied(6);
    EXPECT_EQ(intake.take(whole(kWest, 4, 0), 6, kFramesAhead), Taken::stale) << "older than what is held";
    EXPECT_TRUE(intake.through(10).empty());
    EXPECT_TRUE(intake.whole_due().empty());
}

TEST(SampleIntake, SamplesAreQueuedByFrameUntilApplied) {
    SampleIntake intake("test", "tester", true);
    intake.learn(assignment(1, 1));
    const std::uint32_t west = assignment(1, 1).owner_of(kWest);
    const std::uint32_t east = assignment(1, 1).owner_of(kEast);
    EXPECT_EQ(intake.take(whole(kEast, 8, east), 7, kFramesAhead), Taken::queued);  // a faster writer
    EXPECT_EQ(intake.take(whole(kWest, 7, west), 7, kFramesAhead), Taken::queued);
    EXPECT_EQ(intake.take(partial(kWest, 8, 7, west), 7, kFramesAhead), Taken::queued);
    EXPECT_EQ(frames_of(intake.through(7)), (std::vector<std::uint64_t>{7})) << "no frame's future leaks in";
    EXPECT_EQ(frames_of(intake.through(8)), (std::vector<std::uint64_t>{7, 8, 8}));
    ASSERT_NE(intake.of_frame(8), nullptr);
    EXPECT_EQ(intake.of_frame(8)->size(), 2u);
    EXPECT_EQ(intake.take_received_bytes(7), wire::SectorFrame::getCdrSerializedSize(whole(kWest, 7, west)));
    EXPECT_EQ(intake.take_received_bytes(7), 0u) << "taken once";
    intake.drop_queued(8, [](const wire::SectorFrame& f) { return from_wire(f.sector()) == kEast; });
    EXPECT_EQ(frames_of(intake.through(8)), (std::vector<std::uint64_t>{7, 8}));
    intake.applied(7);
    EXPECT_EQ(frames_of(intake.through(8)), (std::vector<std::uint64_t>{8}));
    EXPECT_EQ(intake.of_frame(7), nullptr);
}

TEST(SampleIntake, RequestsForWholeSectorsNameTheAskerAndCountOn) {
    SampleIntake intake("test", "lpss-worker-9");
    std::uint64_t next = 5;  // a client numbers its inventory requests with the same counter
    EXPECT_FALSE(intake.whole_request(next)) << "nothing wanted";
    EXPECT_EQ(next, 5u);
    intake.want_whole(kEast);
    intake.want_whole(kWest);
    const std::optional<wire::SectorRequest> request = intake.whole_request(next);
    ASSERT_TRUE(request);
    EXPECT_EQ(request->reader(), "lpss-worker-9");
    EXPECT_EQ(request->request(), 5u);
    EXPECT_EQ(request->sectors().size(), 2u);
    EXPECT_FALSE(request->inventory());
    EXPECT_EQ(next, 6u);
    EXPECT_FALSE(intake.whole_request(next)) << "asked again only after 100 ms";
    EXPECT_EQ(intake.take_received_bytes(0), 0u);
    EXPECT_EQ(intake.take(whole(kWest, 1, 1), 1, kFramesAhead), Taken::queued);
    EXPECT_EQ(intake.take_received_bytes(1), 0u) << "bytes are counted only if asked for";
}

TEST(SampleIntake, WhatTheReaderWroteItselfCarriesItsChain) {
    // The coordinator writes the world's first state, and a gone worker's sectors, itself: the workers'
    // partial samples that follow are based on those.
    SampleIntake intake("test", "tester");
    intake.wrote(whole(kWest, 4, 0));
    EXPECT_TRUE(intake.through(4).empty()) << "not queued: the reader holds it already";
    EXPECT_EQ(intake.take(partial(kWest, 6, 4, 1), 6, kFramesAhead), Taken::queued);
}

TEST(SampleIntake, ASampleOfAnUnknownEpochIsGivenBackWhenItsAssignmentComes) {
    SampleIntake intake("test", "tester");
    intake.learn(assignment(1, 1));
    const std::uint32_t west = assignment(2, 9).owner_of(kWest);
    EXPECT_EQ(intake.take(whole(kWest, 9, west, 2), 8, kFramesAhead), Taken::refused);
    EXPECT_TRUE(intake.through(9).empty());
    std::vector<wire::SectorFrame> again = intake.learn(assignment(2, 9));
    ASSERT_EQ(again.size(), 1u);
    EXPECT_EQ(intake.take(std::move(again[0]), 8, kFramesAhead), Taken::queued);
    EXPECT_EQ(intake.refused(), 0u) << "held, not refused for good";
}

TEST(SampleIntake, StartingOverForgetsTheQueueAndRefusesHistory) {
    SampleIntake intake("test", "tester");
    EXPECT_EQ(intake.take(whole(kWest, 3, 1), 3, kFramesAhead), Taken::queued);
    EXPECT_EQ(intake.take(partial(kEast, 3, 2, 1), 3, kFramesAhead), Taken::without_base);
    intake.start_over(20);
    EXPECT_TRUE(intake.through(100).empty());
    EXPECT_TRUE(intake.whole_due().empty());
    EXPECT_EQ(intake.take(whole(kWest, 19, 1), 20, kFramesAhead), Taken::refused) << "before the floor";
    EXPECT_EQ(intake.take(whole(kWest, 20, 1), 20, kFramesAhead), Taken::queued);
}

}  // namespace
}  // namespace lpss::dds
