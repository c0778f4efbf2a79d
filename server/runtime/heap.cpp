#include "heap.hpp"

#include <malloc.h>

namespace lpss::runtime {

void keep_large_buffers_apart() {
    // Setting the threshold also turns off glibc's raising it on its own.
    mallopt(M_MMAP_THRESHOLD, 256 * 1024);
}

void give_back_free_memory() { malloc_trim(0); }

}  // namespace lpss::runtime
