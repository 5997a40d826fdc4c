// SPDX-License-Identifier: MIT
// Tests for energy/psd_projection.hpp: the reference numerical projection is PSD, leaves
// PSD matrices alone, is idempotent, and is the Frobenius-nearest PSD matrix (checked by
// its optimality conditions: P ⪰ 0, P − H ⪰ 0, P (P − H) = 0).
#include "support/conformance.hpp"
#include "support/scalars.hpp"

#include <gtest/gtest.h>

namespace {
using namespace pce_test;

template <class S> class PsdProjection : public testing::Test {};
TYPED_TEST_SUITE(PsdProjection, Scalars);

TYPED_TEST(PsdProjection, NearestPsdMatrix) {
  using S = TypeParam;
  std::mt19937_64 rng(71);
  std::normal_distribution<double> N(0, 1);
  for (int t = 0; t < 20; ++t) {
    pce::Mat12<S> A;
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) A(i, j) = S(N(rng));
    const pce::Mat12<S> H = (A + A.transpose()) / S(2);
    const pce::Mat12<S> P = pce::project_psd(H);
    const double n = max_abs(H), tol = ulps<S>(200) * n;
    EXPECT_GE(min_eigenvalue(P), -tol);
    EXPECT_GE(min_eigenvalue((P - H).eval()), -tol);
    EXPECT_LT(max_abs((P * (P - H)).eval()), tol * n);
    EXPECT_LT(max_abs((pce::project_psd(P) - P).eval()), tol);
    // A PSD input comes back unchanged (the early exit).
    const pce::Mat12<S> G = A * A.transpose();
    EXPECT_EQ(pce::project_psd(G), G);
  }
}

}  // namespace
