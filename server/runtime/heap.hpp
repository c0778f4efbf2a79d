// The heap of a long-running server process (glibc's malloc). A worker and the coordinator build large
// short-lived buffers (a sector's samples, the world's first state); left to its defaults, glibc raises
// its mmap threshold after the first such buffer is freed, serves the later ones from the heap, and the
// process then keeps tens of megabytes it no longer uses (measured: two workers of the same world
// differing by 30 MB from one run to the next).
#pragma once

namespace lpss::runtime {

/// Large buffers (256 KiB and more) always get pages of their own, returned when freed.
void keep_large_buffers_apart();

/// Returns the heap's free pages to the system (after a burst of allocations, such as loading a world).
void give_back_free_memory();

}  // namespace lpss::runtime
