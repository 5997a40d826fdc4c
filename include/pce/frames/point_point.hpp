// SPDX-License-Identifier: MIT
/// @file
/// Point-point pair `x = (p, q)` (6 coordinates): the distance `d = |p − q|`, the norm of
/// a one-edge frame `c = e = p − q = J x` with `J = (1, −1) ⊗ I3` (`docs/math.md` §9).
/// `J`'s rows are orthogonal, so for this kind the frame-space clamp *is* the x-space
/// projection. `d` is unsigned: this kind has no side.
#pragma once

#include <pce/frames/frame.hpp>

#include <cmath>

namespace pce {

template <class Scalar> struct PointPointEnergy;

/// Frame of a point-point pair: the unit direction and the distance, plus two unit vectors
/// completing a right-handed orthonormal basis `(u, v, w)` (for the eigenvectors).
template <class Scalar> struct PointPointFrame {
  Vec3<Scalar> u;  ///< û = (p − q)/d
  Vec3<Scalar> v;  ///< a unit vector orthogonal to û
  Vec3<Scalar> w;  ///< û × v̂
  Scalar d;        ///< |p − q|
};

/// Tag type for the point-point pair kind.
struct PointPoint {
  /// The kind's name, as `pce-probe` and the tests spell it.
  static constexpr const char* name = "point_point";
  static constexpr int dofs = 6;        ///< coordinates: p, q
  static constexpr int frame_dofs = 3;  ///< frame coordinates (e = p − q)
  /// The evaluated energy of this kind (`energy/point_point_energy.hpp`).
  template <class Scalar> using Energy = PointPointEnergy<Scalar>;

  /// Builds the frame of `x = (p, q)`: `invalid_input` for non-finite or absurd
  /// coordinates, `degenerate` for coincident points (d = 0: no direction). On failure
  /// `f` is untouched.
  template <class Scalar> PCE_HOST_DEVICE static Status frame(const Vec6<Scalar>& x, PointPointFrame<Scalar>& f) {
    using std::abs;
    using std::sqrt;
    if (!detail::coordinates_valid(x)) return Status::invalid_input;
    const Vec3<Scalar> e = x.template segment<3>(0) - x.template segment<3>(3);
    const Scalar big = e.cwiseAbs().maxCoeff();
    if (!(big > Scalar(0))) return Status::degenerate;
    const detail::PowerOfTwoScale<Scalar> sc(big);
    const Vec3<Scalar> E = sc.down(e);
    const Scalar dn = sqrt(E.squaredNorm());
    f.u = E / dn;
    f.d = sc.up(dn);
    // v: û crossed with the axis it is least aligned with, normalised.
    int axis = 0;
    for (int i = 1; i < 3; ++i)
      if (abs(f.u[i]) < abs(f.u[axis])) axis = i;
    const Vec3<Scalar> c = f.u.cross(Vec3<Scalar>::Unit(axis));
    f.v = c / sqrt(c.squaredNorm());
    f.w = f.u.cross(f.v);
    return Status::ok;
  }
};

}  // namespace pce
