// Removing the shared-memory files that Fast DDS leaves in /dev/shm when a process dies without closing
// its participant (SIGKILL, a crash): a test suite or a cluster that has stopped should leave the machine
// as it found it.
#pragma once

#include <cstddef>

namespace lpss::dds {

/// Removes Fast DDS's abandoned shared-memory files: every participant segment whose lock no live process
/// holds, and the port files of `domain` that no live process maps. Files still in use are left alone, so
/// this is safe while other programs run. Returns how many files it removed.
std::size_t remove_abandoned_shm(int domain);

}  // namespace lpss::dds
