// SPDX-License-Identifier: MIT
/// @file
/// Eigen-decompositions of small fixed-size symmetric matrices, where no closed form
/// exists: cyclic Jacobi rotations (Rutishauser's update; Golub & Van Loan, Matrix
/// Computations, Sec. 8.5) for the mollified energy's 3×3 block, which keeps small
/// eigenvalues of graded matrices accurate to their own size (Demmel & Veselić 1992), and
/// tridiagonalisation + implicit QR (Sec. 8.3) for the exact projection's ≤ 5×5 reduced
/// problem (`energy/exact_projection.hpp`), about twice as fast for absolute accuracy.
#pragma once

#include <pce/core/scaling.hpp>
#include <pce/core/tridiagonal.hpp>
#include <pce/core/types.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pce::detail {

/// Diagonalises the symmetric `A` in place (`A` ends diagonal, eigenvalues unsorted on its
/// diagonal) and returns the orthonormal eigenvectors as the columns of `V`. An
/// off-diagonal entry is treated as zero when it is below `ε/4·√|a_pp a_qq|` (relative
/// accuracy) or not above `floor` (an absolute threshold, so that a zero diagonal entry
/// cannot keep it sweeping; 0 keeps full relative accuracy for graded matrices).
template <class Scalar, int N>
PCE_HOST_DEVICE void jacobi_eigen(MatN<Scalar, N>& A, MatN<Scalar, N>& V, const Scalar& floor) {
  using std::abs;
  using std::sqrt;
  V.setIdentity();
  const Scalar eps = Constants<Scalar>::epsilon();
  for (int sweep = 0; sweep < 16; ++sweep) {
    bool rotated = false;
    for (int p = 0; p < N - 1; ++p)
      for (int q = p + 1; q < N; ++q) {
        const Scalar apq = A(p, q);
        const Scalar aapq = abs(apq);
        if (aapq <= floor || aapq <= eps * sqrt(abs(A(p, p) * A(q, q))) / Scalar(4)) {
          A(p, q) = A(q, p) = Scalar(0);
          continue;
        }
        rotated = true;
        const Scalar theta = (A(q, q) - A(p, p)) / (Scalar(2) * apq);
        const Scalar at = abs(theta);
        const Scalar t =
            (at > Scalar(1) / eps ? Scalar(1) / (Scalar(2) * at) : Scalar(1) / (at + sqrt(at * at + Scalar(1)))) *
            (theta < Scalar(0) ? Scalar(-1) : Scalar(1));
        const Scalar c = Scalar(1) / sqrt(t * t + Scalar(1)), s = t * c;
        A(p, p) -= t * apq;
        A(q, q) += t * apq;
        A(p, q) = A(q, p) = Scalar(0);
        for (int r = 0; r < N; ++r) {
          if (r == p || r == q) continue;
          const Scalar arp = A(r, p), arq = A(r, q);
          A(r, p) = A(p, r) = c * arp - s * arq;
          A(r, q) = A(q, r) = s * arp + c * arq;
        }
        for (int i = 0; i < N; ++i) {
          const Scalar vip = V(i, p), viq = V(i, q);
          V(i, p) = c * vip - s * viq;
          V(i, q) = s * vip + c * viq;
        }
      }
    if (!rotated) break;
  }
}

/// `jacobi_eigen` with the absolute threshold `ε²·max|A|`: every eigenvalue accurate to
/// about ε·max|A| (what a PSD projection needs), in fewer sweeps.
template <class Scalar, int N> PCE_HOST_DEVICE void jacobi_eigen(MatN<Scalar, N>& A, MatN<Scalar, N>& V) {
  const Scalar eps = Constants<Scalar>::epsilon();
  jacobi_eigen(A, V, Scalar(eps * eps * A.cwiseAbs().maxCoeff()));
}

/// Eigen-decomposition of a small symmetric matrix by Householder tridiagonalisation and
/// the implicit symmetric QR algorithm with Wilkinson shifts (Golub & Van Loan, Matrix
/// Computations, Algs. 8.3.1 and 8.3.2): on return the eigenvalues (unsorted) are in `d`
/// and the orthonormal eigenvectors in the columns of `V`. Accurate to about ε·max|A|
/// (absolute), which is what a PSD projection needs; it takes about half the rotations of
/// cyclic Jacobi and one square root per rotation instead of two. `A` is first rescaled
/// exactly by a power of two to max|A_ij| in [½, 1), so that no square or product of its
/// entries overflows or underflows whatever its magnitude. A zero `A` gives d = 0, V = I;
/// a non-finite one gives NaN eigenvalues.
template <class Scalar, int N>
PCE_HOST_DEVICE void symmetric_qr_eigen(MatN<Scalar, N> A, VecN<Scalar, N>& d, MatN<Scalar, N>& V) {
  using std::abs;
  using std::sqrt;
  V.setIdentity();
  if (!all_finite(A)) {
    d.setConstant(std::numeric_limits<Scalar>::quiet_NaN());
    return;
  }
  const Scalar amax = A.cwiseAbs().maxCoeff();
  if (!(amax > Scalar(0))) {
    d.setZero();
    return;
  }
  const PowerOfTwoScale<Scalar> scale(amax);
  A = scale.down(A);
  const Scalar eps = Constants<Scalar>::epsilon();
  // 1. A = V T Vᵀ with T tridiagonal (`core/tridiagonal.hpp`; a column whose entries below
  // the subdiagonal have a norm below ε, ε·max|A| before the rescaling, is taken as
  // tridiagonal: an absolute perturbation within the accuracy above).
  const Tridiagonalization<Scalar, N> t(A);
  V = t.matrix();
  Scalar e[N > 1 ? N - 1 : 1];
  Scalar tmax = Scalar(0);
  for (int i = 0; i < N; ++i) d[i] = t.d[i], tmax = std::max(tmax, Scalar(abs(t.d[i])));
  for (int i = 0; i + 1 < N; ++i) e[i] = t.e[i], tmax = std::max(tmax, Scalar(abs(t.e[i])));
  const Scalar floor = eps * tmax;
  // 2. Implicit QR steps on the unreduced trailing block [start, end], deflating from the end.
  int end = N - 1, iterations = 0;
  while (end > 0 && iterations < 30 * N) {
    if (abs(e[end - 1]) <= floor || abs(e[end - 1]) <= eps * (abs(d[end - 1]) + abs(d[end]))) {
      e[end - 1] = Scalar(0);
      --end;
      continue;
    }
    int start = end - 1;
    while (start > 0 && abs(e[start - 1]) > floor && abs(e[start - 1]) > eps * (abs(d[start - 1]) + abs(d[start])))
      --start;
    ++iterations;
    // Wilkinson shift: the eigenvalue of the trailing 2×2 nearer to d[end].
    const Scalar delta = (d[end - 1] - d[end]) / Scalar(2), b = e[end - 1];
    const Scalar root = sqrt(delta * delta + b * b);
    const Scalar mu = d[end] - (b * b) / (delta + (delta < Scalar(0) ? Scalar(-root) : root));
    Scalar x = d[start] - mu, z = e[start];
    for (int k = start; k < end; ++k) {
      // G = [[c, s], [−s, c]] on (k, k+1) with Gᵀ(x, z) = (r, 0); T ← Gᵀ T G.
      const Scalar r = sqrt(x * x + z * z);
      Scalar c = Scalar(1), s = Scalar(0);
      if (r > Scalar(0)) {
        const Scalar inv = Scalar(1) / r;
        c = x * inv;
        s = -z * inv;
      }
      if (k > start) e[k - 1] = r;
      const Scalar a = d[k], bb = e[k], d2 = d[k + 1];
      const Scalar cc = c * c, ss = s * s, cs = c * s;
      d[k] = cc * a - Scalar(2) * cs * bb + ss * d2;
      d[k + 1] = ss * a + Scalar(2) * cs * bb + cc * d2;
      e[k] = cs * (a - d2) + (cc - ss) * bb;
      if (k + 1 < end) {
        z = -s * e[k + 1];
        e[k + 1] = c * e[k + 1];
      }
      x = e[k];
      for (int i = 0; i < N; ++i) {
        const Scalar vk = V(i, k), vk1 = V(i, k + 1);
        V(i, k) = c * vk - s * vk1;
        V(i, k + 1) = s * vk + c * vk1;
      }
    }
  }
  for (int i = 0; i < N; ++i) d[i] = scale.up(d[i]);
}

}  // namespace pce::detail
