// SPDX-License-Identifier: MIT
/// @file
/// The tests' dense symmetric eigensolvers, compiled once (`eigensolvers_float.cpp`,
/// `eigensolvers_double.cpp`, `eigensolvers_long_double.cpp` and
/// `eigensolvers_high_precision.cpp`, linked into every test as `pce_test_support`)
/// instead of in every test executable. One translation unit per scalar type: they build
/// in parallel, and g++ 12 is superlinear on several scalar types in one unit (the three
/// native ones together took 105 CPU seconds, apart 71).
///
/// Eigen's `SelfAdjointEigenSolver` costs about 6 s of compile time per scalar type and
/// matrix size, and the suite needs it for four scalars (float, double, long double and
/// the 50-digit reference) and three sizes (12, 9 and 6: the plane and the point kinds): directly, and through
/// `pce::project_psd`, which `pce::projected_hessian` instantiates for every scalar it is called with. The explicit
/// instantiation declarations below keep each test from compiling those bodies again (`pce::project_psd` for the
/// native scalars comes from pce::precompiled, which every test links).
#pragma once

#include "high_precision.hpp"

#include <pce/energy/closest_feature.hpp>
#include <pce/energy/psd_projection.hpp>

#include <Eigen/Eigenvalues>

namespace pce_test {

/// Smallest eigenvalue of a symmetric matrix (computed in its own precision), as double.
template <class S, int N> double min_eigenvalue(const Eigen::Matrix<S, N, N>& H) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<S, N, N>> es(H);
  return static_cast<double>(es.eigenvalues().minCoeff());
}

/// Eigenvalues (ascending) and orthonormal eigenvectors of a symmetric matrix.
template <class S, int N> struct SymmetricEigen {
  Eigen::Matrix<S, N, 1> values;
  Eigen::Matrix<S, N, N> vectors;
};
template <class S, int N> SymmetricEigen<S, N> symmetric_eigen(const Eigen::Matrix<S, N, N>& H) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<S, N, N>> es(H);
  return {es.eigenvalues(), es.eigenvectors()};
}

#define PCE_TEST_EIGENSOLVERS(EXTERN, S)                                                         \
  EXTERN template double min_eigenvalue<S, 12>(const Eigen::Matrix<S, 12, 12>&);                 \
  EXTERN template double min_eigenvalue<S, 9>(const Eigen::Matrix<S, 9, 9>&);                    \
  EXTERN template SymmetricEigen<S, 9> symmetric_eigen<S, 9>(const Eigen::Matrix<S, 9, 9>&);     \
  EXTERN template SymmetricEigen<S, 12> symmetric_eigen<S, 12>(const Eigen::Matrix<S, 12, 12>&); \
  EXTERN template double min_eigenvalue<S, 6>(const Eigen::Matrix<S, 6, 6>&);                    \
  EXTERN template SymmetricEigen<S, 6> symmetric_eigen<S, 6>(const Eigen::Matrix<S, 6, 6>&);
PCE_TEST_EIGENSOLVERS(extern, float)
PCE_TEST_EIGENSOLVERS(extern, double)
PCE_TEST_EIGENSOLVERS(extern, long double)

}  // namespace pce_test

// pce::project_psd for the 50-digit reference (pce::precompiled has the native scalars'),
// and the run-time projected_hessian of the kinds several tests compare in 50 digits
// (support/projections_high_precision.cpp).
namespace pce {
PCE_PSD_PROJECTION_INSTANCES(extern, pce_test::HighPrecision)
PCE_PAIR_ENERGY_INSTANCES(extern, pce_test::HighPrecision)
PCE_POINT_EDGE_ENERGY_INSTANCES(extern, pce_test::HighPrecision)
PCE_POINT_POINT_ENERGY_INSTANCES(extern, pce_test::HighPrecision)
PCE_CLOSEST_FEATURE_INSTANCES(extern, pce_test::HighPrecision)
}  // namespace pce
