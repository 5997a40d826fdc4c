// SPDX-License-Identifier: MIT
/// @file
/// The signed length's frame derivatives and their closed-form eigensystem
/// (Shi & Kim 2023, Sec. 4.2–4.3; supplement Eqs. 13, 19, 22, 30, 32, 37 and Sec. 2).
///
/// At the reduced frame, with the orthonormal basis (ê0, ê1, n̂):
///
///     ∂l/∂c = (0, 0, n̂)                                  (supplement Eq. 13)
///     H_l[e0,e0] = −(l/|e0|²) n̂n̂ᵀ,  H_l[e1⊥,e1⊥] = −(l/|e1⊥|²) n̂n̂ᵀ   (Eqs. 30, 32)
///     H_l[e0,e2⊥] = −n̂ ê0ᵀ/|e0|,    H_l[e1⊥,e2⊥] = −n̂ ê1ᵀ/|e1⊥|     (Eqs. 19, 22)
///     all other blocks zero                                (Eqs. 16, 37)
///
/// so H_l splits into two 2×2 families, k = 0, 1, on the basis (n̂ in slot k, ê_k in slot 2):
///
///     B_k = [[−l/a_k², −1/a_k], [−1/a_k, 0]],   a_0 = |e0|, a_1 = |e1⊥|.
///
/// We evaluate its eigenpairs in the cancellation-free form of `docs/math.md` (§ Eigenpairs):
/// with t = l/(2a), ρ = |t| + √(1+t²), w = 1/ρ and s = sgn(l) (s = +1 at l = 0),
///
///     λ_big = −s ρ / a,   q_big ∝ (s, w);     λ_small = s w / a,   q_small ∝ (w, −s).
///
/// These equal the paper's `λ = −l/(2a²)(1 ± √(1 + 4a²/|e2⊥|²))` but need no division by
/// |e2⊥| and are smooth through l = 0.
#pragma once

#include <pce/frames/frame.hpp>

#include <utility>
#include <array>
#include <cmath>

namespace pce {

/// Eigenpairs of one 2×2 family `B_k` (see the file comment). Vectors are unit 2-vectors
/// in the basis (n̂ in frame slot k, ê_k in frame slot 2):
/// `q_big = (s, w)/√(1+w²)`, `q_small = (w, −s)/√(1+w²)`.
template <class Scalar> struct LengthFamily {
  ///@{
  Scalar lambda_big, lambda_small;  ///< λ_big·λ_small = −1/a², |λ_big| ≥ 1/a ≥ |λ_small|
  ///@}
  Scalar s;   ///< sgn(l), +1 at l = 0
  Scalar w;   ///< w = 1/ρ ∈ (0, 1]
  Scalar n2;  ///< 1/(1 + w²), the squared normalisation of both vectors

  /// `q_big = (s, w)/√(1+w²)`, the unit eigenvector of λ_big.
  PCE_HOST_DEVICE Eigen::Matrix<Scalar, 2, 1> big() const {
    using std::sqrt;
    const Scalar c = sqrt(n2);
    return {s * c, w * c};
  }
  /// `q_small = (w, −s)/√(1+w²)`, the unit eigenvector of λ_small.
  PCE_HOST_DEVICE Eigen::Matrix<Scalar, 2, 1> small() const {
    using std::sqrt;
    const Scalar c = sqrt(n2);
    return {w * c, -s * c};
  }
};

/// Closed-form eigenpairs of `B = [[−l/a², −1/a], [−1/a, 0]]` (supplement Sec. 2, in the
/// stable form of `docs/math.md` (M16)–(M17)). Requires a > 0.
template <class Scalar> PCE_HOST_DEVICE LengthFamily<Scalar> length_family(const Scalar& l, const Scalar& a) {
  using std::abs;
  using std::sqrt;
  const Scalar s = detail::sign_nonneg(l);
  const Scalar t = abs(l / a) / Scalar(2);
  // sqrt(1 + t²) without overflow: beyond 1/sqrt(eps) it rounds to t anyway.
  const Scalar h = t < Scalar(1) / sqrt(Constants<Scalar>::epsilon()) ? Scalar(sqrt(Scalar(1) + t * t)) : t;
  const Scalar rho = t + h;
  LengthFamily<Scalar> r;
  r.s = s;
  r.w = Scalar(1) / rho;
  r.n2 = Scalar(1) / (Scalar(1) + r.w * r.w);
  r.lambda_big = -s * rho / a;
  r.lambda_small = s * r.w / a;
  return r;
}

/// A symmetric eigensystem in frame space (9-dimensional for the plane kinds, 6 for
/// point-edge, 3 for point-point): `values` ascending, `vectors` the matching orthonormal
/// columns.
template <class Scalar, int N = 9> struct FrameEigensystem {
  /// Eigenvalues, ascending.
  VecN<Scalar, N> values;
  /// Column i is the unit eigenvector of `values(i)`.
  MatN<Scalar, N> vectors;
};

namespace detail {
/// Sorts `n` eigenpairs ascending (insertion sort: stable, no allocation).
template <class Scalar, int N>
PCE_HOST_DEVICE FrameEigensystem<Scalar, N> sorted_eigensystem(const std::array<Scalar, N>& val,
                                                               const std::array<VecN<Scalar, N>, N>& vec) {
  std::array<int, N> order;
  for (int i = 0; i < N; ++i) order[i] = i;
  for (int i = 1; i < N; ++i)
    for (int j = i; j > 0 && val[order[j]] < val[order[j - 1]]; --j) Eigen::numext::swap(order[j], order[j - 1]);
  FrameEigensystem<Scalar, N> out;
  for (int i = 0; i < N; ++i) {
    out.values[i] = val[order[i]];
    out.vectors.col(i) = vec[order[i]];
  }
  return out;
}
}  // namespace detail

namespace detail {

/// Eigensystem of the frame-space matrix `c2 ggᵀ + c1 H_l` (g = (0,0,n̂)): the pair
/// (c2, g), the four pairs (c1 λ, q) of the families, and four zeros (in-plane directions
/// of slots 0 and 1). `c1 = σψ′`, `c2 = ψ″` for an energy; `c1 = σ`, `c2 = 0` for a length.
template <class Scalar>
PCE_HOST_DEVICE FrameEigensystem<Scalar> frame_eigensystem(const Frame<Scalar>& f, const Scalar& c1, const Scalar& c2) {
  const LengthFamily<Scalar> F[2] = {length_family(f.l, f.a0), length_family(f.l, f.a1)};
  const Vec3<Scalar>* tk[2] = {&f.t0, &f.t1};
  std::array<Scalar, 9> val;
  std::array<Vec9<Scalar>, 9> vec;
  for (auto& v : vec) v.setZero();
  val[0] = c2;
  vec[0].template segment<3>(6) = f.n;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Matrix<Scalar, 2, 1> qb = F[k].big(), qs = F[k].small();
    val[1 + 2 * k] = c1 * F[k].lambda_big;
    vec[1 + 2 * k].template segment<3>(3 * k) = qb[0] * f.n;
    vec[1 + 2 * k].template segment<3>(6) = qb[1] * *tk[k];
    val[2 + 2 * k] = c1 * F[k].lambda_small;
    vec[2 + 2 * k].template segment<3>(3 * k) = qs[0] * f.n;
    vec[2 + 2 * k].template segment<3>(6) = qs[1] * *tk[k];
  }
  for (int k = 0; k < 2; ++k) {
    val[5 + 2 * k] = Scalar(0);
    vec[5 + 2 * k].template segment<3>(3 * k) = f.t0;
    val[6 + 2 * k] = Scalar(0);
    vec[6 + 2 * k].template segment<3>(3 * k) = f.t1;
  }
  return sorted_eigensystem<Scalar, 9>(val, vec);
}

/// Blocks of `c2 ggᵀ + c1 H_l` with exact zeros where H_l has them (`docs/stability.md`).
template <class Scalar>
PCE_HOST_DEVICE FrameBlocks<Scalar> frame_hessian_blocks(const Frame<Scalar>& f, const Scalar& c1, const Scalar& c2) {
  FrameBlocks<Scalar> b;
  const Mat3<Scalar> nn = f.n * f.n.transpose();
  b.h00 = (-c1 * ((f.l / f.a0) / f.a0)) * nn;
  b.h11 = (-c1 * ((f.l / f.a1) / f.a1)) * nn;
  b.h22 = c2 * nn;
  b.h02 = (-c1 / f.a0) * (f.n * f.t0.transpose());
  b.h12 = (-c1 / f.a1) * (f.n * f.t1.transpose());
  return b;
}

}  // namespace detail
}  // namespace pce
