// SPDX-License-Identifier: MIT
/// @file
/// The dense symmetric eigensolvers of the fuzz body, compiled in their own translation
/// unit (`fuzz_eigensolvers.cpp`, same sanitizer flags) so that the two halves of the
/// fuzz target build in parallel: Eigen's `SelfAdjointEigenSolver` is the most expensive
/// template the body instantiates (once per scalar through `pce::project_psd`, once more
/// for the long double checker).
#pragma once

#include <pce/energy/psd_projection.hpp>

namespace pce_fuzz {

/// Smallest eigenvalue of the symmetric `M` (its lower triangle), in long double.
struct MinEig {
  long double lambda_min = 0;
  bool converged = true;
};
MinEig min_eigenvalue(const Eigen::Matrix<long double, 12, 12>& M);

}  // namespace pce_fuzz

namespace pce {
#define PCE_FUZZ_PROJECT_PSD(EXTERN, S) EXTERN template Mat12<S> project_psd<S, 12>(const Mat12<S>&);
PCE_FUZZ_PROJECT_PSD(extern, float)
PCE_FUZZ_PROJECT_PSD(extern, double)
PCE_FUZZ_PROJECT_PSD(extern, long double)
}  // namespace pce
