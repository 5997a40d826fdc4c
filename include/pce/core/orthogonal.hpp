// SPDX-License-Identifier: MIT
/// @file
/// A unit vector orthogonal to a given one, chosen deterministically: the completion of a
/// basis where any completion will do (a flat element's singular vectors, a straight strand's
/// binormal).
#pragma once

#include <pce/core/types.hpp>

#include <Eigen/Geometry>

namespace pce {

/// A unit vector orthogonal to the unit vector `u`: `u × e_k` normalised, with e_k the axis of
/// u's smallest component (the first such), so that the cross product is far from zero.
template <class Scalar> PCE_HOST_DEVICE Vec3<Scalar> any_orthogonal(const Vec3<Scalar>& u) {
  Eigen::Index k;
  u.cwiseAbs().minCoeff(&k);
  return u.cross(Vec3<Scalar>::Unit(k)).normalized();
}

}  // namespace pce
