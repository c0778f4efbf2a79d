// How much memory a process holds, as the kernel counts it (Linux /proc): for the programs' reports and
// the benchmarks that compare them.
#pragma once

#include <sys/types.h>
#include <cstdint>
#include <optional>

namespace lpss {

struct MemoryUse {
    std::uint64_t resident_bytes = 0;  ///< resident set size now (VmRSS)
    std::uint64_t peak_bytes = 0;      ///< the most it has held at once (VmHWM)
    std::uint64_t shared_bytes = 0;    ///< of the resident set, shared memory (RssShmem): DDS segments
                                       ///< that every process mapping them counts
};

/// The memory use of a process (this one by default), or nothing if it is gone or unreadable.
std::optional<MemoryUse> memory_use(pid_t pid = 0);

/// A process's resident set with each page that n processes share counted 1/n (Pss, /proc/PID/smaps_rollup):
/// summed over the processes of a cluster, what they cost the machine together, each library's code counted
/// once. The kernel walks every page to answer (17 ms for a process of 1.2 GB here): for reports, not per
/// frame. Nothing if the process is gone or the kernel does not say.
std::optional<std::uint64_t> proportional_resident_bytes(pid_t pid = 0);

}  // namespace lpss
