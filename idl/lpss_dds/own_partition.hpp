// The partitions that keep a process's own sector samples out of its own sector reader. Fast DDS 2.9 (it has
// no ignore_local_endpoints) matches a participant's reader with its own writer of the same topic and hands
// it every sample written, in the writer's thread (intraprocess delivery), only for the reader to drop it: a
// worker's own samples (perf: 6% of its time, on the frame's path), the coordinator's first state (the whole
// world, taken and dropped by its own reader). Sector writers publish in the default partition and in their
// participant's own one; sector readers of workers and coordinators subscribe to every partition of that
// form but their own, and not to the default one. Every other reader (clients, another vendor's) keeps the
// default partition and matches every writer as before.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace lpss::dds {

/// A participant's own partition: "lpss-from-" and its GUID prefix in hex (24 digits, unique to it).
std::string own_partition(const std::array<std::uint8_t, 12>& guid_prefix);

/// Patterns (fnmatch, as Fast DDS matches partitions) that match every own partition but `own`: one for each
/// digit of it, matching the names that agree with it before that digit and differ there.
std::vector<std::string> every_own_partition_but(const std::string& own);

}  // namespace lpss::dds
