// SPDX-License-Identifier: MIT
/// @file
/// The generic numerical PSD projection every closed form is compared against: the
/// nearest positive semidefinite matrix in the Frobenius norm, `V max(Λ, 0) Vᵀ` from a
/// full symmetric eigendecomposition (Higham 1988). This is what solvers do without a
/// closed-form eigensystem; it costs a 12×12 eigensolve per pair.
#pragma once

#include <pce/core/types.hpp>

#include <Eigen/Eigenvalues>

namespace pce {

/// Nearest PSD matrix `V max(Λ, 0) Vᵀ` of a symmetric `H`; returns `H` unchanged when its
/// smallest eigenvalue is already ≥ 0 (the cheap early exit).
template <class Scalar, int N> Eigen::Matrix<Scalar, N, N> project_psd(const Eigen::Matrix<Scalar, N, N>& H) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<Scalar, N, N>> es(H);
  const auto& lam = es.eigenvalues();
  if (lam.minCoeff() >= Scalar(0)) return H;
  Eigen::Matrix<Scalar, N, 1> clamped = lam;
  for (int i = 0; i < N; ++i)
    if (clamped[i] < Scalar(0)) clamped[i] = Scalar(0);
  return es.eigenvectors() * clamped.asDiagonal() * es.eigenvectors().transpose();
}

}  // namespace pce
