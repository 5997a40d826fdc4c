// SPDX-License-Identifier: MIT
/// @file
/// The reduced frame of a pair (Shi & Kim 2023, Sec. 4.1; supplement Sec. 1): three
/// mutually orthogonal edges `c = (e0, e1⊥, e2⊥)` built from the pair's edge vectors
/// `e0, e1, e2` by one Gram–Schmidt sweep,
///
///     e1⊥ = e1 − α e0,   e2⊥ = e2 − β e0 − γ e1,
///
/// and the linear map `c = J x` (α, β, γ held fixed) that every derivative is pulled back
/// through. `J = P ⊗ I3` with a 3×4 coefficient matrix `P`, so `Jᵀ M J` is a weighted sum
/// of 3×3 blocks (see `pullback`). The pair kinds live in `vertex_face.hpp` and
/// `edge_edge.hpp`; both reduce to this one struct.
#pragma once

#include <pce/core/scaling.hpp>
#include <pce/core/types.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

namespace pce {

/// Reduced frame of one pair. All vectors are in world coordinates.
template <class Scalar> struct Frame {
  /// Frame coefficients: `e0 = Σ P(0,j) x_j`, `e1⊥ = Σ P(1,j) x_j`, `e2⊥ = Σ P(2,j) x_j`.
  Mat34<Scalar> P;
  Vec3<Scalar> n;   ///< n̂ = (e0 × e1)/|e0 × e1|, the unit normal; e2⊥ = l n̂
  Vec3<Scalar> t0;  ///< ê0 = e0/|e0|
  Vec3<Scalar> t1;  ///< ê1 = n̂ × ê0 = e1⊥/|e1⊥|; (ê0, ê1, n̂) is right-handed
  Scalar l;         ///< signed length l = e2·n̂ (paper Eq. 9 / supplement Eq. 9)
  Scalar a0;        ///< |e0|
  Scalar a1;        ///< |e1⊥| = |e0 × e1|/|e0|
  Scalar alpha;     ///< α = e0·e1/|e0|²
  Scalar beta;      ///< β = ((e2 × e1)·m)/|m|², m = e0 × e1
  Scalar gamma;     ///< γ = ((e0 × e2)·m)/|m|²
};

/// Frame-space Hessian (9×9 in the coordinates c = (e0, e1⊥, e2⊥)) stored as its only
/// possibly nonzero 3×3 blocks; the (0,1) block of every Hessian in this library is zero
/// (supplement Eq. 37), as are its transposes.
template <class Scalar> struct FrameBlocks {
  ///@{
  Mat3<Scalar> h00, h11, h22;  ///< diagonal blocks
  ///@}
  ///@{
  Mat3<Scalar> h02, h12;  ///< off-diagonal blocks; (2,0) and (2,1) are their transposes
  ///@}

  /// All five blocks zero.
  static FrameBlocks Zero() {
    FrameBlocks b;
    b.h00.setZero();
    b.h11.setZero();
    b.h22.setZero();
    b.h02.setZero();
    b.h12.setZero();
    return b;
  }
  /// The dense 9×9 matrix.
  Mat9<Scalar> dense() const {
    Mat9<Scalar> m = Mat9<Scalar>::Zero();
    m.template block<3, 3>(0, 0) = h00;
    m.template block<3, 3>(3, 3) = h11;
    m.template block<3, 3>(6, 6) = h22;
    m.template block<3, 3>(0, 6) = h02;
    m.template block<3, 3>(6, 0) = h02.transpose();
    m.template block<3, 3>(3, 6) = h12;
    m.template block<3, 3>(6, 3) = h12.transpose();
    return m;
  }
};

/// The frame Jacobian `J = ∂c/∂x` (9×12) with α, β, γ held fixed: `J = P ⊗ I3`.
template <class Scalar> Eigen::Matrix<Scalar, 9, 12> frame_jacobian(const Frame<Scalar>& f) {
  Eigen::Matrix<Scalar, 9, 12> J = Eigen::Matrix<Scalar, 9, 12>::Zero();
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j) J.template block<3, 3>(3 * k, 3 * j).diagonal().setConstant(f.P(k, j));
  return J;
}

namespace detail {
/// `r ⊗ d`: point `j` gets `r[j] d` (a frame direction `d` in slot k pulled back to the
/// coordinates is `P.row(k) ⊗ d`, i.e. `Jᵀ` of that slot vector).
template <class Scalar, class Row> VecN<Scalar, 3 * Row::SizeAtCompileTime> kron(const Row& r, const Vec3<Scalar>& d) {
  constexpr int n = Row::SizeAtCompileTime;
  VecN<Scalar, 3 * n> v;
  for (int j = 0; j < n; ++j) v.template segment<3>(3 * j) = r[j] * d;
  return v;
}

}  // namespace detail

/// Pull a frame-space gradient `gc` (9) back to the 12 coordinates: `Jᵀ gc`.
template <class Scalar> Vec12<Scalar> pullback(const Frame<Scalar>& f, const Vec9<Scalar>& gc) {
  Vec12<Scalar> g;
  for (int j = 0; j < 4; ++j)
    g.template segment<3>(3 * j) = f.P(0, j) * gc.template segment<3>(0) + f.P(1, j) * gc.template segment<3>(3) +
                                   f.P(2, j) * gc.template segment<3>(6);
  return g;
}

/// Pull a frame-space Hessian back to the 12 coordinates: `H = Jᵀ Hc J`, block (i, j):
/// `Σ_ab P(a,i) P(b,j) Hc(a,b)` over the five nonzero blocks. Symmetric by construction.
template <class Scalar> Mat12<Scalar> pullback(const Frame<Scalar>& f, const FrameBlocks<Scalar>& hc) {
  Mat12<Scalar> H;
  for (int i = 0; i < 4; ++i) {
    const Scalar p0i = f.P(0, i), p1i = f.P(1, i), p2i = f.P(2, i);
    for (int j = i; j < 4; ++j) {
      const Scalar p0j = f.P(0, j), p1j = f.P(1, j), p2j = f.P(2, j);
      Mat3<Scalar> b = (p0i * p0j) * hc.h00 + (p1i * p1j) * hc.h11 + (p2i * p2j) * hc.h22 + (p0i * p2j) * hc.h02 +
                       (p2i * p0j) * hc.h02.transpose() + (p1i * p2j) * hc.h12 + (p2i * p1j) * hc.h12.transpose();
      H.template block<3, 3>(3 * i, 3 * j) = b;
      if (j != i) H.template block<3, 3>(3 * j, 3 * i) = b.transpose();
    }
  }
  return H;
}

namespace detail {

/// Build the frame from the pair's edge vectors and the constant map `D` (rows: e0, e1, e2
/// as combinations of the four vertices). Uses the stable forms of
/// `docs/stability.md`: an exact power-of-two rescaling, β and γ from `m = e0 × e1`
/// rather than the Gram determinant, and `l = e2⊥·n̂` rather than `e2·n̂`.
/// Returns `degenerate` when `e0 × e1` vanishes (in the rescaled coordinates), `overflow`
/// when the third edge is beyond the scalar's range relative to the primitive; `f` is
/// written only on `ok`.
template <class Scalar> Status make_frame(const Vec3<Scalar>& e0, const Vec3<Scalar>& e1, const Vec3<Scalar>& e2,
                                          const Mat34<Scalar>& D, Frame<Scalar>& f) {
  using std::frexp;
  using std::ldexp;
  using std::sqrt;
  const Scalar big =
      (e0.cwiseAbs().maxCoeff() > e1.cwiseAbs().maxCoeff()) ? e0.cwiseAbs().maxCoeff() : e1.cwiseAbs().maxCoeff();
  if (!(big > Scalar(0))) return Status::degenerate;
  const PowerOfTwoScale<Scalar> sc(big);
  const Vec3<Scalar> E0 = sc.down(e0), E1 = sc.down(e1), E2 = sc.down(e2);
  const auto unscale = [&](const Scalar& v) -> Scalar { return sc.up(v); };

  const Vec3<Scalar> m = E0.cross(E1);
  const Scalar mn = sqrt(m.squaredNorm());
  const Scalar a0 = sqrt(E0.squaredNorm());
  if (!(mn > Scalar(0)) || !(a0 > Scalar(0))) return Status::degenerate;
  const Vec3<Scalar> n = m / mn;
  const Vec3<Scalar> t0 = E0 / a0;

  const Scalar alpha = t0.dot(E1) / a0;
  const Scalar beta = E2.cross(E1).dot(n) / mn;
  const Scalar gamma = E0.cross(E2).dot(n) / mn;
  const Scalar ls = (E2 - beta * E0 - gamma * E1).dot(n);
  const Scalar l = unscale(ls);
  // The third edge is rescaled by the primitive's scale; a vertex (or edge) farther away
  // than the scalar's range allows relative to a tiny primitive overflows here (found by
  // pce-fuzz: a 1e-33 triangle with its vertex at 1e6, in float), and so can the sum
  // beta + gamma in the third row of P (found next: a 1e-22 triangle, vertex at 3.6e16).
  if (!is_finite(alpha) || !is_finite(beta) || !is_finite(gamma) || !is_finite(l)) return Status::overflow;
  Mat34<Scalar> P;
  P.row(0) = D.row(0);
  P.row(1) = D.row(1) - alpha * D.row(0);
  P.row(2) = D.row(2) - beta * D.row(0) - gamma * D.row(1);
  if (!all_finite(P)) return Status::overflow;

  // The stored basis (t̂0, t̂1, n̂) must be orthonormal to rounding: the Hessians and the
  // exact projection use it as an orthonormal basis. n̂ = m/|m| is orthogonal to t̂0 only to
  // ε/sin θ (the rounding of m), O(1) off for angles below ε (found by pce-fuzz: exact and
  // numerical then differ by up to 100 %). Gram-Schmidt against t̂0, twice ("twice is
  // enough", Parlett, The Symmetric Eigenvalue Problem, Sec. 6.9); it moves n̂ by no more than
  // its own error, and α, β, γ, l above keep the plain m/|m|.
  Vec3<Scalar> nb = n;
  for (int pass = 0; pass < 2; ++pass) {  // the second only if the first lost over half the norm
    nb -= nb.dot(t0) * t0;
    const Scalar nn = sqrt(nb.squaredNorm());
    if (!(nn > Scalar(0))) return Status::degenerate;  // m ∥ e0: only for m of pure rounding
    nb /= nn;
    if (nn > Scalar(0.5)) break;
  }
  f.alpha = alpha;
  f.beta = beta;
  f.gamma = gamma;
  f.n = nb;
  f.t0 = t0;
  f.t1 = nb.cross(t0);
  f.l = l;
  f.a0 = unscale(a0);
  f.a1 = unscale(mn / a0);
  f.P = P;
  return Status::ok;
}

/// `invalid_input` unless every coordinate is finite and within `max_coordinate`.
template <class Scalar> Status check_coordinates(const Vec12<Scalar>& x) {
  return coordinates_valid(x) ? Status::ok : Status::invalid_input;
}

/// The frame of a pair whose edge vectors are `e_k = Σ_j D(k, j) x_j` (D has entries
/// 0, ±1, so each e_k is one exact-rounding difference of two vertices): checks the
/// coordinates, then `make_frame`. `f` is written only on `ok`.
template <class Scalar> Status frame_from_vertices(const Vec12<Scalar>& x, const Mat34<Scalar>& D, Frame<Scalar>& f) {
  const Status s = check_coordinates(x);
  if (s != Status::ok) return s;
  Vec3<Scalar> e[3];
  for (int k = 0; k < 3; ++k) {
    e[k].setZero();
    for (int j = 0; j < 4; ++j)
      if (D(k, j) != Scalar(0)) e[k] += D(k, j) * x.template segment<3>(3 * j);
  }
  return make_frame<Scalar>(e[0], e[1], e[2], D, f);
}

}  // namespace detail
}  // namespace pce
