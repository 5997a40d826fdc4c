// SPDX-License-Identifier: MIT
// core/tridiagonal.hpp: Householder tridiagonalisation by reconstruction (H T Hᵀ = A, H
// orthogonal, no reflection for a matrix that is already tridiagonal); float, double and
// long double.
#include "support/known_spectrum.hpp"
#include "support/scalars.hpp"

#include <pce/core/tridiagonal.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace {
using namespace pce_test;
using pce::detail::Tridiagonalization;

/// Ascending eigenvalues in [−1, 1], consecutive ones at least `gap` apart.
template <int N> Eigen::Matrix<long double, N, 1> random_spectrum(std::mt19937_64& rng, long double gap = 0) {
  std::uniform_real_distribution<long double> u(-1, 1);
  Eigen::Matrix<long double, N, 1> l;
  for (;;) {
    for (int i = 0; i < N; ++i) l[i] = u(rng);
    std::sort(l.data(), l.data() + N);
    bool ok = true;
    for (int i = 0; i + 1 < N; ++i) ok = ok && l[i + 1] - l[i] >= gap;
    if (ok) return l;
  }
}

template <class S, int N> void expect_reconstructs(const pce::MatN<S, N>& A) {
  const Tridiagonalization<S, N> t(A);
  pce::MatN<S, N> T = pce::MatN<S, N>::Zero();
  for (int i = 0; i < N; ++i) T(i, i) = t.d[i];
  for (int i = 0; i + 1 < N; ++i) T(i + 1, i) = T(i, i + 1) = t.e[i];
  const pce::MatN<S, N> H = t.matrix();
  const long double eps = std::numeric_limits<S>::epsilon();
  EXPECT_LE(static_cast<long double>((H * T * H.transpose() - A).cwiseAbs().maxCoeff()), 32 * eps) << "N=" << N;
  EXPECT_LE(static_cast<long double>((H.transpose() * H - pce::MatN<S, N>::Identity()).cwiseAbs().maxCoeff()),
            32 * eps);
}

template <class S> class TridiagonalTest : public testing::Test {};
TYPED_TEST_SUITE(TridiagonalTest, Scalars);

TYPED_TEST(TridiagonalTest, HouseholderReductionReconstructsTheMatrix) {
  using S = TypeParam;
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 100; ++trial) {
    expect_reconstructs<S, 3>(known_spectrum<3>(rng, random_spectrum<3>(rng)).matrix().template cast<S>());
    expect_reconstructs<S, 5>(known_spectrum<5>(rng, random_spectrum<5>(rng)).matrix().template cast<S>());
    expect_reconstructs<S, 9>(known_spectrum<9>(rng, random_spectrum<9>(rng)).matrix().template cast<S>());
  }
  // already tridiagonal (and diagonal): no reflection, H = I
  pce::MatN<S, 5> D = pce::MatN<S, 5>::Zero();
  D.diagonal() << S(1), S(-2), S(0.5), S(0), S(0.25);
  const Tridiagonalization<S, 5> t(D);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(t.beta[k], S(0));
  expect_reconstructs<S, 5>(D);
}

}  // namespace
