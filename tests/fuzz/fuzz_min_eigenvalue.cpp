// SPDX-License-Identifier: MIT
/// @file
/// The long double eigensolver of the PSD checks (`min_eigenvalue`, see
/// `fuzz_eigensolvers.hpp`), compiled with the fuzz body's sanitizer flags in a translation
/// unit of its own.
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
