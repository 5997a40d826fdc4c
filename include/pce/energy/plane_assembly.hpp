// SPDX-License-Identifier: MIT
/// @file
/// The plane kinds' 12×12 Hessians assembled from the rank-one and rank-two terms they are
/// (`docs/math.md` §6): with `w_k = P.row(k) ⊗ n̂` and `u_k = P.row(2) ⊗ ê_k`,
///
///     ∇²E      = ψ″ w₂w₂ᵀ + Σ_k [m_k w_k w_kᵀ + μ_k (w_k u_kᵀ + u_k w_kᵀ)]     (m_k = −σψ′l/a_k², μ_k = −σψ′/a_k)
///              = ψ″ w₂w₂ᵀ + Σ_k (w_k z_kᵀ + z_k w_kᵀ),   z_k = (m_k/2) w_k + μ_k u_k
///     analytic = f(ψ″) w₂w₂ᵀ + Σ_k Σ_{q = big, small} f(σψ′λ_q) n₂ v_q v_qᵀ   (v_big = s w_k + w u_k,
///                                                                          v_small = w w_k − s u_k)
///
/// (f = max(·, 0) for `analytic`, |·| for `abs`; the families' s, w, n₂, λ of
/// `lengths/length_hessian.hpp`). Each entry of the upper triangle is summed term by term in a
/// fixed order and mirrored, so the result is symmetric bit for bit. The kernels are templates
/// on `T`, a scalar or `Lanes<Scalar>` (one pair per lane, `core/lanes.hpp`): the single-pair
/// functions and the vectorised batches (`energy/evaluate_batch.hpp`) run the same operations
/// and give the same bits. A term whose weight is zero is skipped (per lane for `Lanes`).
#pragma once

#include <pce/core/lanes.hpp>
#include <pce/frames/frame.hpp>

#include <cmath>
#include <type_traits>

namespace pce::detail {

/// What the plane kinds' Hessian kernels read of a frame, as plain values of `T`.
template <class T> struct PlaneValues {
  T P[3][4];  ///< the frame coefficients
  T n[3];     ///< n̂
  T t[2][3];  ///< ê0, ê1
  T l;        ///< the signed length l
  T a[2];     ///< |e0|, |e1⊥|

  PlaneValues() = default;
  /// From a scalar frame.
  template <class Scalar> PCE_HOST_DEVICE explicit PlaneValues(const Frame<Scalar>& f) {
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 4; ++j) P[k][j] = f.P(k, j);
    for (int i = 0; i < 3; ++i) n[i] = f.n[i], t[0][i] = f.t0[i], t[1][i] = f.t1[i];
    l = f.l;
    a[0] = f.a0;
    a[1] = f.a1;
  }
  /// `w_k = P.row(k) ⊗ n̂`
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE void w(int k, T (&v)[12]) const {
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) v[3 * j + i] = P[k][j] * n[i];
  }
  /// `u_k = P.row(2) ⊗ ê_k`
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE void u(int k, T (&v)[12]) const {
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) v[3 * j + i] = P[2][j] * t[k][i];
  }
};

/// The upper triangle of a symmetric 12×12 matrix, row by row (78 entries), summed term by
/// term: the first term is assigned (0 where it is off), the others added.
template <class T> struct UpperTriangle12 {
  T h[78];
  /// sets `c v vᵀ` (entry (a, b): `(c v_a) v_b`) where `on` holds, 0 elsewhere
  template <class Mask>
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE void first_rank_one(const T& c, const T (&v)[12], const Mask& on) {
    T cv[12];
    for (int a = 0; a < 12; ++a) cv[a] = c * v[a];
    int idx = 0;
    for (int a = 0; a < 12; ++a)
      for (int b = a; b < 12; ++b, ++idx) h[idx] = select(on, T(cv[a] * v[b]), T(0));
  }
  /// adds `c v vᵀ` (entry (a, b): `(c v_a) v_b`), in the lanes where `on` holds
  template <class Mask> PCE_HOST_DEVICE PCE_ALWAYS_INLINE void rank_one(const T& c, const T (&v)[12], const Mask& on) {
    if (!any(on)) return;
    T cv[12];
    for (int a = 0; a < 12; ++a) cv[a] = c * v[a];
    int idx = 0;
    if (all(on)) {
      for (int a = 0; a < 12; ++a)
        for (int b = a; b < 12; ++b, ++idx) h[idx] = h[idx] + cv[a] * v[b];
    } else {
      for (int a = 0; a < 12; ++a)
        for (int b = a; b < 12; ++b, ++idx) h[idx] = select(on, T(h[idx] + cv[a] * v[b]), h[idx]);
    }
  }
  /// adds `x yᵀ + y xᵀ` (entry (a, b): `x_a y_b + y_a x_b`, symmetric as written)
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE void rank_two(const T (&x)[12], const T (&y)[12]) {
    int idx = 0;
    for (int a = 0; a < 12; ++a)
      for (int b = a; b < 12; ++b, ++idx) h[idx] = h[idx] + (x[a] * y[b] + y[a] * x[b]);
  }
};

/// The same sums for one scalar pair into a caller's dense matrix `M`, by column segments as
/// fixed-size Eigen vectors (vectorised, unrolled): in column b only the rows of the block
/// columns up to b's, which hold the upper triangle, with the operations per entry of
/// `UpperTriangle12`; `mirror()` then copies the upper triangle into the lower. Equal to
/// `UpperTriangle12<Scalar>` bit for bit.
template <class Scalar> struct DenseSymmetric12 {
  Mat12<Scalar>& M;
  /// `op(rows, b)` for every column b with the fixed-size row count `rows` (3, 6, 9 or 12) of
  /// its block column
  template <class Op> PCE_HOST_DEVICE PCE_ALWAYS_INLINE static void columns(Op op) {
    for (int b = 0; b < 3; ++b) op(std::integral_constant<int, 3>(), b);
    for (int b = 3; b < 6; ++b) op(std::integral_constant<int, 6>(), b);
    for (int b = 6; b < 9; ++b) op(std::integral_constant<int, 9>(), b);
    for (int b = 9; b < 12; ++b) op(std::integral_constant<int, 12>(), b);
  }
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE void first_rank_one(const Scalar& c, const Scalar (&v)[12], bool on) {
    if (!on) {
      M.setZero();
      return;
    }
    const Vec12<Scalar> cv = c * Eigen::Map<const Vec12<Scalar>>(v);
    columns([&](auto rows, int b) {
      constexpr int r = decltype(rows)::value;
      M.col(b).template head<r>() = cv.template head<r>() * v[b];
    });
  }
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE void rank_one(const Scalar& c, const Scalar (&v)[12], bool on) {
    if (!on) return;
    const Vec12<Scalar> cv = c * Eigen::Map<const Vec12<Scalar>>(v);
    columns([&](auto rows, int b) {
      constexpr int r = decltype(rows)::value;
      M.col(b).template head<r>() += cv.template head<r>() * v[b];
    });
  }
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE void rank_two(const Scalar (&x)[12], const Scalar (&y)[12]) {
    const Eigen::Map<const Vec12<Scalar>> X(x), Y(y);
    columns([&](auto rows, int b) {
      constexpr int r = decltype(rows)::value;
      M.col(b).template head<r>() += X.template head<r>() * y[b] + Y.template head<r>() * x[b];
    });
  }
  /// Copies the upper triangle into the lower.
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE void mirror() {
    for (int b = 0; b < 12; ++b)
      for (int a = b + 1; a < 12; ++a) M(a, b) = M(b, a);
  }
};

/// One family's eigenpairs (`length_family`) on `T`: s = sgn(l) (+1 at l = 0), w = 1/ρ,
/// n₂ = 1/(1+w²), λ_big = −sρ/a, λ_small = sw/a, with ρ = t + √(1+t²), t = |l/a|/2.
template <class T> struct FamilyValues {
  T s, w, n2, lambda_big, lambda_small;
  PCE_HOST_DEVICE PCE_ALWAYS_INLINE FamilyValues(const T& l, const T& a, const T& big_t) {
    using std::abs;
    using std::sqrt;
    s = select(l < T(0), T(-1), T(1));
    const T t = abs(l / a) / T(2);
    const T h = select(t < big_t, T(sqrt(T(1) + t * t)), t);  // beyond 1/√ε, √(1+t²) rounds to t
    const T rho = t + h;
    w = T(1) / rho;
    n2 = T(1) / (T(1) + w * w);
    lambda_big = -s * rho / a;
    lambda_small = s * w / a;
  }
};

/// `∇²E` of a plane kind (see the file comment) into `H` (`UpperTriangle12<T>`, or
/// `DenseSymmetric12` for a scalar); c1 = σψ′, c2 = ψ″.
template <class T, class Acc>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE void plane_exact_hessian(const PlaneValues<T>& f, const T& c1, const T& c2, Acc& H) {
  T w2[12];
  f.w(2, w2);
  H.first_rank_one(c2, w2, true);
  for (int k = 0; k < 2; ++k) {
    T wk[12], uk[12];
    f.w(k, wk);
    f.u(k, uk);
    // m w wᵀ + μ (w uᵀ + u wᵀ) = w zᵀ + z wᵀ with z = (m/2) w + μ u
    const T m = -c1 * ((f.l / f.a[k]) / f.a[k]), mu = -c1 / f.a[k];
    const T half_m = m / T(2);
    T z[12];
    for (int a = 0; a < 12; ++a) z[a] = half_m * wk[a] + mu * uk[a];
    H.rank_two(wk, z);
  }
}

/// The clamped (`flip` false: f = max(·, 0)) or flipped (`flip` true: f = |·|) closed-form
/// Hessian of a plane kind into `H`; c1 = σψ′, c2 = ψ″. `big_t` = 1/√ε of the scalar.
template <class T, class Acc>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE void plane_filtered_hessian(const PlaneValues<T>& f, const T& c1, const T& c2,
                                                              bool flip, const T& big_t, Acc& H) {
  using std::abs;
  const auto filter = [flip](const T& v) { return flip ? T(abs(v)) : select(v > T(0), v, T(0)); };
  T w2[12];
  f.w(2, w2);
  const T f2 = filter(c2);
  H.first_rank_one(f2, w2, f2 != T(0));
  for (int k = 0; k < 2; ++k) {
    const FamilyValues<T> fam(f.l, f.a[k], big_t);
    const T mb = filter(T(c1 * fam.lambda_big)), ms = filter(T(c1 * fam.lambda_small));
    const auto on_b = (mb != T(0)) && (c1 != T(0)), on_s = (ms != T(0)) && (c1 != T(0));
    if (!any(on_b || on_s)) continue;
    T wk[12], uk[12], v[12];
    f.w(k, wk);
    f.u(k, uk);
    // q_big = (s, w)√n2 and q_small = (w, −s)√n2 in the basis (w_k, u_k); the √n2 goes into
    // the weight, so no square root is taken.
    for (int a = 0; a < 12; ++a) v[a] = fam.s * wk[a] + fam.w * uk[a];
    H.rank_one(T(mb * fam.n2), v, on_b);
    for (int a = 0; a < 12; ++a) v[a] = fam.w * wk[a] - fam.s * uk[a];
    H.rank_one(T(ms * fam.n2), v, on_s);
  }
}

}  // namespace pce::detail
