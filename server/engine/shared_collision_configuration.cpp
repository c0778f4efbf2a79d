#include "shared_collision_configuration.hpp"

#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>

namespace lpss::engine {
namespace {

btDefaultCollisionConstructionInfo drained_pools(btPoolAllocator* manifolds, btPoolAllocator* algorithms) {
    btDefaultCollisionConstructionInfo info;
    info.m_persistentManifoldPool = manifolds;
    info.m_collisionAlgorithmPool = algorithms;
    return info;
}

}  // namespace

SharedCollisionConfiguration::SharedCollisionConfiguration()
    : manifold_pool_(sizeof(btPersistentManifold), 1),
      algorithm_pool_(16, 1),
      manifold_slot_(manifold_pool_.allocate(sizeof(btPersistentManifold))),
      algorithm_slot_(algorithm_pool_.allocate(16)),
      configuration_(drained_pools(&manifold_pool_, &algorithm_pool_)) {}

SharedCollisionConfiguration::~SharedCollisionConfiguration() {
    manifold_pool_.freeMemory(manifold_slot_);
    algorithm_pool_.freeMemory(algorithm_slot_);
}

}  // namespace lpss::engine
