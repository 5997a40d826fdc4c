// SPDX-License-Identifier: MIT
/// @file
/// FCL's distance from a point to an obstacle's shape, by libccd's GJK: the independent
/// reference the closed forms of `surface_distance` are tested against. Not used by the
/// simulation itself.
#pragma once

#include <pce/sim/obstacle.hpp>

#include <Eigen/Geometry>

namespace pce::sim {

/// Distance from the world point `p` to obstacle `o` (sphere, box or capsule) at `pose`,
/// through `fcl::distance` with `gjk_solver_type = GST_LIBCCD` and a distance tolerance
/// of 1e-12. The point is a zero-size `fcl::Box` and the sphere an `fcl::Ellipsoid` with
/// equal radii, so every pair takes libccd's GJK path (FCL 0.7 answers sphere–box,
/// sphere–capsule and sphere–sphere with its own closed forms instead).
/// @note Meaningful for points outside the shape only: inside, FCL reports 0 or a
/// penetration depth by another algorithm. Throws std::invalid_argument for a mesh.
double fcl_point_distance(const Obstacle& o, const Eigen::Isometry3d& pose, const Eigen::Vector3d& p);

}  // namespace pce::sim
