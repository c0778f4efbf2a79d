// LockedKeyType: a type's keys computed from two threads at once, as a participant's writer and reader of
// one topic do, each come out as its own sample's key.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "lpssPubSubTypes.h"
#include "lpss_dds/participant.hpp"

namespace lpss::dds {
namespace {

/// Computes the key of a sample of worker `worker` again and again; counts those that came out as another's.
template <class Type>
void compute_keys(Type& type, std::uint32_t worker, int times, std::atomic<int>& wrong) {
    wire::SectorFrame sample;
    sample.worker(worker);
    sample.slot(0);
    for (int n = 0; n < times; ++n) {
        eprosima::fastrtps::rtps::InstanceHandle_t handle;
        type.getKey(&sample, &handle, false);
        // Big-endian CDR of the key: the worker's id in the first four bytes.
        const std::uint32_t got = (std::uint32_t{handle.value[0]} << 24) |
                                  (std::uint32_t{handle.value[1]} << 16) |
                                  (std::uint32_t{handle.value[2]} << 8) | std::uint32_t{handle.value[3]};
        if (got != worker) wrong.fetch_add(1);
    }
}

template <class Type>
int wrong_keys_from_two_threads() {
    Type type;
    std::atomic<int> wrong{0};
    constexpr int kTimes = 2'000'000;
    std::thread a([&] { compute_keys(type, 1, kTimes, wrong); });
    std::thread b([&] { compute_keys(type, 2, kTimes, wrong); });
    a.join();
    b.join();
    return wrong.load();
}

TEST(LockedKeyType, KeysComputedFromTwoThreadsAtOnceAreEachTheirSamples) {
    EXPECT_EQ(wrong_keys_from_two_threads<LockedKeyType<wire::SectorFramePubSubType>>(), 0);
}

}  // namespace
}  // namespace lpss::dds
