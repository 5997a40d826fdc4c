// SPDX-License-Identifier: MIT
/// @file
/// `Projection::exact`: the nearest positive semidefinite matrix (Frobenius norm, Higham
/// 1988) of a pair's exact x-space Hessian, computed through the Hessian's low-rank
/// structure instead of a full eigendecomposition (`docs/math.md` §9).
///
/// Every Hessian in this library is `∇²E = W M Wᵀ`, where each column of `W` is a row of the
/// frame coefficients times a unit direction, `w = P.row(k) ⊗ d` (`Jᵀ` of a frame vector),
/// and `M` is the frame Hessian in an orthonormal frame-space basis (≤ 5×5). The rows of `P`
/// span exactly the vectors orthogonal to (1, …, 1) (a translation moves no frame vector),
/// for which a fixed orthonormal basis `h_i` is known; so `W = Q R` with orthonormal `Q`
/// (columns `h_i ⊗ d` or `P̂.row(k) ⊗ d`) and a small `R` in closed form, and
///
///     ∇²E = Q (R M Rᵀ) Qᵀ,    proj(∇²E) = Q proj(R M Rᵀ) Qᵀ.
///
/// For the plane kinds `S = R M Rᵀ` has exactly two negative eigenvalues in the contact
/// regime, and `proj(S) = S − Σ λ_k q_k q_kᵀ` needs only those two eigenpairs, which
/// `energy/plane_eigenpairs.hpp` finds in closed form up to a scalar Newton iteration; its
/// three positive rank-one terms (a pivoted LDLᵀ) are mapped back by `Q`.
/// Where that does not apply (or its proof fails) `S` is diagonalised by Householder
/// tridiagonalisation and implicit QR steps (`core/jacobi.hpp`).
#pragma once

#include <pce/core/jacobi.hpp>
#include <pce/energy/plane_assembly.hpp>
#include <pce/energy/plane_eigenpairs.hpp>
#include <pce/frames/frame.hpp>

#include <cmath>

namespace pce::detail {

/// Rows: an orthonormal basis of the vectors in R^n orthogonal to (1, …, 1) (the Helmert
/// basis: `h_i = (1, …, 1, −(i+1), 0, …)/√((i+1)(i+2))` with i+1 ones).
template <class Scalar, int n> PCE_HOST_DEVICE Eigen::Matrix<Scalar, n - 1, n> helmert_basis() {
  using std::sqrt;
  Eigen::Matrix<Scalar, n - 1, n> h = Eigen::Matrix<Scalar, n - 1, n>::Zero();
  for (int i = 0; i < n - 1; ++i) {
    const Scalar c = Scalar(1) / sqrt(Scalar((i + 1) * (i + 2)));
    for (int j = 0; j <= i; ++j) h(i, j) = c;
    h(i, i + 1) = -Scalar(i + 1) * c;
  }
  return h;
}

/// Symmetric matrix accumulated as `S + Sᵀ` from rank-one and rank-two terms, so the
/// result is symmetric bit for bit.
template <class Scalar, int N> struct SymmetricSum {
  MatN<Scalar, N> half = MatN<Scalar, N>::Zero();
  /// adds `μ v vᵀ`
  PCE_HOST_DEVICE void rank_one(const Scalar& mu, const VecN<Scalar, N>& v) {
    half.noalias() += (Scalar(mu / Scalar(2)) * v) * v.transpose();
  }
  /// adds `a bᵀ + b aᵀ`
  PCE_HOST_DEVICE void rank_two(const VecN<Scalar, N>& a, const VecN<Scalar, N>& b) {
    half.noalias() += a * b.transpose();
  }
  PCE_HOST_DEVICE MatN<Scalar, N> matrix() const { return half + half.transpose(); }
};

/// `Q proj(S) Qᵀ` for orthonormal columns `Q`: diagonalise `S` (tridiagonalisation and
/// implicit QR, `core/jacobi.hpp`) and sum `λ (Q v)(Q v)ᵀ` over its positive eigenpairs.
template <class Scalar, int Dofs, int K>
PCE_HOST_DEVICE MatN<Scalar, Dofs> projected_in_basis(const Eigen::Matrix<Scalar, Dofs, K>& Q,
                                                      const MatN<Scalar, K>& S) {
  VecN<Scalar, K> lambda;
  MatN<Scalar, K> V;
  symmetric_qr_eigen(S, lambda, V);
  SymmetricSum<Scalar, Dofs> sum;
  for (int i = 0; i < K; ++i)
    if (!(lambda[i] <= Scalar(0))) sum.rank_one(lambda[i], (Q * V.col(i)).eval());  // NaN propagates
  return sum.matrix();
}

/// `const Eigen::Matrix<Scalar, 3, 4> NAME = helmert_basis<Scalar, 4>()`, built once per
/// program on the host (a function-scope static) and per call in device code, which has no
/// dynamically initialised statics; the same values either way.
#if defined(__CUDA_ARCH__)
#define PCE_HELMERT_4(NAME) const Eigen::Matrix<Scalar, 3, 4> NAME = helmert_basis<Scalar, 4>()
#else
#define PCE_HELMERT_4(NAME) static const Eigen::Matrix<Scalar, 3, 4> NAME = helmert_basis<Scalar, 4>()
#endif

/// The plane kinds' reduced problem `S = R M Rᵀ` (5×5) for `Jᵀ(c2 ggᵀ + c1 H_l)J`
/// (c1 = σψ′, c2 = ψ″) in the orthonormal basis `h_i ⊗ n̂` (i = 0, 1, 2), `p̂_2 ⊗ ê_k`
/// (k = 0, 1): with `r_k = R₃ e_k` (R₃ = h Pᵀ), `S = [[Σ d_k r_k r_kᵀ, [e₀r₀, e₁r₁]], [·ᵀ, 0]]`,
/// `d = (m_0, m_1, c2)`, `e_k = μ_k |p_2|`, `m_k = −c1 l/a_k²`, `μ_k = −c1/a_k` (M28).
template <class Scalar> struct PlaneReducedProblem {
  Mat3<Scalar> R;     ///< R₃ = h Pᵀ, columns r_k (p_k = Σ_i R₃(i, k) h_i)
  Scalar d[3], e[2];  ///< the weights above
  Scalar p2_norm;     ///< |p_2|
  PCE_HOST_DEVICE PlaneReducedProblem(const Frame<Scalar>& f, const Scalar& c1, const Scalar& c2) {
    using std::sqrt;
    PCE_HELMERT_4(h);
    R = h * f.P.transpose();
    p2_norm = sqrt(f.P.row(2).squaredNorm());
    const Scalar r0 = Scalar(1) / f.a0, r1 = Scalar(1) / f.a1;
    d[0] = -c1 * ((f.l * r0) * r0), d[1] = -c1 * ((f.l * r1) * r1), d[2] = c2;
    e[0] = (-c1 * r0) * p2_norm, e[1] = (-c1 * r1) * p2_norm;
  }
  /// S itself
  PCE_HOST_DEVICE MatN<Scalar, 5> matrix() const {
    MatN<Scalar, 5> S;
    S.template topLeftCorner<3, 3>() = R * Vec3<Scalar>(d[0], d[1], d[2]).asDiagonal() * R.transpose();
    S.template block<3, 1>(0, 3) = e[0] * R.col(0);
    S.template block<3, 1>(0, 4) = e[1] * R.col(1);
    S.template block<1, 3>(3, 0) = S.template block<3, 1>(0, 3).transpose();
    S.template block<1, 3>(4, 0) = S.template block<3, 1>(0, 4).transpose();
    S.template bottomRightCorner<2, 2>().setZero();
    return S;
  }
};

/// `T = proj(S) = S − Σ_k λ_k q_k q_kᵀ` (M29) as the sum `Σ_s δ_s l_s l_sᵀ` of at most three
/// positive rank-one terms: pivoted LDLᵀ (the largest remaining diagonal entry as pivot, Higham,
/// *Accuracy and Stability of Numerical Algorithms*, Sec. 10.3), stopped after three steps,
/// since T is PSD of rank 3 (S has three nonnegative eigenvalues, §9.3), or when no positive
/// pivot is left. What it drops is T's rounding, of size ε‖S‖. Returns the number of terms.
template <class Scalar>
PCE_HOST_DEVICE int rank_three_factor(MatN<Scalar, 5> T, Scalar (&delta)[3], VecN<Scalar, 5> (&l)[3]) {
  bool used[5] = {false, false, false, false, false};
  int count = 0;
  for (; count < 3; ++count) {
    int p = -1;
    Scalar best = Scalar(0);
    for (int i = 0; i < 5; ++i) {
      const bool better = !used[i] && T(i, i) > best;  // NaN: never a pivot
      best = better ? T(i, i) : best;
      p = better ? i : p;
    }
    if (p < 0) break;
    used[p] = true;
    const Scalar inv = Scalar(1) / best;
    VecN<Scalar, 5> c;
    for (int i = 0; i < 5; ++i) c[i] = used[i] ? Scalar(0) : T(i, p) * inv;  // eliminated rows: 0 exactly
    c[p] = Scalar(1);
    delta[count] = best;
    l[count] = c;
    if (count < 2) T.noalias() -= (best * c) * c.transpose();  // (the last step's update is never read)
  }
  return count;
}

/// Exact projection of a plane kind's Hessian `Jᵀ(c2 ggᵀ + c1 H_l)J` (c1 = σψ′, c2 = ψ″) into
/// `out`: when σψ′ ≠ 0 and ψ″ ≥ 0, S has exactly two negative eigenvalues (§9.3); with those
/// from `plane_negative_eigenpairs`, `proj(S) = S − Σ λ_k q_k q_kᵀ` is factored into three
/// positive rank-one terms (`rank_three_factor`) and the result is `Σ_s δ_s (Q l_s)(Q l_s)ᵀ`,
/// PSD term by term. Otherwise, or if the eigenpairs cannot be proven, `Q proj(S) Qᵀ` by the
/// QR algorithm.
template <class Scalar>
PCE_HOST_DEVICE void exact_projection(const Frame<Scalar>& f, const Scalar& c1, const Scalar& c2, Mat12<Scalar>& out) {
  PCE_HELMERT_4(h);
  const PlaneReducedProblem<Scalar> pr(f, c1, c2);
  const Eigen::Matrix<Scalar, 1, 4> p2 = f.P.row(2) * (Scalar(1) / pr.p2_norm);
  // Q g = Σ_i g_i h_i ⊗ n̂ + p̂_2 ⊗ (g_3 ê_0 + g_4 ê_1), vertex by vertex
  const auto to_x = [&](const VecN<Scalar, 5>& g, Scalar(&x)[12]) {
    const Eigen::Matrix<Scalar, 1, 4> a = g.template head<3>().transpose() * h;
    const Vec3<Scalar> b = g[3] * f.t0 + g[4] * f.t1;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) x[3 * j + i] = a[j] * f.n[i] + p2[j] * b[i];
  };
  const MatN<Scalar, 5> S = pr.matrix();
  if (c1 != Scalar(0) && c2 >= Scalar(0)) {
    Scalar lambda[2];
    VecN<Scalar, 5> q[2];
    if (plane_negative_eigenpairs(pr.R, pr.d, pr.e, lambda, q)) {
      MatN<Scalar, 5> T = S;
      for (int k = 0; k < 2; ++k) T.noalias() -= (lambda[k] * q[k]) * q[k].transpose();
      Scalar delta[3];
      VecN<Scalar, 5> l[3];
      const int terms = rank_three_factor(T, delta, l);
      if (terms == 0) {
        out.setZero();
        return;
      }
      DenseSymmetric12<Scalar> hessian{out};
      Scalar v[12];
      for (int s = 0; s < terms; ++s) {
        to_x(l[s], v);
        if (s == 0)
          hessian.first_rank_one(delta[s], v, true);
        else
          hessian.rank_one(delta[s], v, true);
      }
      hessian.mirror();
      return;
    }
  }
  Eigen::Matrix<Scalar, 12, 5> Q;
  for (int i = 0; i < 5; ++i) {
    Scalar v[12];
    to_x(VecN<Scalar, 5>::Unit(i), v);
    Q.col(i) = Eigen::Map<const Vec12<Scalar>>(v);
  }
  out = projected_in_basis(Q, S);
}

/// Exact projection of `Jᵀ Hc J` for a dense frame Hessian `Hc` (the mollified energy,
/// whose frame Hessian can have rank 9): the reduced problem is 9×9 in the basis
/// `h_i ⊗ e_a`, since `Jᵀ = Pᵀ ⊗ I3 = (hᵀ ⊗ I3)(h Pᵀ ⊗ I3)`.
template <class Scalar> PCE_HOST_DEVICE Mat12<Scalar> exact_projection(const Frame<Scalar>& f, const Mat9<Scalar>& Hc) {
  const Eigen::Matrix<Scalar, 3, 4> h = helmert_basis<Scalar, 4>();
  const Mat3<Scalar> R3 = h * f.P.transpose();
  Mat9<Scalar> R = Mat9<Scalar>::Zero();
  Eigen::Matrix<Scalar, 12, 9> Q = Eigen::Matrix<Scalar, 12, 9>::Zero();
  for (int i = 0; i < 3; ++i)
    for (int a = 0; a < 3; ++a) {
      for (int k = 0; k < 3; ++k) R(3 * i + a, 3 * k + a) = R3(i, k);
      for (int j = 0; j < 4; ++j) Q(3 * j + a, 3 * i + a) = h(i, j);
    }
  return projected_in_basis(Q, Mat9<Scalar>(R * Hc * R.transpose()));
}

}  // namespace pce::detail
