// SPDX-License-Identifier: MIT
// core/negative_eigenpairs.hpp: the negative eigenpairs of small symmetric matrices of
// known spectrum, from approximations of varying quality, give the PSD part to rounding;
// every way the fast path can fail is reported as a failure (the caller's fallback), never
// as a wrong answer; float, double and long double.
#include "support/known_spectrum.hpp"
#include "support/scalars.hpp"

#include <pce/core/negative_eigenpairs.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace {
using namespace pce_test;

/// max|(S − Σ λ q qᵀ) − psd(S)| / max|S| if the call succeeds, −1 if it reports failure.
template <class S, int N, int K>
long double psd_error(const KnownSpectrum<N>& k, const pce::MatN<S, N>& A, const S (&guess)[K]) {
  S lambda[K];
  pce::VecN<S, N> q[K];
  if (!pce::detail::negative_eigenpairs(A, guess, lambda, q)) return -1;
  Eigen::Matrix<long double, N, N> P = A.template cast<long double>();
  for (int j = 0; j < K; ++j) {
    const Eigen::Matrix<long double, N, 1> ql = q[j].template cast<long double>();
    P -= static_cast<long double>(lambda[j]) * ql * ql.transpose();
  }
  const long double scale = A.template cast<long double>().cwiseAbs().maxCoeff();
  return (P - k.psd_part()).cwiseAbs().maxCoeff() / scale;
}

template <class S> class NegativeEigenpairs : public testing::Test {};
TYPED_TEST_SUITE(NegativeEigenpairs, Scalars);

TYPED_TEST(NegativeEigenpairs, TwoNegativeEigenvaluesFromApproximationsWithinTenPercent) {
  using S = TypeParam;
  const long double eps = std::numeric_limits<S>::epsilon();
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<long double> u(0.05L, 1), rel(-0.1L, 0.1L);
  int solved = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::Matrix<long double, 5, 1> l;
    l << -u(rng), -u(rng), trial % 3 == 0 ? 0.0L : u(rng), u(rng), 50 * u(rng);  // a dominant one, as c2
    if (l[1] < l[0]) std::swap(l[0], l[1]);
    if (l[1] - l[0] < 0.3L * std::fabs(l[1])) continue;  // the 10 % approximations must stay separated
    const auto k = known_spectrum<5>(rng, l);
    const pce::MatN<S, 5> A = k.matrix().template cast<S>();
    const S guess[2] = {static_cast<S>(l[0] * (1 + rel(rng))), static_cast<S>(l[1] * (1 + rel(rng)))};
    const long double err = psd_error<S, 5, 2>(k, A, guess);
    ASSERT_GE(err, 0) << "trial " << trial;
    EXPECT_LE(err, 64 * eps) << "trial " << trial;
    ++solved;
  }
  EXPECT_GE(solved, 100);
}

TYPED_TEST(NegativeEigenpairs, OneNegativeEigenvalue) {
  using S = TypeParam;
  const long double eps = std::numeric_limits<S>::epsilon();
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<long double> u(0.05L, 1), rel(-0.3L, 0.3L);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix<long double, 3, 1> l(-u(rng), u(rng), 10 * u(rng));
    const auto k = known_spectrum<3>(rng, l);
    const S guess[1] = {static_cast<S>(l[0] * (1 + rel(rng)))};
    const long double err = psd_error<S, 3, 1>(k, k.matrix().template cast<S>(), guess);
    ASSERT_GE(err, 0) << "trial " << trial;
    EXPECT_LE(err, 64 * eps) << "trial " << trial;
  }
}

TYPED_TEST(NegativeEigenpairs, EveryMagnitudeOfTheScalar) {
  using S = TypeParam;
  using L = std::numeric_limits<S>;
  const long double eps = L::epsilon();
  std::mt19937_64 rng(23);
  Eigen::Matrix<long double, 5, 1> l;
  l << -0.8L, -0.3L, 0.2L, 0.6L, 40;
  const auto k = known_spectrum<5>(rng, l);
  for (int ex = L::min_exponent + 8; ex < L::max_exponent - 8; ex += (L::max_exponent - L::min_exponent) / 40) {
    const pce::MatN<S, 5> A = (k.matrix() * std::ldexp(1.0L, ex)).template cast<S>();
    const S guess[2] = {static_cast<S>(std::ldexp(-0.85L, ex)), static_cast<S>(std::ldexp(-0.28L, ex))};
    KnownSpectrum<5> ks = k;
    ks.lambda *= std::ldexp(1.0L, ex);
    const long double err = psd_error<S, 5, 2>(ks, A, guess);
    ASSERT_GE(err, 0) << "2^" << ex;
    EXPECT_LE(err, 64 * eps) << "2^" << ex;
  }
}

TYPED_TEST(NegativeEigenpairs, ReportsFailureInsteadOfAWrongAnswer) {
  using S = TypeParam;
  std::mt19937_64 rng(29);
  Eigen::Matrix<long double, 5, 1> l;
  l << -0.8L, -0.3L, 0.2L, 0.6L, 40;
  const auto k = known_spectrum<5>(rng, l);
  const pce::MatN<S, 5> A = k.matrix().template cast<S>();
  S lambda[2];
  pce::VecN<S, 5> q[2];
  const auto fails = [&](const pce::MatN<S, 5>& M, S g0, S g1) {
    const S guess[2] = {g0, g1};
    return !pce::detail::negative_eigenpairs(M, guess, lambda, q);
  };
  EXPECT_FALSE(fails(A, S(-0.75), S(-0.35)));  // the control: good approximations succeed
  EXPECT_TRUE(fails(A, S(-0.75), S(0.3)));      // beyond λ3: would converge to a positive eigenvalue
  EXPECT_TRUE(fails(A, S(-0.2), S(-0.35)));     // the first beyond λ2
  EXPECT_TRUE(fails(pce::MatN<S, 5>::Zero(), S(-1), S(-0.5)));
  pce::MatN<S, 5> N = A;
  N(2, 3) = N(3, 2) = std::numeric_limits<S>::quiet_NaN();
  EXPECT_TRUE(fails(N, S(-0.75), S(-0.35)));
  N = A;
  N(0, 0) = std::numeric_limits<S>::infinity();
  EXPECT_TRUE(fails(N, S(-0.75), S(-0.35)));
  // a second "negative" eigenvalue of rounding size: left to the fallback
  l << -0.8L, -std::numeric_limits<S>::epsilon(), 0.2L, 0.6L, 40;
  const pce::MatN<S, 5> B = known_spectrum<5>(rng, l).matrix().template cast<S>();
  EXPECT_TRUE(fails(B, S(-0.75), S(-1e-3)));
}

}  // namespace
