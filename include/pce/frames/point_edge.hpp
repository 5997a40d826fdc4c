// SPDX-License-Identifier: MIT
/// @file
/// Point-edge pair `x = (p, e0, e1)` (9 coordinates): the distance from `p` to the infinite
/// line through `e0`, `e1`. Its reduced frame has two edges, `c0 = e = e1 − e0` and
/// `c1 = r⊥ = r − β e` with `r = p − e0` and `β = r·e/|e|²` (one Gram–Schmidt step, as in
/// Shi & Kim 2023 Sec. 4.1), so the distance is the length of the second frame edge,
/// `d = |r⊥|`, and `c = J x` with `J = P ⊗ I3` for β held fixed (`docs/math.md` §9).
/// `d` is unsigned: this kind has no side.
#pragma once

#include <pce/frames/frame.hpp>

#include <cmath>
#include <limits>

namespace pce {

template <class Scalar> struct PointEdgeEnergy;

/// Reduced frame of a point-edge pair. All vectors are in world coordinates; `(t, u, n)`
/// is a right-handed orthonormal basis.
template <class Scalar> struct PointEdgeFrame {
  Eigen::Matrix<Scalar, 2, 3> P;  ///< c0 = e = Σ P(0,j) x_j,  c1 = r⊥ = Σ P(1,j) x_j
  Vec3<Scalar> t;                 ///< ê = e/|e|, along the edge
  Vec3<Scalar> u;                 ///< û = r⊥/d, from the line to the point
  Vec3<Scalar> n;                 ///< n̂ = (e × r)/|e × r| = t × u, normal to the plane of the three points
  Scalar d;                       ///< distance |r⊥| = |e × r|/|e|
  Scalar a;                       ///< edge length |e|
  Scalar beta;                    ///< β = r·e/|e|², the foot of p on the line is e0 + β e
};

/// Tag type for the point-edge pair kind.
struct PointEdge {
  /// The kind's name, as `pce-probe` and the tests spell it.
  static constexpr const char* name = "point_edge";
  static constexpr int dofs = 9;        ///< coordinates: p, e0, e1
  static constexpr int frame_dofs = 6;  ///< frame coordinates (e, r⊥)
  /// The evaluated energy of this kind (`energy/point_edge_energy.hpp`).
  template <class Scalar> using Energy = PointEdgeEnergy<Scalar>;

  /// Builds the reduced frame of `x = (p, e0, e1)`: `invalid_input` for non-finite or
  /// absurd coordinates, `degenerate` for a zero-length edge or a point on the line
  /// (d = 0 — exactly, or after underflow — where the distance has no direction), `overflow` when the point is beyond
  /// the scalar's range relative to the edge. On failure `f` is untouched.
  template <class Scalar> PCE_HOST_DEVICE static Status frame(const Vec9<Scalar>& x, PointEdgeFrame<Scalar>& f) {
    using std::sqrt;
    if (!detail::coordinates_valid(x)) return Status::invalid_input;
    const Vec3<Scalar> e = x.template segment<3>(6) - x.template segment<3>(3);
    const Vec3<Scalar> r = x.template segment<3>(0) - x.template segment<3>(3);
    // Exact power-of-two rescaling by the edge's size (as detail::make_frame).
    const Scalar big = e.cwiseAbs().maxCoeff();
    if (!(big > Scalar(0))) return Status::degenerate;
    const detail::PowerOfTwoScale<Scalar> sc(big);
    const Vec3<Scalar> E = sc.down(e), Rv = sc.down(r);
    const Scalar a = sqrt(E.squaredNorm());
    const Vec3<Scalar> m = E.cross(Rv);
    const Scalar mn = sqrt(m.squaredNorm());
    if (!detail::is_finite(mn)) return Status::overflow;
    if (!(mn > Scalar(0))) return Status::degenerate;
    const Vec3<Scalar> t = E / a;
    // n̂ = m/|m| is orthogonal to t̂ only to the rounding of m relative to |m|: O(1) off when
    // p is on the line to within rounding (found by the fuzzer). Gram-Schmidt against t̂,
    // twice ("twice is enough", Parlett, The Symmetric Eigenvalue Problem, Sec. 6.9), makes
    // (t̂, û, n̂) orthonormal to rounding whatever |m| is; it moves n̂ by no more than its own
    // error. (n̂ ∥ t̂ exactly, possible only for m of pure rounding, is `degenerate`.)
    Vec3<Scalar> n = m / mn;
    for (int pass = 0; pass < 2; ++pass) {  // the second only if the first lost over half the norm
      n -= n.dot(t) * t;
      const Scalar nn = sqrt(n.squaredNorm());
      if (!(nn > Scalar(0))) return Status::degenerate;
      n /= nn;
      if (nn > Scalar(0.5)) break;
    }
    const Scalar beta = t.dot(Rv) / a;
    const Scalar d = sc.up(Scalar(mn / a));
    if (!detail::is_finite(beta) || !detail::is_finite(d)) return Status::overflow;
    // The distance itself can underflow to 0 (a subnormal d over a long edge, found by the
    // fuzzer): the point is on the line as far as the scalar can tell.
    if (!(d > Scalar(0))) return Status::degenerate;
    f.P << Scalar(0), Scalar(-1), Scalar(1),  //
        Scalar(1), Scalar(-1) + beta, -beta;
    f.t = t;
    f.n = n;
    f.u = n.cross(t);
    f.d = d;
    f.a = sc.up(a);
    f.beta = beta;
    return Status::ok;
  }
};

}  // namespace pce
