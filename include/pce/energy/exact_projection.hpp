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
/// For the plane kinds `S = R M Rᵀ` has at most two negative eigenvalues, and first-order
/// perturbation theory in the contact regime (|ψ′| l ≪ |ψ′| a ≪ ψ″ a², `docs/math.md` §9)
/// approximates them in closed form; `core/negative_eigenpairs.hpp` refines them and their
/// eigenvectors, and `proj(S) = S − Σ_{λ<0} λ q qᵀ`. Where that does not apply (or any of
/// its checks fails) `S` is diagonalised by Householder tridiagonalisation and implicit QR
/// steps (`core/jacobi.hpp`).
#pragma once

#include <pce/core/jacobi.hpp>
#include <pce/core/negative_eigenpairs.hpp>
#include <pce/frames/frame.hpp>

#include <cmath>
#include <utility>

namespace pce::detail {

/// Rows: an orthonormal basis of the vectors in R^n orthogonal to (1, …, 1) (the Helmert
/// basis: `h_i = (1, …, 1, −(i+1), 0, …)/√((i+1)(i+2))` with i+1 ones).
template <class Scalar, int n> Eigen::Matrix<Scalar, n - 1, n> helmert_basis() {
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
  void rank_one(const Scalar& mu, const VecN<Scalar, N>& v) { half.noalias() += (Scalar(mu / Scalar(2)) * v) * v.transpose(); }
  /// adds `a bᵀ + b aᵀ`
  void rank_two(const VecN<Scalar, N>& a, const VecN<Scalar, N>& b) { half.noalias() += a * b.transpose(); }
  MatN<Scalar, N> matrix() const { return half + half.transpose(); }
};

/// `Q proj(S) Qᵀ` for orthonormal columns `Q`: diagonalise `S` (tridiagonalisation and
/// implicit QR, `core/jacobi.hpp`) and sum `λ (Q v)(Q v)ᵀ` over its positive eigenpairs.
template <class Scalar, int Dofs, int K>
MatN<Scalar, Dofs> projected_in_basis(const Eigen::Matrix<Scalar, Dofs, K>& Q, const MatN<Scalar, K>& S) {
  VecN<Scalar, K> lambda;
  MatN<Scalar, K> V;
  symmetric_qr_eigen(S, lambda, V);
  SymmetricSum<Scalar, Dofs> sum;
  for (int i = 0; i < K; ++i)
    if (!(lambda[i] <= Scalar(0))) sum.rank_one(lambda[i], (Q * V.col(i)).eval());  // NaN propagates
  return sum.matrix();
}

/// `Σ (Q g)(Q g)ᵀ` over the columns `g` of the diagonally pivoted Cholesky factor of a
/// positive semidefinite `S` of rank ≤ R, stopped when no diagonal entry above
/// `Kε·max S_ii` is left; `to_x(g)` computes `Q g`. Formed as `G Gᵀ`, symmetric bit for bit.
template <int Dofs, int R, class Scalar, int K, class ToX>
MatN<Scalar, Dofs> assembled_psd(MatN<Scalar, K> S, const ToX& to_x) {
  using std::sqrt;
  Eigen::Matrix<Scalar, Dofs, R> G = Eigen::Matrix<Scalar, Dofs, R>::Zero();
  const Scalar floor = Scalar(K) * Constants<Scalar>::epsilon() * S.diagonal().maxCoeff();
  for (int r = 0; r < R; ++r) {
    int p = 0;
    for (int i = 1; i < K; ++i)
      if (S(i, i) > S(p, p)) p = i;
    if (!(S(p, p) > floor)) break;
    const VecN<Scalar, K> g = S.col(p) / sqrt(S(p, p));
    G.col(r) = to_x(g);
    S.noalias() -= g * g.transpose();
  }
  return (G * G.transpose()).eval();
}

/// Closed-form approximations (ascending) of the two negative eigenvalues of the plane
/// kinds' `S = [[A, B], [Bᵀ, 0]]` (A 3×3, B 3×2), first order in the contact regime: with
/// `v` the unit direction of A's dominant ψ″ term, `B′ = (I − v vᵀ) B` has singular values
/// σ_k and left singular vectors x_k, and `λ_k ≈ −σ_k + x_kᵀ A x_k / (2σ_k²)` (unnormalised
/// x_k = B′ y_k).
template <class Scalar> void negative_eigenvalue_guesses(const MatN<Scalar, 5>& S, const Vec3<Scalar>& v, Scalar (&g)[2]) {
  using std::sqrt;
  Eigen::Matrix<Scalar, 3, 2> B = S.template block<3, 2>(0, 3);
  B -= v * (v.transpose() * B);
  const Scalar a = B.col(0).squaredNorm(), c = B.col(1).squaredNorm(), b = B.col(0).dot(B.col(1));
  const Scalar half = (a - c) / Scalar(2), root = sqrt(half * half + b * b), mean = (a + c) / Scalar(2);
  Eigen::Matrix<Scalar, 2, 1> y0(Scalar(1), Scalar(0));  // eigenvector of BᵀB, larger eigenvalue
  if (root > Scalar(0)) {
    if (half >= Scalar(0))
      y0 << half + root, b;
    else
      y0 << b, root - half;
    y0.normalize();
  }
  const Eigen::Matrix<Scalar, 2, 1> y1(-y0[1], y0[0]);
  const Scalar s2[2] = {Scalar(mean + root), Scalar(mean - root)};
  const Vec3<Scalar> x[2] = {B * y0, B * y1};
  const Mat3<Scalar> A = S.template topLeftCorner<3, 3>();
  for (int k = 0; k < 2; ++k) {
    const Scalar s = s2[k] > Scalar(0) ? Scalar(sqrt(s2[k])) : Scalar(0);
    g[k] = s > Scalar(0) ? Scalar(-s + x[k].dot(A * x[k]) / (Scalar(2) * s2[k])) : Scalar(0);
  }
  if (g[1] < g[0]) std::swap(g[0], g[1]);
}

/// The plane kinds' reduced problem `S = R M Rᵀ` (5×5) for `Jᵀ(c2 ggᵀ + c1 H_l)J`
/// (c1 = σψ′, c2 = ψ″) in the orthonormal basis `h_i ⊗ n̂` (i = 0, 1, 2), `p̂_2 ⊗ ê_k`
/// (k = 0, 1), and `v`, the unit direction of its ψ″ term in the first three coordinates.
/// Range basis of M: `w_k = p_k ⊗ n̂` (k = 0, 1, 2; w_2 = ∇l) and `u_k = p_2 ⊗ ê_k`;
/// `M` has `m_k = −c1 l/a_k²` on w_k, `c2` on w_2, `−c1/a_k` between w_k and u_k.
template <class Scalar>
void plane_reduced_problem(const Frame<Scalar>& f, const Scalar& c1, const Scalar& c2, MatN<Scalar, 5>& S, Vec3<Scalar>& v) {
  using std::sqrt;
  static const Eigen::Matrix<Scalar, 3, 4> h = helmert_basis<Scalar, 4>();
  const Mat3<Scalar> R = h * f.P.transpose();  // p_k = Σ_i R(i, k) h_i
  const Scalar r2 = sqrt(f.P.row(2).squaredNorm());
  const Scalar m0 = -c1 * ((f.l / f.a0) / f.a0), m1 = -c1 * ((f.l / f.a1) / f.a1);
  const Scalar mu0 = -c1 / f.a0, mu1 = -c1 / f.a1;
  S.template topLeftCorner<3, 3>() = R * Vec3<Scalar>(m0, m1, c2).asDiagonal() * R.transpose();
  S.template block<3, 1>(0, 3) = (mu0 * r2) * R.col(0);
  S.template block<3, 1>(0, 4) = (mu1 * r2) * R.col(1);
  S.template block<1, 3>(3, 0) = S.template block<3, 1>(0, 3).transpose();
  S.template block<1, 3>(4, 0) = S.template block<3, 1>(0, 4).transpose();
  S.template bottomRightCorner<2, 2>().setZero();
  v = R.col(2) / r2;
}

/// Exact projection of a plane kind's Hessian `Jᵀ(c2 ggᵀ + c1 H_l)J` (c1 = σψ′, c2 = ψ″)
/// through `plane_reduced_problem`.
template <class Scalar> Mat12<Scalar> exact_projection(const Frame<Scalar>& f, const Scalar& c1, const Scalar& c2) {
  using std::sqrt;
  static const Eigen::Matrix<Scalar, 3, 4> h = helmert_basis<Scalar, 4>();
  MatN<Scalar, 5> S;
  Vec3<Scalar> v;
  plane_reduced_problem(f, c1, c2, S, v);
  const Scalar r2 = sqrt(f.P.row(2).squaredNorm());
  const Eigen::Matrix<Scalar, 1, 4> p2 = f.P.row(2) / r2;
  // Q g = Σ_i g_i h_i ⊗ n̂ + p̂_2 ⊗ (g_3 ê_0 + g_4 ê_1), vertex by vertex
  const auto to_x = [&](const VecN<Scalar, 5>& g) {
    const Eigen::Matrix<Scalar, 1, 4> a = g.template head<3>().transpose() * h;
    const Vec3<Scalar> b = g[3] * f.t0 + g[4] * f.t1;
    Vec12<Scalar> x;
    for (int j = 0; j < 4; ++j) x.template segment<3>(3 * j) = a[j] * f.n + p2[j] * b;
    return x;
  };
  // Two negative eigenvalues when ψ′ ≠ 0 and ψ″ ≥ 0 (S is congruent to M: two 2×2 blocks
  // of negative determinant and c2 ≥ 0).
  if (c1 != Scalar(0) && c2 >= Scalar(0)) {
    Scalar guess[2], lambda[2];
    VecN<Scalar, 5> q[2];
    negative_eigenvalue_guesses(S, v, guess);
    if (negative_eigenpairs(S, guess, lambda, q)) {
      for (int k = 0; k < 2; ++k) S.noalias() -= (lambda[k] * q[k]) * q[k].transpose();
      return assembled_psd<12, 3>(S, to_x);
    }
  }
  Eigen::Matrix<Scalar, 12, 5> Q;
  for (int i = 0; i < 5; ++i) Q.col(i) = to_x(VecN<Scalar, 5>::Unit(i));
  return projected_in_basis(Q, S);
}

/// Exact projection of `Jᵀ Hc J` for a dense frame Hessian `Hc` (the mollified energy,
/// whose frame Hessian can have rank 9): the reduced problem is 9×9 in the basis
/// `h_i ⊗ e_a`, since `Jᵀ = Pᵀ ⊗ I3 = (hᵀ ⊗ I3)(h Pᵀ ⊗ I3)`.
template <class Scalar> Mat12<Scalar> exact_projection(const Frame<Scalar>& f, const Mat9<Scalar>& Hc) {
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
