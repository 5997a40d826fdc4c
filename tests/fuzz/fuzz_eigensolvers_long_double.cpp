// SPDX-License-Identifier: MIT
/// @file
/// `pce::project_psd` in long double, and the long double eigensolver of the PSD checks,
/// which shares its 12×12 instantiation of `Eigen::SelfAdjointEigenSolver` (see
/// `fuzz_eigensolvers.hpp`).
#include "fuzz_eigensolvers.hpp"

namespace pce_fuzz {

MinEig min_eigenvalue(const Eigen::Matrix<long double, 12, 12>& M) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<long double, 12, 12>> es(M, Eigen::EigenvaluesOnly);
  MinEig r;
  r.converged = es.info() == Eigen::Success;
  if (r.converged) r.lambda_min = es.eigenvalues()[0];
  return r;
}

}  // namespace pce_fuzz

namespace pce {
PCE_FUZZ_PROJECT_PSD(, long double)
}  // namespace pce
