// SPDX-License-Identifier: MIT
/// @file
/// The generic numerical PSD projection every closed form is compared against: the
/// nearest positive semidefinite matrix in the Frobenius norm, `V max(Λ, 0) Vᵀ` from a
/// full symmetric eigendecomposition (Higham 1988). This is what solvers do without a
/// closed-form eigensystem; it costs a 12×12 eigensolve per pair.
#pragma once

#include <pce/core/precompiled.hpp>
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

/// Eigenvalues of a symmetric `H`, ascending (Eigen's `SelfAdjointEigenSolver`): the check
/// that a projected Hessian is PSD (`symmetric_eigenvalues(H)[0] >= 0`), with the eigensolver
/// `project_psd` uses (compiled once in `pce::precompiled`).
template <class Scalar, int N> VecN<Scalar, N> symmetric_eigenvalues(const Eigen::Matrix<Scalar, N, N>& H) {
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix<Scalar, N, N>>(H, Eigen::EigenvaluesOnly).eigenvalues();
}

/// The instantiations `pce::precompiled` compiles (`core/precompiled.hpp`).
// (EXTERN is `extern` or nothing and S a type: neither can be parenthesised.)
// NOLINTBEGIN(bugprone-macro-parentheses)
#define PCE_PSD_PROJECTION_INSTANCES(EXTERN, S)                           \
  EXTERN template Mat12<S> project_psd<S, 12>(const Mat12<S>&);           \
  EXTERN template Mat9<S> project_psd<S, 9>(const Mat9<S>&);              \
  EXTERN template Mat6<S> project_psd<S, 6>(const Mat6<S>&);              \
  EXTERN template Vec12<S> symmetric_eigenvalues<S, 12>(const Mat12<S>&); \
  EXTERN template Vec9<S> symmetric_eigenvalues<S, 9>(const Mat9<S>&);    \
  EXTERN template Vec6<S> symmetric_eigenvalues<S, 6>(const Mat6<S>&);
// NOLINTEND(bugprone-macro-parentheses)
PCE_DECLARE_PRECOMPILED(PCE_PSD_PROJECTION_INSTANCES)

}  // namespace pce
