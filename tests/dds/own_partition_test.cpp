// The partitions that keep a process's own sector samples from its own sector reader (own_partition.hpp):
// its readers' patterns match every other participant's partition and not its own. On the wire:
// Wire.ASectorReaderGetsEveryOtherProcesssSamplesAndNotItsOwn.
#include <gtest/gtest.h>

#include <fastrtps/utils/StringMatching.h>

#include <random>

#include "lpss_dds/own_partition.hpp"

namespace lpss::dds {
namespace {

/// Whether a reader subscribed to `patterns` matches a writer publishing in `name`, as Fast DDS decides it.
bool matches(const std::vector<std::string>& patterns, const std::string& name) {
    for (const std::string& pattern : patterns) {
        if (eprosima::fastrtps::rtps::StringMatching::matchString(pattern.c_str(), name.c_str())) return true;
    }
    return false;
}

TEST(OwnPartition, ItsPatternsMatchEveryOtherParticipantsPartitionAndNotItsOwn) {
    std::mt19937_64 random(17);
    for (int round = 0; round < 200; ++round) {
        std::array<std::uint8_t, 12> self{};
        for (auto& byte : self)
            byte = static_cast<std::uint8_t>(random());
        const std::string own = own_partition(self);
        ASSERT_EQ(own.size(), std::string("lpss-from-").size() + 24);
        const std::vector<std::string> others = every_own_partition_but(own);
        EXPECT_FALSE(matches(others, own)) << own;
        EXPECT_FALSE(matches(others, "")) << "the default partition, where its own writer also publishes";
        // Participants of the same host and process share most of their prefix: one byte off anywhere.
        for (std::size_t n = 0; n < self.size(); ++n) {
            for (int change : {1, 16, 255}) {
                std::array<std::uint8_t, 12> other = self;
                other[n] = static_cast<std::uint8_t>(other[n] + change);
                EXPECT_TRUE(matches(others, own_partition(other)))
                    << own << " against " << own_partition(other);
            }
        }
        std::array<std::uint8_t, 12> stranger{};
        for (auto& byte : stranger)
            byte = static_cast<std::uint8_t>(random());
        if (stranger != self) {
            EXPECT_TRUE(matches(others, own_partition(stranger)));
        }
    }
}

}  // namespace
}  // namespace lpss::dds
