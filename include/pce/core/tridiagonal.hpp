// SPDX-License-Identifier: MIT
/// @file
/// Symmetric tridiagonal matrices for the small eigenproblems of the exact projection:
/// Householder reduction of a small symmetric matrix to tridiagonal form (Golub & Van Loan,
/// Matrix Computations, Alg. 8.3.1), the characteristic polynomial with its first two
/// derivatives and its Sturm count by the three-term recurrence (Sec. 8.4.1), Laguerre's
/// iteration towards a neighbouring eigenvalue (Parlett 1964; Li & Zeng, "Laguerre's
/// iteration in solving the symmetric tridiagonal eigenproblem", SIAM J. Sci. Comput.
/// 15(5), 1994) and eigenvectors by twisted factorisations (Dhillon & Parlett, "Orthogonal
/// eigenvectors and relative gaps", SIAM J. Matrix Anal. Appl. 25(3), 2004).
#pragma once

#include <pce/core/types.hpp>

#include <cmath>
#include <limits>

namespace pce::detail {

/// `A = H T Hᵀ` for a symmetric N×N `A`: the tridiagonal `T` (diagonal `d`, subdiagonal
/// `e`) and the orthogonal `H = H_0 ⋯ H_{N-3}` as its Householder reflections
/// `H_k = I − β_k v_k v_kᵀ` (v_k zero above row k+1; β_k = 0 for a column that was already
/// tridiagonal to ε·max|A|).
template <class Scalar, int N> struct Tridiagonalization {
  static constexpr int R = N > 2 ? N - 2 : 1;
  Scalar d[N];
  Scalar e[N > 1 ? N - 1 : 1];
  VecN<Scalar, N> v[R];
  Scalar beta[R];

  /// Reduces `A` (entries of order one: callers rescale first, `core/scaling.hpp`).
  explicit Tridiagonalization(MatN<Scalar, N> A) {
    using std::sqrt;
    const Scalar eps = Constants<Scalar>::epsilon();
    for (int k = 0; k + 2 < N; ++k) {
      v[k].setZero();
      beta[k] = Scalar(0);
      Scalar tail2 = Scalar(0);
      for (int i = k + 2; i < N; ++i) {
        v[k][i] = A(i, k);
        tail2 += v[k][i] * v[k][i];
      }
      if (!(tail2 > eps * eps)) continue;  // already tridiagonal to ε (ε·max|A| unscaled)
      const Scalar x1 = A(k + 1, k);
      const Scalar xnorm = sqrt(x1 * x1 + tail2);
      const Scalar alpha = x1 > Scalar(0) ? Scalar(-xnorm) : xnorm;
      v[k][k + 1] = x1 - alpha;  // no cancellation: α has the opposite sign of x1
      beta[k] = Scalar(2) / (tail2 + v[k][k + 1] * v[k][k + 1]);
      const VecN<Scalar, N> p = beta[k] * (A * v[k]);
      const VecN<Scalar, N> w = p - (beta[k] * Scalar(0.5) * p.dot(v[k])) * v[k];
      A.noalias() -= v[k] * w.transpose() + w * v[k].transpose();
    }
    for (int i = 0; i < N; ++i) d[i] = A(i, i);
    for (int i = 0; i + 1 < N; ++i) e[i] = A(i + 1, i);
  }

  /// `H y`: an eigenvector of `T` mapped to one of `A`.
  VecN<Scalar, N> apply(VecN<Scalar, N> y) const {
    for (int k = N - 3; k >= 0; --k)
      if (beta[k] != Scalar(0)) y -= (beta[k] * v[k].dot(y)) * v[k];
    return y;
  }

  /// `H` as a matrix.
  MatN<Scalar, N> matrix() const {
    MatN<Scalar, N> H = MatN<Scalar, N>::Identity();
    for (int k = 0; k + 2 < N; ++k)
      if (beta[k] != Scalar(0)) H.noalias() -= (beta[k] * (H * v[k])) * v[k].transpose();
    return H;
  }
};

/// `p(x) = det(T − xI)` with `p′` and `p″` by the three-term recurrence of the leading
/// principal minors, and the number of eigenvalues of `T` below `x` (the sign changes of
/// that Sturm sequence). Entries of `T` of order one (no overflow for |x| ≲ 1).
template <class Scalar, int N> struct CharacteristicPolynomial {
  Scalar p, dp, ddp;
  int below;
  CharacteristicPolynomial(const Tridiagonalization<Scalar, N>& t, const Scalar& x) {
    Scalar p0 = Scalar(1), d0 = Scalar(0), dd0 = Scalar(0);
    Scalar p1 = t.d[0] - x, d1 = Scalar(-1), dd1 = Scalar(0);
    below = p1 < Scalar(0) ? 1 : 0;
    for (int i = 1; i < N; ++i) {
      const Scalar a = t.d[i] - x, b = t.e[i - 1] * t.e[i - 1];
      const Scalar pn = a * p1 - b * p0;
      const Scalar dn = a * d1 - p1 - b * d0;
      const Scalar ddn = a * dd1 - Scalar(2) * d1 - b * dd0;
      // a zero minor takes the sign opposite to its predecessor (Wilkinson's convention)
      below += ((pn < Scalar(0)) != (p1 < Scalar(0))) || (pn == Scalar(0) && p1 != Scalar(0)) ? 1 : 0;
      p0 = p1, p1 = pn, d0 = d1, d1 = dn, dd0 = dd1, dd1 = ddn;
    }
    p = p1, dp = d1, ddp = dd1;
  }

  /// Laguerre's step from `x` towards the nearest eigenvalue above (`up`) or below it:
  /// `x − N/(G ∓ √((N−1)(N·H − G²)))` with `G = p′/p`, `H = G² − p″/p`. For a polynomial
  /// with real roots it stays between `x` and that eigenvalue and converges to it
  /// monotonically and, for a simple root, cubically.
  Scalar laguerre_step(bool up) const {
    using std::sqrt;
    if (p == Scalar(0)) return Scalar(0);
    const Scalar G = dp / p, H = G * G - ddp / p;
    const Scalar arg = Scalar(N - 1) * (Scalar(N) * H - G * G);
    const Scalar root = arg > Scalar(0) ? Scalar(sqrt(arg)) : Scalar(0);
    return -Scalar(N) / (up ? Scalar(G - root) : Scalar(G + root));
  }
};

/// Eigenvector of `T` for an eigenvalue approximation `lambda` by the twisted factorisation
/// `T − λI = N_r Δ_r N_rᵀ` with the smallest |γ_r|: `y_r = 1` and the two bidiagonal
/// recurrences outwards. Returns `γ_r`, the residual `(T − λI) y = γ_r e_r`; `y` is not
/// normalised. Pivots below `pivmin` in magnitude are replaced by `−pivmin`.
template <class Scalar, int N>
Scalar twisted_eigenvector(const Tridiagonalization<Scalar, N>& t, const Scalar& lambda, const Scalar& pivmin,
                           VecN<Scalar, N>& y) {
  using std::abs;
  Scalar dplus[N], dminus[N];
  const auto safe = [&](Scalar q) { return abs(q) < pivmin ? Scalar(-pivmin) : q; };
  dplus[0] = safe(t.d[0] - lambda);
  for (int i = 1; i < N; ++i) dplus[i] = safe((t.d[i] - lambda) - t.e[i - 1] * t.e[i - 1] / dplus[i - 1]);
  dminus[N - 1] = safe(t.d[N - 1] - lambda);
  for (int i = N - 2; i >= 0; --i) dminus[i] = safe((t.d[i] - lambda) - t.e[i] * t.e[i] / dminus[i + 1]);
  int r = 0;
  Scalar gamma = dplus[0] + dminus[0] - (t.d[0] - lambda);
  for (int i = 1; i < N; ++i) {
    const Scalar g = dplus[i] + dminus[i] - (t.d[i] - lambda);
    if (abs(g) < abs(gamma)) gamma = g, r = i;
  }
  y[r] = Scalar(1);
  for (int i = r - 1; i >= 0; --i) y[i] = -(t.e[i] / dplus[i]) * y[i + 1];
  for (int i = r + 1; i < N; ++i) y[i] = -(t.e[i - 1] / dminus[i]) * y[i - 1];
  return gamma;
}

}  // namespace pce::detail
