// SPDX-License-Identifier: MIT
/// @file
/// The dense symmetric eigensolvers of the fuzz body. Eigen's `SelfAdjointEigenSolver` is the
/// most expensive template the body instantiates (through `pce::project_psd`, once per scalar
/// and size: 12×12 for the plane kinds and closest-feature evaluation, 9×9 for point_edge,
/// 6×6 for point_point). Those instantiations are the ones `pce::precompiled` compiles
/// (`pce/core/precompiled.hpp`); the fuzz targets declare them extern here and link that
/// library's archive (not the target: its `PCE_PRECOMPILED` would also take the run-time
/// `projected_hessian` dispatch, the code under test, out of the sanitized units). So
/// `project_psd`, Eigen's eigensolver behind `Projection::numerical`, runs unsanitized and
/// without Eigen's assertions, as it does in `pce-scene-fuzz`; every strategy of every pair
/// kind up to that call, and the checks, are compiled with the sanitizers. The checks' own long
/// double eigensolver (`min_eigenvalue`, which also reports convergence) is compiled with the
/// body's flags in `fuzz_min_eigenvalue.cpp`.
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

#if !defined(PCE_PRECOMPILED)
namespace pce {
// project_psd (12×12, 9×9, 6×6) and symmetric_eigenvalues, from pce::precompiled's archive.
PCE_PSD_PROJECTION_INSTANCES(extern, float)
PCE_PSD_PROJECTION_INSTANCES(extern, double)
PCE_PSD_PROJECTION_INSTANCES(extern, long double)
}  // namespace pce
#endif
