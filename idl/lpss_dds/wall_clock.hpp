// The system clock in nanoseconds since the epoch: what DDS source timestamps and FrameGo::started_ns are
// read against (SampleInfo::source_timestamp.to_ns()). One place, so that every comparison uses one clock.
#pragma once

#include <chrono>
#include <cstdint>

namespace lpss::dds {

inline std::int64_t wall_clock_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

}  // namespace lpss::dds
