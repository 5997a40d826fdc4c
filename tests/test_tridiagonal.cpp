// SPDX-License-Identifier: MIT
// core/tridiagonal.hpp: Householder tridiagonalisation by reconstruction, the
// characteristic polynomial and its Sturm count against known spectra, Laguerre's step by
// its bracketing property, twisted-factorisation eigenvectors by their residuals; float,
// double and long double.
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
using pce::detail::CharacteristicPolynomial;
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
  EXPECT_LE(static_cast<long double>((H.transpose() * H - pce::MatN<S, N>::Identity()).cwiseAbs().maxCoeff()), 32 * eps);
  pce::VecN<S, N> y;
  for (int i = 0; i < N; ++i) y[i] = S(i + 1) / S(N);
  EXPECT_LE(static_cast<long double>((t.apply(y) - H * y).cwiseAbs().maxCoeff()), 32 * eps);
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

TYPED_TEST(TridiagonalTest, CharacteristicPolynomialAndSturmCountMatchTheSpectrum) {
  using S = TypeParam;
  const long double eps = std::numeric_limits<S>::epsilon();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<long double> u(-1.2L, 1.2L);
  for (int trial = 0; trial < 100; ++trial) {
    const auto k = known_spectrum<5>(rng, random_spectrum<5>(rng));
    const Tridiagonalization<S, 5> t(k.matrix().template cast<S>());
    for (int j = 0; j < 20; ++j) {
      const long double x = static_cast<long double>(static_cast<S>(u(rng)));
      long double gap = 1, prod = 1, G = 0, H = 0;
      int below = 0;
      for (int i = 0; i < 5; ++i) {
        gap = std::min(gap, std::fabs(k.lambda[i] - x));
        prod *= k.lambda[i] - x;
        G += 1 / (x - k.lambda[i]);
        H += 1 / ((x - k.lambda[i]) * (x - k.lambda[i]));
        below += k.lambda[i] < x ? 1 : 0;
      }
      if (gap < 1e3L * eps) continue;  // too close to an eigenvalue for a sign to be sure
      const CharacteristicPolynomial<S, 5> cp(t, static_cast<S>(x));
      EXPECT_EQ(cp.below, below) << "x=" << static_cast<double>(x);
      // p = Π(λ_i − x); p′/p = Σ 1/(x − λ_i); p″/p = (p′/p)² − Σ 1/(x − λ_i)²
      const long double tol = 2000 * eps / gap;
      EXPECT_NEAR(static_cast<long double>(cp.p) / prod, 1.0L, tol);
      EXPECT_NEAR(static_cast<long double>(cp.dp) / static_cast<long double>(cp.p) / G, 1.0L, tol / std::min(1.0L, std::fabs(G) * gap));
      EXPECT_NEAR(static_cast<long double>(cp.ddp) / static_cast<long double>(cp.p), G * G - H, tol * (G * G + H));
    }
  }
}

TYPED_TEST(TridiagonalTest, LaguerreStepsStayBetweenNeighboursAndConverge) {
  using S = TypeParam;
  const long double eps = std::numeric_limits<S>::epsilon();
  std::mt19937_64 rng(9);
  for (int trial = 0; trial < 100; ++trial) {
    // Separated eigenvalues: near a cluster Laguerre's iteration is at first only linear.
    const auto k = known_spectrum<5>(rng, random_spectrum<5>(rng, 0.05L));
    const Tridiagonalization<S, 5> t(k.matrix().template cast<S>());
    for (int j = 0; j + 1 < 5; ++j) {  // start between λ_j and λ_{j+1}, go both ways
      for (const bool up : {true, false}) {
        S x = static_cast<S>((k.lambda[j] + k.lambda[j + 1]) / 2);
        const long double target = up ? k.lambda[j + 1] : k.lambda[j];
        long double previous = std::fabs(x - target);
        for (int it = 0; it < 8; ++it) {
          x += CharacteristicPolynomial<S, 5>(t, x).laguerre_step(up);
          const long double dist = std::fabs(x - target);
          EXPECT_LE(dist, previous + 256 * eps) << "the step left the bracket or moved away";
          previous = dist;
        }
        // the eigenvalues of the rounded matrix and the rounding of p near them
        EXPECT_LE(previous, 256 * eps) << "j=" << j << " up=" << up;
      }
    }
  }
}

TYPED_TEST(TridiagonalTest, TwistedEigenvectorHasASmallResidual) {
  using S = TypeParam;
  const long double eps = std::numeric_limits<S>::epsilon();
  const S pivmin = std::numeric_limits<S>::min() / std::numeric_limits<S>::epsilon();
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 100; ++trial) {
    const auto k = known_spectrum<5>(rng, random_spectrum<5>(rng));
    const pce::MatN<S, 5> A = k.matrix().template cast<S>();
    const Tridiagonalization<S, 5> t(A);
    for (int j = 0; j < 5; ++j) {
      pce::VecN<S, 5> y;
      const S gamma = pce::detail::twisted_eigenvector(t, static_cast<S>(k.lambda[j]), pivmin, y);
      const pce::VecN<S, 5> q = t.apply(y / y.norm());
      const Eigen::Matrix<long double, 5, 1> ql = q.template cast<long double>();
      const long double res = (k.matrix() * ql - k.lambda[j] * ql).norm();
      EXPECT_LE(res, 64 * eps) << "j=" << j;
      EXPECT_LE(std::fabs(static_cast<long double>(gamma)) / static_cast<long double>(y.norm()), 64 * eps);
    }
  }
}

}  // namespace
