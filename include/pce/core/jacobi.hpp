// SPDX-License-Identifier: MIT
/// @file
/// Eigen-decomposition of a small fixed-size symmetric matrix by cyclic Jacobi rotations
/// (Rutishauser's update; Golub & Van Loan, Matrix Computations, Sec. 8.5). Used where no
/// closed form exists: the mollified energy's 3×3 block and the exact projection's ≤ 5×5
/// reduced problem (`energy/exact_projection.hpp`). Unlike a trigonometric or
/// characteristic-polynomial closed form it keeps small eigenvalues of graded matrices
/// accurate to their own size (Demmel & Veselić 1992).
#pragma once

#include <pce/core/types.hpp>

#include <cmath>

namespace pce::detail {

/// Diagonalises the symmetric `A` in place (`A` ends diagonal, eigenvalues unsorted on its
/// diagonal) and returns the orthonormal eigenvectors as the columns of `V`. An
/// off-diagonal entry is treated as zero when it is below `ε/4·√|a_pp a_qq|` (relative
/// accuracy) or not above `floor` (an absolute threshold, so that a zero diagonal entry
/// cannot keep it sweeping; 0 keeps full relative accuracy for graded matrices).
template <class Scalar, int N> void jacobi_eigen(MatN<Scalar, N>& A, MatN<Scalar, N>& V, const Scalar& floor) {
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
        const Scalar t = (at > Scalar(1) / eps ? Scalar(1) / (Scalar(2) * at) : Scalar(1) / (at + sqrt(at * at + Scalar(1)))) *
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
template <class Scalar, int N> void jacobi_eigen(MatN<Scalar, N>& A, MatN<Scalar, N>& V) {
  const Scalar eps = Constants<Scalar>::epsilon();
  jacobi_eigen(A, V, Scalar(eps * eps * A.cwiseAbs().maxCoeff()));
}

}  // namespace pce::detail
