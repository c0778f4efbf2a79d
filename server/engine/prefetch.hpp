// Asking for memory a walk will read a few steps later. The engine's walks go from body records to partner
// and clone lists to Bullet objects, each its own heap block, so the hardware cannot guess the next
// address; a walk that knows it asks ahead and waits less (cloning.cpp measures it).
#pragma once

namespace lpss::engine {

/// Asks for the cache line holding `address`, to be read soon. A hint only: any address may be passed.
inline void prefetch(const void* address) { __builtin_prefetch(address); }

}  // namespace lpss::engine
