// SPDX-License-Identifier: MIT
// Tests for frames/frame.hpp: the reduced frame's defining properties, the frame Jacobian
// and both pullbacks, and the exact power-of-two rescaling.
#include "support/conformance.hpp"
#include "support/scalars.hpp"

#include <gtest/gtest.h>

namespace {
using namespace pce_test;

template <class S> class Frame : public testing::Test {};
TYPED_TEST_SUITE(Frame, Scalars);

template <class S> Eigen::Matrix<S, 3, 1> frame_edge(const pce::Frame<S>& f, const pce::Vec12<S>& x, int k) {
  Eigen::Matrix<S, 3, 1> c = Eigen::Matrix<S, 3, 1>::Zero();
  for (int j = 0; j < 4; ++j) c += f.P(k, j) * x.template segment<3>(3 * j);
  return c;
}

TYPED_TEST(Frame, EdgesAreMutuallyOrthogonalAndMatchTheBasis) {
  using S = TypeParam;
  std::mt19937_64 rng(11);
  for (PairKind kind : {PairKind::vertex_face, PairKind::edge_edge})
    for (int i = 0; i < 50; ++i) {
      const pce::Vec12<S> x = cast12<S>(random_configuration(kind, 0.3 * (i % 5 - 2), 1.0, 3.0, rng).x);
      pce::Frame<S> f;
      ASSERT_EQ(with_pair(kind, [&](auto pair) { return decltype(pair)::frame(x, f); }), pce::Status::ok);
      const auto c0 = frame_edge(f, x, 0), c1 = frame_edge(f, x, 1), c2 = frame_edge(f, x, 2);
      const double tol = ulps<S>(64);
      // (ê0, ê1, n̂) is a right-handed orthonormal basis.
      EXPECT_NEAR(double(f.n.norm()), 1.0, tol);
      EXPECT_NEAR(double(f.t0.norm()), 1.0, tol);
      EXPECT_NEAR(double(f.t1.norm()), 1.0, tol);
      EXPECT_LT(max_abs((f.t0.cross(f.t1) - f.n).eval()), tol);
      // c0 = |e0| ê0, c1 = e1⊥ = |e1⊥| ê1, c2 = e2⊥ = l n̂.
      EXPECT_LT(max_abs((c0 - f.a0 * f.t0).eval()), tol * 8);
      EXPECT_LT(max_abs((c1 - f.a1 * f.t1).eval()), tol * 8);
      EXPECT_LT(max_abs((c2 - f.l * f.n).eval()), tol * 8);
      EXPECT_NEAR(double(c0.dot(c1)), 0.0, tol * 8);
      EXPECT_NEAR(double(c0.dot(c2)), 0.0, tol * 8);
      EXPECT_NEAR(double(c1.dot(c2)), 0.0, tol * 8);
      // The coefficients of each frame edge sum to zero: translation invariance.
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(double(f.P.row(k).sum()), 0.0, tol * 8);
    }
}

TYPED_TEST(Frame, JacobianAndPullbacksAgree) {
  using S = TypeParam;
  std::mt19937_64 rng(12);
  const pce::Vec12<S> x = cast12<S>(random_configuration(PairKind::edge_edge, 0.2, 1.0, 0.0, rng).x);
  pce::Frame<S> f;
  ASSERT_EQ(pce::edge_edge_frame(x, f), pce::Status::ok);
  const Eigen::Matrix<S, 9, 12> J = pce::frame_jacobian(f);
  pce::Vec9<S> gc;
  pce::Mat9<S> A;
  std::uniform_real_distribution<double> U(-1, 1);
  for (int i = 0; i < 9; ++i) {
    gc[i] = S(U(rng));
    for (int j = 0; j < 9; ++j) A(i, j) = S(U(rng));
  }
  EXPECT_LT(rel_error(pce::pullback(f, gc), (J.transpose() * gc).eval()), ulps<S>(16));
  // A FrameBlocks matrix with random blocks (and its zero (0,1) block) pulled back.
  pce::FrameBlocks<S> b;
  b.h00 = A.template block<3, 3>(0, 0) + A.template block<3, 3>(0, 0).transpose();
  b.h11 = A.template block<3, 3>(3, 3) + A.template block<3, 3>(3, 3).transpose();
  b.h22 = A.template block<3, 3>(6, 6) + A.template block<3, 3>(6, 6).transpose();
  b.h02 = A.template block<3, 3>(0, 6);
  b.h12 = A.template block<3, 3>(3, 6);
  const pce::Mat9<S> D = b.dense();
  EXPECT_EQ(D, D.transpose());
  EXPECT_TRUE((D.template block<3, 3>(0, 3).isZero(0)));
  EXPECT_LT(rel_error(pce::pullback(f, b), (J.transpose() * D * J).eval()), ulps<S>(64));
}

TYPED_TEST(Frame, PowerOfTwoScalingIsExact) {
  using S = TypeParam;
  std::mt19937_64 rng(13);
  const pce::Vec12<S> x = cast12<S>(random_configuration(PairKind::vertex_face, 0.4, 1.0, 0.5, rng).x);
  pce::Frame<S> f, g;
  ASSERT_EQ(pce::vertex_face_frame(x, f), pce::Status::ok);
  for (int k : {-40, -3, 5, 40}) {
    const S s = std::ldexp(S(1), k);
    ASSERT_EQ(pce::vertex_face_frame(pce::Vec12<S>(x * s), g), pce::Status::ok);
    // Scale-free quantities are bit-identical; lengths scale exactly.
    EXPECT_EQ(g.n, f.n);
    EXPECT_EQ(g.P, f.P);
    EXPECT_EQ(g.l, f.l * s);
    EXPECT_EQ(g.a0, f.a0 * s);
    EXPECT_EQ(g.a1, f.a1 * s);
  }
}

}  // namespace
