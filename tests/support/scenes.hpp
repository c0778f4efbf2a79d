// Scenes shared by the tests and the benchmarks: the paper's experiments, placed anywhere.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>

#include "lpss/common/body_snapshot.hpp"
#include "lpss/common/scene.hpp"

namespace lpss::scenes {

/// Where an experiment is centred: a double global position or an exact sector position.
using Centre = Placement;

/// The centre as an exact sector position on `grid` (global centres are converted).
SectorPosition centre_on(const SectorGrid& grid, const Centre& centre);

/// `centre` moved by `by` (in double for a global centre, in the local offset for a sector centre).
Centre shifted(const Centre& centre, const Eigen::Vector3d& by);

/// One body of each kind, placed at a centre.
BodyDesc box_body(BodyId id, const Eigen::Vector3d& half_extents, double mass, const Centre& at);
BodyDesc sphere_body(BodyId id, double radius, double mass, const Centre& at);
/// A static plane through `at` with the given normal.
BodyDesc ground_plane(BodyId id, const Centre& at, const Eigen::Vector3d& normal = Eigen::Vector3d::UnitY());

/// The paper's Figure 5: two unit spheres 4.1 apart along `axis`, at 2 units/s towards each other,
/// restitution 1, no friction, no gravity, no sleeping (ids 1 and 2; body 1 starts at -axis).
Scene sphere_pair(const Centre& centre, double sector_size,
                  const Eigen::Vector3d& axis = Eigen::Vector3d::UnitX());

/// Eight spheres in the eight octants around `centre`, moving towards it at 2 units/s (ids 1..8).
Scene sphere_octet(const Centre& centre, double sector_size);

/// The paper's Figure 8: `count` unit boxes stacked on a ground plane through `base` (normal +y), with
/// gravity -9.81 y. The plane has id 1000, the boxes ids 1..count from the bottom.
Scene box_stack(const Centre& base, int count, double sector_size);

/// A large world mostly at rest, for the cluster's scale benchmark: `resting` bodies of mixed shapes
/// (boxes, spheres, capsules, convex hulls, flat boxes) 3 units apart in a square grid on a ground plane
/// (id 1), starting asleep, over sectors of 64; and `moving` balls thrown across the middle of the grid,
/// above it, waking and pushing what they hit. The middle is the same at every size: the activity does not
/// grow with the world. Ids: the resting bodies from 2, then the balls.
Scene resting_world(std::size_t resting, std::size_t moving, std::uint64_t seed = 7);

/// Bodies (about 0.9 across: spheres and boxes in turn, ids from 1) in a 3D lattice 1.2 units apart from the
/// origin, drifting at up to 1 unit/s in random directions without gravity nor sleeping: they collide
/// within a second, and with sectors of 8 about half of them are near a border at any time, and they keep
/// crossing (the overhead benchmark's world, paper Figure 7).
Scene drifting_lattice(int count, double sector_size, std::uint64_t seed = 12345);

/// Position of a body relative to a centre, computed exactly from sector keys.
Eigen::Vector3d relative_position(const SectorGrid& grid, const BodySnapshot& body, const Centre& centre);

}  // namespace lpss::scenes
