// SPDX-License-Identifier: MIT
/// @file
/// The dense symmetric eigensolvers of the fuzz body, compiled in translation units of
/// their own, one per scalar type (`fuzz_eigensolvers_float.cpp`,
/// `fuzz_eigensolvers_double.cpp`, `fuzz_eigensolvers_long_double.cpp`, same sanitizer
/// flags), so that the parts of the fuzz target build in parallel: Eigen's
/// `SelfAdjointEigenSolver` is the most expensive template the body instantiates (once per
/// scalar and size through `pce::project_psd`: 12×12 for the plane kinds and
/// closest-feature evaluation, 9×9 for point_edge, 6×6 for point_point; once more for the
/// long double checker, which pads every matrix to 12×12).
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
// 12×12: the plane kinds and closest-feature evaluation; 9×9 and 6×6: point_edge and
// point_point.
#define PCE_FUZZ_PROJECT_PSD(EXTERN, S)                         \
  EXTERN template Mat12<S> project_psd<S, 12>(const Mat12<S>&); \
  EXTERN template Mat9<S> project_psd<S, 9>(const Mat9<S>&);    \
  EXTERN template Mat6<S> project_psd<S, 6>(const Mat6<S>&);
PCE_FUZZ_PROJECT_PSD(extern, float)
PCE_FUZZ_PROJECT_PSD(extern, double)
PCE_FUZZ_PROJECT_PSD(extern, long double)
}  // namespace pce
