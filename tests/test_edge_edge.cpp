// SPDX-License-Identifier: MIT
// Tests for frames/edge_edge.hpp: the contract's sign and ordering conventions
// (docs/conventions.md), the closest points of the two lines, and status on bad input.
#include "support/conformance.hpp"
#include "support/scalars.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace {
using namespace pce_test;

template <class S> class EdgeEdge : public testing::Test {};
TYPED_TEST_SUITE(EdgeEdge, Scalars);

template <class S> pce::Vec12<S> ee(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                                    const Eigen::Vector3d& b1) {
  pce::Vec12<double> x;
  x << a0, a1, b0, b1;
  return cast12<S>(x);
}

TYPED_TEST(EdgeEdge, SignFollowsTheContract) {
  using S = TypeParam;
  // ea along +x at z = 0, eb along +y at z = 0.5: n = x × y = +z, l = (eb0 − ea0)·n̂ = 0.5.
  pce::Frame<S> f;
  ASSERT_EQ(pce::edge_edge_frame(ee<S>({-1, 0, 0}, {1, 0, 0}, {0, -1, 0.5}, {0, 1, 0.5}), f), pce::Status::ok);
  EXPECT_NEAR(double(f.l), 0.5, 1e-6);
  // Reversing one edge reverses n and the sign; reversing both keeps it.
  ASSERT_EQ(pce::edge_edge_frame(ee<S>({1, 0, 0}, {-1, 0, 0}, {0, -1, 0.5}, {0, 1, 0.5}), f), pce::Status::ok);
  EXPECT_NEAR(double(f.l), -0.5, 1e-6);
  ASSERT_EQ(pce::edge_edge_frame(ee<S>({1, 0, 0}, {-1, 0, 0}, {0, 1, 0.5}, {0, -1, 0.5}), f), pce::Status::ok);
  EXPECT_NEAR(double(f.l), 0.5, 1e-6);
  // Line distance, not segment distance: the lines' closest points may lie off the segments.
  ASSERT_EQ(pce::edge_edge_frame(ee<S>({5, 0, 0}, {6, 0, 0}, {0, 5, 0.5}, {0, 6, 0.5}), f), pce::Status::ok);
  EXPECT_NEAR(double(f.l), 0.5, 1e-5);
}

TYPED_TEST(EdgeEdge, ClosestPointsOfTheLines) {
  using S = TypeParam;
  std::mt19937_64 rng(31);
  for (int i = 0; i < 100; ++i) {
    const pce::Vec12<S> x = cast12<S>(random_configuration(PairKind::edge_edge, 0.6 * (i % 3 - 1), 1, 2, rng).x);
    pce::Frame<S> f;
    ASSERT_EQ(pce::edge_edge_frame(x, f), pce::Status::ok);
    const Eigen::Matrix<S, 3, 1> a0 = x.template segment<3>(0), a1 = x.template segment<3>(3),
                                 b0 = x.template segment<3>(6), b1 = x.template segment<3>(9);
    // ca = ea0 + β(ea1 − ea0), cb = eb0 − γ(eb1 − eb0); cb − ca = l n̂ ⟂ both edges.
    const Eigen::Matrix<S, 3, 1> ca = a0 + f.beta * (a1 - a0), cb = b0 - f.gamma * (b1 - b0);
    const Eigen::Matrix<S, 3, 1> d = cb - ca;
    const double tol = ulps<S>(64) * 8;
    EXPECT_NEAR(double(d.dot((a1 - a0).normalized())), 0.0, tol);
    EXPECT_NEAR(double(d.dot((b1 - b0).normalized())), 0.0, tol);
    EXPECT_NEAR(double(d.dot(f.n)), double(f.l), tol);
    const Eigen::Matrix<S, 3, 1> n = (a1 - a0).cross(b1 - b0).normalized();
    EXPECT_NEAR(double(f.l), double((b0 - a0).dot(n)), tol);
  }
}

TYPED_TEST(EdgeEdge, ParallelAndZeroLengthEdgesAreDegenerate) {
  using S = TypeParam;
  pce::Frame<S> f;
  f.l = S(42);
  EXPECT_EQ(pce::edge_edge_frame(ee<S>({0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {2, 1, 1}), f), pce::Status::degenerate);
  EXPECT_EQ(pce::edge_edge_frame(ee<S>({0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {-3, 1, 1}), f), pce::Status::degenerate);
  EXPECT_EQ(pce::edge_edge_frame(ee<S>({0, 0, 0}, {0, 0, 0}, {0, 1, 1}, {1, 1, 1}), f), pce::Status::degenerate);
  EXPECT_EQ(pce::edge_edge_frame(ee<S>({0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {0, 1, 1}), f), pce::Status::degenerate);
  EXPECT_EQ(f.l, S(42));
}

TYPED_TEST(EdgeEdge, NonFiniteInputIsInvalid) {
  using S = TypeParam;
  pce::Vec12<S> x = ee<S>({-1, 0, 0}, {1, 0, 0}, {0, -1, 0.5}, {0, 1, 0.5});
  x[7] = std::numeric_limits<S>::quiet_NaN();
  pce::Frame<S> f;
  EXPECT_EQ(pce::edge_edge_frame(x, f), pce::Status::invalid_input);
  x[7] = -std::numeric_limits<S>::infinity();
  EXPECT_EQ(pce::edge_edge_frame(x, f), pce::Status::invalid_input);
}

}  // namespace
