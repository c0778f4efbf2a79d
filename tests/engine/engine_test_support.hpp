// Helpers for engine tests: run a scene, read final positions relative to where it was placed.
#pragma once

#include <gtest/gtest.h>

#include <map>

#include "lpss/engine/world.hpp"
#include "scenes.hpp"

namespace lpss::testing {

inline World make_world(const Scene& scene, const EngineOptions& options = {}) {
    Expected<World> world = World::create(scene, options);
    if (!world) ADD_FAILURE() << world.error().message;
    return std::move(world).value();
}

inline void run(World& world, int frames) {
    for (int f = 0; f < frames; ++f)
        world.step();
}

/// Final positions of every body relative to `centre`, by id.
inline std::map<BodyId, Eigen::Vector3d> relative_positions(const World& world,
                                                            const scenes::Centre& centre) {
    std::map<BodyId, Eigen::Vector3d> out;
    for (const BodySnapshot& b : world.snapshot()) {
        out[b.id] = scenes::relative_position(world.grid(), b, centre);
    }
    return out;
}

/// The paper's error: the sum over bodies of the distance between two runs' relative positions.
inline double summed_error(const std::map<BodyId, Eigen::Vector3d>& a,
                           const std::map<BodyId, Eigen::Vector3d>& b) {
    double error = 0.0;
    for (const auto& [id, p] : a)
        error += (p - b.at(id)).norm();
    return error;
}

}  // namespace lpss::testing
