// SPDX-License-Identifier: MIT
/// @file
/// Where the scene puts things and how they move (motion.cpp): a `rotation` object, a mesh's
/// `transform`, and a `motion` (constant velocities, or keyframes), read for meshes,
/// obstacles and pin groups. Internal.
#pragma once

#include "params.hpp"

#include <pce/sim/mesh.hpp>
#include <pce/sim/obstacle.hpp>

#include <Eigen/Core>

namespace pce::sim {

/// A `rotation` object, `{"axis": [x, y, z] (non-zero), "degrees": a}`, as a rotation matrix.
Eigen::Matrix3d parse_rotation(const Params& p);

/// A `transform` object: `translation` (a position), `rotation` and a uniform `scale` in
/// [1e-6, 1e6] (the transformed coordinates are checked against `kMaxCoordinate` by
/// `validate`).
Transform parse_transform(const Params& p);

/// A `motion` object: `velocity`, `angular_velocity`, `start` and `stop`, or `keyframes` and
/// `interpolation` (not both). The caller states with `only` which keys its motion allows.
Motion parse_motion(const Params& m);

}  // namespace pce::sim
