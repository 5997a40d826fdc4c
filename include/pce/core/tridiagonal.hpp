// SPDX-License-Identifier: MIT
/// @file
/// Householder reduction of a small symmetric matrix to tridiagonal form (Golub & Van Loan,
/// Matrix Computations, Alg. 8.3.1), with the reflections kept: the first half of the
/// small eigensolver of the exact projection's fallback (`core/jacobi.hpp`).
#pragma once

#include <pce/core/types.hpp>

#include <cmath>

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
  PCE_HOST_DEVICE explicit Tridiagonalization(MatN<Scalar, N> A) {
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

  /// `H` as a matrix.
  PCE_HOST_DEVICE MatN<Scalar, N> matrix() const {
    MatN<Scalar, N> H = MatN<Scalar, N>::Identity();
    for (int k = 0; k + 2 < N; ++k)
      if (beta[k] != Scalar(0)) H.noalias() -= (beta[k] * (H * v[k])) * v[k].transpose();
    return H;
  }
};

}  // namespace pce::detail
