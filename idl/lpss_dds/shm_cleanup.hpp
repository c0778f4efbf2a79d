// Removing the shared-memory files that Fast DDS leaves in /dev/shm when a process dies without closing
// its participant (SIGKILL, a crash): a test suite or a cluster that has stopped should leave the machine
// as it found it.
#pragma once

#include <chrono>
#include <cstddef>

namespace lpss::dds {

/// Removes Fast DDS's abandoned shared-memory files: participant segments (of any domain) whose lock no
/// live process holds and that have not changed for `min_age`, and the port files of `domain` that no live
/// process maps. Call it for a domain whose participants (yours) have ended: a participant that starts
/// on `domain` while this runs could lose its port. Returns how many files it removed.
std::size_t remove_abandoned_shm(int domain, std::chrono::seconds min_age = std::chrono::seconds(10));

}  // namespace lpss::dds
