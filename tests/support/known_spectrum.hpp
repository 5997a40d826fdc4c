// SPDX-License-Identifier: MIT
/// @file
/// Symmetric matrices with a prescribed spectrum, `A = U diag(λ) Uᵀ` with a random
/// orthogonal U (a product of Householder reflections of random vectors), built in long
/// double without any eigensolver: the reference for the small eigensolvers' tests.
#pragma once

#include <pce/core/types.hpp>

#include <random>

namespace pce_test {

template <int N> struct KnownSpectrum {
  Eigen::Matrix<long double, N, N> U;       ///< orthonormal eigenvectors (columns)
  Eigen::Matrix<long double, N, 1> lambda;  ///< eigenvalues, as given
  Eigen::Matrix<long double, N, N> matrix() const { return U * lambda.asDiagonal() * U.transpose(); }
  /// the nearest PSD matrix, U max(Λ, 0) Uᵀ
  Eigen::Matrix<long double, N, N> psd_part() const { return U * lambda.cwiseMax(0.0L).asDiagonal() * U.transpose(); }
};

template <int N> KnownSpectrum<N> known_spectrum(std::mt19937_64& rng, const Eigen::Matrix<long double, N, 1>& lambda) {
  std::uniform_real_distribution<long double> u(-1, 1);
  KnownSpectrum<N> k;
  k.lambda = lambda;
  k.U.setIdentity();
  for (int r = 0; r < N; ++r) {
    Eigen::Matrix<long double, N, 1> v;
    for (int i = 0; i < N; ++i) v[i] = u(rng);
    k.U -= (2.0L / v.squaredNorm()) * (k.U * v) * v.transpose();
  }
  return k;
}

}  // namespace pce_test
