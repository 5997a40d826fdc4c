// SPDX-License-Identifier: MIT
// core/jacobi.hpp: the small symmetric eigensolvers (cyclic Jacobi, Householder + implicit
// QR) by their residuals and orthogonality, in float, double and long double, on random
// matrices of every size the library uses, on matrices at the ends of the scalar's range,
// and on the inputs the fuzzer found (docs/fuzzing.md, findings 3 and 4).
#include "support/scalars.hpp"

#include <pce/core/jacobi.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace {
using namespace pce_test;

/// A random symmetric matrix of rank N − rank_deficit (a sum of that many rank-one terms
/// of either sign; no eigensolver needed to build it).
template <class S, int N> pce::MatN<S, N> random_symmetric(std::mt19937_64& rng, int rank_deficit = 0) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix<double, N, N> Sym = Eigen::Matrix<double, N, N>::Zero();
  for (int k = 0; k < N - rank_deficit; ++k) {
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) v[i] = u(rng);
    Sym += (u(rng) < 0 ? -1.0 : 1.0) * v * v.transpose();
  }
  return Sym.template cast<S>();
}

/// max|A V − V diag(d)| / max|A| and max|VᵀV − I|, in long double.
template <class S, int N> std::pair<long double, long double> quality(const pce::MatN<S, N>& A,
                                                                      const pce::VecN<S, N>& d,
                                                                      const pce::MatN<S, N>& V) {
  using LM = Eigen::Matrix<long double, N, N>;
  const LM Al = A.template cast<long double>(), Vl = V.template cast<long double>();
  const Eigen::Matrix<long double, N, 1> dl = d.template cast<long double>();
  const long double scale = Al.cwiseAbs().maxCoeff();
  const long double res = (Al * Vl - Vl * dl.asDiagonal()).cwiseAbs().maxCoeff() / (scale > 0 ? scale : 1);
  const long double orth = (Vl.transpose() * Vl - LM::Identity()).cwiseAbs().maxCoeff();
  return {res, orth};
}

template <class S, int N> void expect_qr_accurate(const pce::MatN<S, N>& A, const char* what) {
  pce::VecN<S, N> d;
  pce::MatN<S, N> V;
  pce::detail::symmetric_qr_eigen(A, d, V);
  ASSERT_TRUE(d.allFinite()) << what;
  ASSERT_TRUE(V.allFinite()) << what;
  const auto [res, orth] = quality<S, N>(A, d, V);
  const long double eps = std::numeric_limits<S>::epsilon();
  EXPECT_LE(res, 64 * eps) << what << " N=" << N;
  EXPECT_LE(orth, 64 * eps) << what << " N=" << N;
}

template <class S> class SymmetricQr : public testing::Test {};
TYPED_TEST_SUITE(SymmetricQr, Scalars);

TYPED_TEST(SymmetricQr, RandomMatricesOfEverySize) {
  using S = TypeParam;
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int deficit = trial % 4;
    expect_qr_accurate<S, 2>(random_symmetric<S, 2>(rng, deficit % 2), "random");
    expect_qr_accurate<S, 3>(random_symmetric<S, 3>(rng, deficit), "random");
    expect_qr_accurate<S, 5>(random_symmetric<S, 5>(rng, deficit), "random");
    expect_qr_accurate<S, 9>(random_symmetric<S, 9>(rng, deficit), "random");
  }
}

TYPED_TEST(SymmetricQr, EveryMagnitudeOfTheScalar) {
  using S = TypeParam;
  using L = std::numeric_limits<S>;
  std::mt19937_64 rng(11);
  // From the subnormal range to the largest finite numbers: the solver squares entries,
  // which must neither overflow nor underflow (docs/fuzzing.md, finding 3).
  for (int ex = L::min_exponent - L::digits + 4; ex < L::max_exponent - 4;
       ex += (L::max_exponent - L::min_exponent) / 40) {
    const pce::MatN<S, 5> A = random_symmetric<S, 5>(rng, 1) * std::ldexp(S(1), ex);
    if (ex < L::min_exponent) {  // subnormal entries: only the eigenvalues' absolute accuracy is defined
      pce::VecN<S, 5> d;
      pce::MatN<S, 5> V;
      pce::detail::symmetric_qr_eigen(A, d, V);
      EXPECT_TRUE(d.allFinite() && V.allFinite()) << "2^" << ex;
      continue;
    }
    SCOPED_TRACE(testing::Message() << "entries ~2^" << ex);
    expect_qr_accurate<S, 5>(A, "scaled");
  }
}

TYPED_TEST(SymmetricQr, ZeroAndNonFinite) {
  using S = TypeParam;
  pce::VecN<S, 5> d;
  pce::MatN<S, 5> V;
  pce::detail::symmetric_qr_eigen(pce::MatN<S, 5>::Zero().eval(), d, V);
  EXPECT_EQ(d, (pce::VecN<S, 5>::Zero()));
  EXPECT_EQ(V, (pce::MatN<S, 5>::Identity()));
  pce::MatN<S, 5> A = pce::MatN<S, 5>::Identity();
  A(1, 2) = A(2, 1) = std::numeric_limits<S>::quiet_NaN();
  pce::detail::symmetric_qr_eigen(A, d, V);
  EXPECT_TRUE(d.array().isNaN().all()) << "NaN in, NaN out";
  A(1, 2) = A(2, 1) = std::numeric_limits<S>::infinity();
  pce::detail::symmetric_qr_eigen(A, d, V);
  EXPECT_TRUE(d.array().isNaN().all());
}

// The reduced matrix of an exact projection that the fuzzer found (float, edge-edge,
// cubic penalty with k = 1e-3): entries from 1e-11 down to 1e-20, whose squares are
// subnormal in float. Before the rescaling, β = 2/|v|² overflowed and every eigenvalue
// came out NaN.
TEST(SymmetricQr, FuzzerFindingGradedFloatMatrix) {
  pce::MatN<float, 5> A;
  A << 1.30461e-11f, 9.48081e-12f, 5.13223e-12f, -9.62271e-21f, 4.63951e-20f,  //
      9.48081e-12f, 6.88987e-12f, 3.72968e-12f, 0, 1.66748e-20f,               //
      5.13223e-12f, 3.72968e-12f, 2.01898e-12f, 0, -2.35817e-20f,              //
      -9.62271e-21f, 0, 0, 0, 0,                                               //
      4.63951e-20f, 1.66748e-20f, -2.35817e-20f, 0, 0;
  expect_qr_accurate<float, 5>(A, "fuzzer finding");
}

// Entries below the subdiagonal at about √ε of the subdiagonal one: computing the tail's
// norm as |x|² − x₁² cancelled to zero and the reflection was skipped, an error of order
// √ε·max|A| (docs/fuzzing.md, finding 4).
TYPED_TEST(SymmetricQr, SmallTailBelowTheSubdiagonalIsNotDropped) {
  using S = TypeParam;
  const S t = std::sqrt(std::numeric_limits<S>::epsilon()) / S(4);
  pce::MatN<S, 5> A;
  A << S(0), S(1), t, t, S(0),         //
      S(1), S(0.5), S(0), S(0), S(0),  //
      t, S(0), S(-0.25), S(0), S(0),   //
      t, S(0), S(0), S(0.75), S(0),    //
      S(0), S(0), S(0), S(0), S(0.125);
  expect_qr_accurate<S, 5>(A, "small tail");
}

TYPED_TEST(SymmetricQr, AgreesWithJacobi) {
  using S = TypeParam;
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 50; ++trial) {
    const pce::MatN<S, 5> A = random_symmetric<S, 5>(rng);
    pce::VecN<S, 5> d;
    pce::MatN<S, 5> V;
    pce::detail::symmetric_qr_eigen(A, d, V);
    pce::MatN<S, 5> J = A, W;
    pce::detail::jacobi_eigen(J, W);
    pce::VecN<S, 5> dj = J.diagonal();
    std::sort(d.data(), d.data() + 5);
    std::sort(dj.data(), dj.data() + 5);
    EXPECT_LE((d - dj).cwiseAbs().maxCoeff(), 32 * std::numeric_limits<S>::epsilon() * A.cwiseAbs().maxCoeff());
  }
}

TYPED_TEST(SymmetricQr, JacobiResidualsAndOrthogonality) {
  using S = TypeParam;
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const pce::MatN<S, 3> A = random_symmetric<S, 3>(rng, trial % 3);
    pce::MatN<S, 3> J = A, W;
    pce::detail::jacobi_eigen(J, W);
    const auto [res, orth] = quality<S, 3>(A, pce::VecN<S, 3>(J.diagonal()), W);
    EXPECT_LE(res, 64 * std::numeric_limits<S>::epsilon());
    EXPECT_LE(orth, 64 * std::numeric_limits<S>::epsilon());
  }
}

}  // namespace
