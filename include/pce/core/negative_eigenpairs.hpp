// SPDX-License-Identifier: MIT
/// @file
/// The few negative eigenpairs of a small symmetric matrix, from approximations of the
/// eigenvalues: what the exact projection needs (`energy/exact_projection.hpp`), since
/// `proj(S) = S − Σ_{λ<0} λ q qᵀ` and the pair Hessians have at most two negative
/// eigenvalues. Householder tridiagonalisation, Laguerre's iteration from each
/// approximation to its eigenvalue (the Sturm count at the approximation says on which
/// side it lies), then one twisted factorisation per eigenvector (`core/tridiagonal.hpp`).
/// With approximations good to a few digits this takes two or three polynomial evaluations
/// per eigenvalue, the two chains independent of each other, instead of the ~27 dependent
/// rotations of the QR algorithm (`core/jacobi.hpp`). Every step is checked; when one
/// fails, the function says so and the caller falls back to the QR algorithm.
#pragma once

#include <pce/core/scaling.hpp>
#include <pce/core/tridiagonal.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pce::detail {

/// Finds the K eigenpairs of the symmetric `S` below zero from approximations `guess`
/// (ascending), as `lambda` (ascending) and orthonormal `q`. Returns false, with the
/// outputs unspecified, unless all of these hold: `S` is finite and nonzero; exactly K
/// of its eigenvalues lie below `−τ` (τ = 4Nε·max|T|, eigenvalues in [−τ, 0) are left
/// out, an absolute perturbation of the accuracy below); each approximation lies between
/// the neighbours of its eigenvalue; Laguerre's iteration settles in 6 steps; each
/// eigenvector's residual is below 16ε·max|T|; exactly k eigenvalues lie below the k-th
/// result minus 64ε·max|T|; and the two vectors are far from parallel. On
/// success `S − Σ λ_k q_k q_kᵀ` is the PSD part of `S` to about ε·max|S| (absolute).
template <class Scalar, int N, int K>
bool negative_eigenpairs(const MatN<Scalar, N>& S, const Scalar (&guess)[K], Scalar (&lambda)[K],
                         VecN<Scalar, N> (&q)[K]) {
  using std::abs;
  static_assert(K >= 1 && K <= 2 && K < N, "one or two eigenpairs of a matrix larger than that");
  if (!S.allFinite()) return false;
  const Scalar amax = S.cwiseAbs().maxCoeff();
  if (!(amax > Scalar(0))) return false;
  const PowerOfTwoScale<Scalar> scale(amax);
  const Tridiagonalization<Scalar, N> t(scale.down(S));
  Scalar tmax = Scalar(0);
  for (int i = 0; i < N; ++i) tmax = std::max(tmax, Scalar(abs(t.d[i])));
  for (int i = 0; i + 1 < N; ++i) tmax = std::max(tmax, Scalar(abs(t.e[i])));
  const Scalar eps = Constants<Scalar>::epsilon();
  const Scalar tau = Scalar(4 * N) * eps * tmax;
  // After a step of at most `settled` = ε^0.45 (relative), Laguerre's cubic convergence
  // leaves an error of order ε^1.35 (relative to the gaps); the residual check below
  // confirms it.
  static const Scalar settled_relative = Scalar(std::pow(static_cast<long double>(eps), 0.45L));
  const Scalar settled = settled_relative * tmax;
  Scalar x[K];
  bool up[K], done[K];
  for (int k = 0; k < K; ++k) {
    x[k] = scale.down(guess[k]);
    if (!(abs(x[k]) <= Scalar(4) * tmax)) return false;
    done[k] = false;
  }
  for (int it = 0; it < 6; ++it) {
    bool all = true;
    for (int k = 0; k < K; ++k) {  // independent chains: their latencies overlap
      if (done[k]) continue;
      const CharacteristicPolynomial<Scalar, N> cp(t, x[k]);
      if (it == 0) {
        if (cp.below == k)
          up[k] = true;  // below λ_k (and above λ_{k−1})
        else if (cp.below == k + 1)
          up[k] = false;  // above λ_k (and below λ_{k+1})
        else
          return false;  // the approximation is beyond a neighbouring eigenvalue
      }
      const Scalar step = cp.laguerre_step(up[k]);
      if (!(abs(step) <= Scalar(4) * tmax)) return false;  // NaN or a jump out of range
      x[k] += step;
      done[k] = abs(step) <= settled;
      all = all && done[k];
    }
    if (all) break;
  }
  const Scalar pivmin = std::numeric_limits<Scalar>::min() / eps;
  for (int k = 0; k < K; ++k) {
    if (!done[k] || !(x[k] < -tau)) return false;
    // The eigenvector by a twisted factorisation at x; if its residual shows that x was
    // not accurate enough (the roots of p are less accurate than its evaluation when
    // eigenvalues of very different size meet, e.g. in float), once more at the Rayleigh
    // quotient of that vector, whose error is of the order of the residual squared.
    VecN<Scalar, N> y;
    Scalar gamma = twisted_eigenvector(t, x[k], pivmin, y), ny = y.norm();
    x[k] += gamma / (ny * ny);  // Rayleigh quotient of y
    if (!(abs(gamma) <= Scalar(8) * eps * tmax * ny)) {
      gamma = twisted_eigenvector(t, x[k], pivmin, y), ny = y.norm();
      x[k] += gamma / (ny * ny);
      if (!(abs(gamma) <= Scalar(16) * eps * tmax * ny)) return false;
    }
    // The index check: a small Laguerre step also happens right next to a *different*
    // eigenvalue (starting beside one that rounds to zero, the steps away from it grow only
    // geometrically), so "settled" alone does not prove that x is λ_k. Exactly k
    // eigenvalues must lie below x − 64ε·max|T| (a fuzzer finding: tests/test_negative_eigenpairs.cpp).
    if (CharacteristicPolynomial<Scalar, N>(t, Scalar(x[k] - Scalar(64) * eps * tmax)).below != k) return false;
    q[k] = t.apply(y / ny);
    lambda[k] = scale.up(x[k]);
  }
  if (K == 2) {  // orthogonalise (exact eigenvectors are orthogonal)
    const int last = K - 1;
    q[last] -= q[0].dot(q[last]) * q[0];
    const Scalar n = q[last].norm();
    if (!(n > Scalar(0.5))) return false;
    q[last] /= n;
  }
  return true;
}

}  // namespace pce::detail
