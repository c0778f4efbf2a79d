// One Bullet collision configuration shared by every sector of a world, safe to use from several
// threads at once.
//
// Why: a default btDefaultCollisionConfiguration preallocates pools of 4096 manifolds and 4096
// collision algorithms (about 4 MiB), which makes a sector cost megabytes; and Debian's Bullet is built
// without BT_THREADSAFE, so those pools are unsynchronised and cannot be shared between sectors stepped
// in parallel. Here both pools are drained at construction: every later allocation finds them empty
// and falls back to btAlignedAlloc (malloc, thread-safe), and the pools' state is only ever read. The
// rest of the configuration (collision algorithm factories, the penetration depth solver) holds no
// mutable state, so sharing it is safe.
#pragma once

#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <LinearMath/btPoolAllocator.h>

namespace lpss::engine {

class SharedCollisionConfiguration {
public:
    SharedCollisionConfiguration();
    ~SharedCollisionConfiguration();
    SharedCollisionConfiguration(const SharedCollisionConfiguration&) = delete;
    SharedCollisionConfiguration& operator=(const SharedCollisionConfiguration&) = delete;

    btCollisionConfiguration* get() { return &configuration_; }

private:
    // Each pool holds one element, taken at construction and given back at destruction.
    btPoolAllocator manifold_pool_;
    btPoolAllocator algorithm_pool_;
    void* manifold_slot_;
    void* algorithm_slot_;
    btDefaultCollisionConfiguration configuration_;
};

}  // namespace lpss::engine
