// A sector sample is taken in only from the worker that owns its sector under the assignment in force at
// its frame, written under that assignment's epoch; a sample of an epoch not yet known waits for it.
#include "lpss_dds/sample_owners.hpp"

#include <gtest/gtest.h>

#include "lpss_dds/convert.hpp"
#include "two_sector_samples.hpp"

namespace lpss::dds {
namespace {

using testing::kEast;
using testing::kWest;

SectorAssignment assignment(std::uint32_t epoch, std::uint64_t from_frame) {
    return testing::two_sector_assignment(epoch, from_frame);
}

wire::SectorFrame sample(const SectorKey& key, std::uint64_t frame, std::uint32_t worker,
                         std::uint32_t epoch) {
    return testing::empty_sample(key, frame, worker, epoch);
}

TEST(SampleOwners, OnlyTheOwnerUnderTheEpochInForceIsTakenIn) {
    SampleOwners owners;
    RefusedSamples refused("test");
    EXPECT_TRUE(owners.admit(sample(kWest, 5, 7, 1), refused)) << "nothing known yet: not judged";
    EXPECT_TRUE(owners.learn(assignment(1, 1)).empty());
    const std::uint32_t west = assignment(1, 1).owner_of(kWest);
    const std::uint32_t east = assignment(1, 1).owner_of(kEast);
    ASSERT_NE(west, east);
    EXPECT_TRUE(owners.admit(sample(kWest, 5, west, 1), refused));
    EXPECT_FALSE(owners.admit(sample(kWest, 5, east, 1), refused)) << "not its sector";
    EXPECT_FALSE(owners.admit(sample(kWest, 5, 7, 1), refused)) << "no such worker";
    EXPECT_FALSE(owners.admit(sample(kWest, 5, west, 0), refused)) << "an older epoch";
    EXPECT_TRUE(owners.admit(sample(kEast, 5, 0, 0), refused)) << "the coordinator's own";
    EXPECT_EQ(refused.count(), 3u);
}

TEST(SampleOwners, ASampleOfAnEpochNotYetKnownWaitsForItsWord) {
    SampleOwners owners;
    RefusedSamples refused("test");
    owners.learn(assignment(1, 1));
    const std::uint32_t west = assignment(2, 40).owner_of(kWest);
    EXPECT_FALSE(owners.admit(sample(kWest, 40, west, 2), refused));
    EXPECT_FALSE(owners.admit(sample(kWest, 40, west, 9), refused));
    EXPECT_EQ(owners.held(), 2u);
    EXPECT_EQ(refused.count(), 0u);
    const std::vector<wire::SectorFrame> again = owners.learn(assignment(2, 40));
    ASSERT_EQ(again.size(), 2u) << "offered again once an assignment comes";
    EXPECT_TRUE(owners.admit(again[0], refused));
    EXPECT_FALSE(owners.admit(again[1], refused)) << "epoch 9 is still unknown: held again";
    owners.applied(39, refused);
    EXPECT_EQ(owners.held(), 1u) << "held until its own frame is applied";
    owners.applied(40, refused);
    EXPECT_EQ(owners.held(), 0u);
    EXPECT_EQ(refused.count(), 1u) << "its epoch never came";
    EXPECT_FALSE(owners.admit(sample(kWest, 39, west, 2), refused)) << "epoch 2 is in force only from 40";
}

TEST(SampleOwners, AnAssignmentDroppedBeforeItCameIntoForceIsForgotten) {
    // The coordinator announced epoch 2 from frame 100, then a worker went at frame 49: epoch 3 from 50
    // replaces it. Samples of frame 120 are under epoch 3.
    SampleOwners owners;
    RefusedSamples refused("test");
    owners.learn(assignment(1, 1));
    owners.learn(assignment(2, 100));
    owners.learn(assignment(3, 50));
    ASSERT_NE(owners.in_force(120), nullptr);
    EXPECT_EQ(owners.in_force(120)->epoch, 3u);
    const std::uint32_t west = assignment(3, 50).owner_of(kWest);
    EXPECT_TRUE(owners.admit(sample(kWest, 120, west, 3), refused));
    EXPECT_FALSE(owners.admit(sample(kWest, 120, west, 2), refused));
}

TEST(SampleOwners, WhatCannotBeJudgedIsLetThrough) {
    SampleOwners owners;
    RefusedSamples refused("test");
    owners.learn(assignment(1, 100));
    owners.learn(assignment(3, 200));
    const std::uint32_t west = assignment(1, 1).owner_of(kWest);
    EXPECT_TRUE(owners.admit(sample(kWest, 50, 7, 0), refused)) << "before every assignment known";
    EXPECT_TRUE(owners.admit(sample(kWest, 150, west, 2), refused)) << "an assignment this reader missed";
    EXPECT_EQ(refused.count(), 0u);
}

TEST(SampleOwners, HoldsABoundedNumberOfSamples) {
    SampleOwners owners;
    RefusedSamples refused("test");
    owners.learn(assignment(1, 1));
    for (std::size_t n = 0; n < SampleOwners::kMostHeld + 10; ++n)
        owners.admit(sample(kWest, 5, 1, 1000), refused);
    EXPECT_EQ(owners.held(), SampleOwners::kMostHeld);
    EXPECT_EQ(refused.count(), 10u);
}

}  // namespace
}  // namespace lpss::dds
