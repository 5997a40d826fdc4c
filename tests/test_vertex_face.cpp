// SPDX-License-Identifier: MIT
// Tests for frames/vertex_face.hpp: the contract's sign and ordering conventions
// (docs/conventions.md), the projection point, and status on bad or degenerate input.
#include "support/conformance.hpp"
#include "support/scalars.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace {
using namespace pce_test;

template <class S> class VertexFace : public testing::Test {};
TYPED_TEST_SUITE(VertexFace, Scalars);

template <class S> pce::Vec12<S> vf(const Eigen::Vector3d& p, const Eigen::Vector3d& t0, const Eigen::Vector3d& t1,
                                    const Eigen::Vector3d& t2) {
  pce::Vec12<double> x;
  x << p, t0, t1, t2;
  return cast12<S>(x);
}

TYPED_TEST(VertexFace, PositiveOnTheRightHandNormalSide) {
  using S = TypeParam;
  // Counter-clockwise in the xy-plane seen from +z: n = (t1 − t0) × (t2 − t0) = +z.
  const Eigen::Vector3d t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  pce::Frame<S> f;
  ASSERT_EQ(pce::vertex_face_frame(vf<S>({0.2, 0.3, 0.5}, t0, t1, t2), f), pce::Status::ok);
  EXPECT_NEAR(double(f.l), 0.5, 1e-6);
  EXPECT_NEAR(double(f.n.z()), 1.0, 1e-6);
  ASSERT_EQ(pce::vertex_face_frame(vf<S>({0.2, 0.3, -0.5}, t0, t1, t2), f), pce::Status::ok);
  EXPECT_NEAR(double(f.l), -0.5, 1e-6);
  // Swapping t1 and t2 reverses the normal and the sign.
  ASSERT_EQ(pce::vertex_face_frame(vf<S>({0.2, 0.3, 0.5}, t0, t2, t1), f), pce::Status::ok);
  EXPECT_NEAR(double(f.l), -0.5, 1e-6);
  // Plane distance, not closest-feature distance: far outside the triangle, same l.
  ASSERT_EQ(pce::vertex_face_frame(vf<S>({7, -9, 0.5}, t0, t1, t2), f), pce::Status::ok);
  EXPECT_NEAR(double(f.l), 0.5, 1e-5);
}

TYPED_TEST(VertexFace, LengthEqualsDirectFormula) {
  using S = TypeParam;
  std::mt19937_64 rng(21);
  for (int i = 0; i < 100; ++i) {
    const pce::Vec12<S> x = cast12<S>(random_configuration(PairKind::vertex_face, 0.7 * (i % 3 - 1), 1, 2, rng).x);
    const Eigen::Matrix<S, 3, 1> p = x.template segment<3>(0), t0 = x.template segment<3>(3),
                                 t1 = x.template segment<3>(6), t2 = x.template segment<3>(9);
    const Eigen::Matrix<S, 3, 1> n = (t1 - t0).cross(t2 - t0).normalized();
    pce::Frame<S> f;
    ASSERT_EQ(pce::vertex_face_frame(x, f), pce::Status::ok);
    EXPECT_NEAR(double(f.l), double((p - t0).dot(n)), ulps<S>(64) * 4);
    // Row 2 of P is p minus its projection onto the plane with barycentrics (1−β−γ, β, γ).
    EXPECT_EQ(f.P(2, 0), S(1));
    EXPECT_NEAR(double(f.P(2, 1) + f.P(2, 2) + f.P(2, 3)), -1.0, ulps<S>(16));
    const Eigen::Matrix<S, 3, 1> q = -(f.P(2, 1) * t0 + f.P(2, 2) * t1 + f.P(2, 3) * t2);
    EXPECT_LT(max_abs(((p - q) - f.l * n).eval()), ulps<S>(64) * 8);
  }
}

TYPED_TEST(VertexFace, DegenerateTrianglesAreReportedAndNothingIsWritten) {
  using S = TypeParam;
  pce::Frame<S> f;
  f.l = S(42);
  const Eigen::Vector3d p(0.1, 0.2, 0.3);
  EXPECT_EQ(pce::vertex_face_frame(vf<S>(p, {0, 0, 0}, {1, 1, 1}, {2, 2, 2}), f), pce::Status::degenerate);
  EXPECT_EQ(pce::vertex_face_frame(vf<S>(p, {0, 0, 0}, {0, 0, 0}, {1, 0, 0}), f), pce::Status::degenerate);
  EXPECT_EQ(pce::vertex_face_frame(vf<S>(p, {1, 2, 3}, {1, 2, 3}, {1, 2, 3}), f), pce::Status::degenerate);
  EXPECT_EQ(f.l, S(42));
}

TEST(VertexFaceFloat, FarVertexOverATinyTriangleOverflowsExplicitly) {
  // Found by pce-fuzz (seed 7, input 88491): relative to a 1e-33 triangle a vertex at 1e6
  // is beyond float's range; the frame says so instead of returning non-finite members.
  pce::Vec12<float> x;
  x << 1000000.375f, 3.0584478544014759e-33f, -4.0764412987414353e-34f, 0, 0, 0, 1.5407439555097887e-33f, 0, 0,
      3.459532679880283e-34f, 4.5623396946710012e-34f, 0;
  pce::Frame<float> f;
  f.l = 42.0f;
  EXPECT_EQ(pce::vertex_face_frame(x, f), pce::Status::overflow);
  EXPECT_EQ(f.l, 42.0f);
  pce::PairResult<float> r;
  EXPECT_EQ(pce::evaluate<pce::VertexFace>(x, pce::SignedLength{}, pce::QuadraticPenalty{1, 0.1},
                                           pce::Projection::analytic, r),
            pce::Status::overflow);
  // The same geometry in double is fine.
  pce::Frame<double> fd;
  EXPECT_EQ(pce::vertex_face_frame(pce::Vec12<double>(x.cast<double>()), fd), pce::Status::ok);
}

TEST(VertexFaceFloat, FarVertexOverATinyTriangleCannotOverflowThePullback) {
  // Found by pce-fuzz after the fix above (seed 7, input 1279286): alpha, beta, gamma and l
  // are finite (beta, gamma ~ -2e38 and -3e38) but the pullback's third row holds
  // -1 + beta + gamma, beyond float's range. Every member of an `ok` frame must be finite.
  pce::Vec12<float> x;
  x << 0x1.fffffep+54f, 0x1.c2a3c2p-74f, 0x1.446544p-75f, -0x1.618162p-80f, 0x1.7b297cp-76f, -0x1.c771c8p-77f,
      -0x1.e921eap-78f, -0x1.b88bb8p-74f, 0x1.0d670ep-74f, -0x1.ceb3cep-74f, 0x1.166716p-74f, -0x1.ac97acp-74f;
  pce::Frame<float> f;
  f.l = 42.0f;
  EXPECT_EQ(pce::vertex_face_frame(x, f), pce::Status::overflow);
  EXPECT_EQ(f.l, 42.0f);
  pce::PairResult<float> r;
  EXPECT_EQ(pce::evaluate<pce::VertexFace>(x, pce::SignedLength{pce::Side::negative}, pce::LogBarrierPenalty{1, 2e16},
                                           pce::Projection::numerical, r),
            pce::Status::overflow);
  pce::Frame<double> fd;
  ASSERT_EQ(pce::vertex_face_frame(pce::Vec12<double>(x.cast<double>()), fd), pce::Status::ok);
  EXPECT_TRUE(fd.P.allFinite());
}

TYPED_TEST(VertexFace, NonFiniteAndAbsurdInputIsInvalid) {
  using S = TypeParam;
  const pce::Vec12<S> good = vf<S>({0.2, 0.3, 0.5}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  const S bad[3] = {std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                    S(2) * pce::Constants<S>::max_coordinate()};
  for (int i = 0; i < 12; ++i)
    for (S b : bad) {
      pce::Vec12<S> x = good;
      x[i] = b;
      pce::Frame<S> f;
      f.l = S(42);
      EXPECT_EQ(pce::vertex_face_frame(x, f), pce::Status::invalid_input) << "coordinate " << i;
      EXPECT_EQ(f.l, S(42));
    }
}

}  // namespace
