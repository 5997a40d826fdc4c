// SPDX-License-Identifier: MIT
// Tests for lengths/unsigned_length.hpp: L = |l| with σ = sgn(l) (+1 at l = 0), its exact
// Hessian equal to that of the paper's norm form |e2⊥| (checked by finite differences of an
// independent implementation), and a projected Hessian that stays bounded as L → 0.
#include "support/conformance.hpp"
#include "support/scalars.hpp"

#include <gtest/gtest.h>

namespace {
using namespace pce_test;

template <class S> class UnsignedLength : public testing::Test {};
TYPED_TEST_SUITE(UnsignedLength, Scalars);

TYPED_TEST(UnsignedLength, IsTheAbsoluteValueWithSignSigma) {
  using S = TypeParam;
  std::mt19937_64 rng(61);
  for (double l : {-0.5, -1e-3, 0.0, 1e-3, 0.5}) {
    const pce::Vec12<S> x = cast12<S>(random_configuration(PairKind::edge_edge, l, 1, 0, rng).x);
    pce::Frame<S> f;
    ASSERT_EQ(pce::edge_edge_frame(x, f), pce::Status::ok);
    const pce::UnsignedLength u{};
    EXPECT_GE(pce::length_value(f, u), S(0));
    EXPECT_EQ(pce::length_value(f, u), f.l < S(0) ? S(-f.l) : f.l);
    EXPECT_EQ(pce::length_gradient(f, u), (u.sigma(f) * pce::length_gradient(f, pce::SignedLength{})).eval());
  }
  pce::Frame<S> f;
  f.l = S(0);
  EXPECT_EQ(pce::UnsignedLength{}.sigma(f), S(1));
  f.l = -S(0);
  EXPECT_EQ(pce::UnsignedLength{}.sigma(f), S(1));
}

/// |e2⊥| computed independently: the distance of eb0 − ea0 (or p − t0) from the span of
/// the two edge directions, via the normal equations solved in long double.
long double norm_form(PairKind kind, const pce::Vec12<long double>& x) {
  using V = Eigen::Matrix<long double, 3, 1>;
  V e0, e1, e2;
  if (kind == PairKind::vertex_face) {
    e0 = x.segment<3>(6) - x.segment<3>(3), e1 = x.segment<3>(9) - x.segment<3>(3),
    e2 = x.segment<3>(0) - x.segment<3>(3);
  } else {
    e0 = x.segment<3>(3) - x.segment<3>(0), e1 = x.segment<3>(9) - x.segment<3>(6),
    e2 = x.segment<3>(6) - x.segment<3>(0);
  }
  Eigen::Matrix<long double, 3, 2> A;
  A << e0, e1;
  const Eigen::Matrix<long double, 2, 1> bg = (A.transpose() * A).ldlt().solve(A.transpose() * e2);
  return (e2 - A * bg).norm();
}

TEST(UnsignedLengthCoordinates, HessianEqualsThatOfTheNormForm) {
  std::mt19937_64 rng(62);
  for (PairKind kind : {PairKind::vertex_face, PairKind::edge_edge})
    for (double l : {-0.6, -0.2, 0.3, 0.9}) {
      const pce::Vec12<long double> x = cast12<long double>(random_configuration(kind, l, 1, 0.5, rng).x);
      pce::Frame<long double> f;
      ASSERT_EQ(with_pair(kind, [&](auto p) { return decltype(p)::frame(x, f); }), pce::Status::ok);
      const pce::UnsignedLength u{};
      const pce::Mat12<long double> H = pce::pullback(f, pce::detail::frame_hessian_blocks(f, u.sigma(f), 0.0L));
      const pce::Vec12<long double> g = pce::pullback(f, pce::length_gradient(f, u));
      // Second differences of the independent norm form.
      const long double h = 1e-4L;
      pce::Mat12<long double> Hfd;
      pce::Vec12<long double> gfd;
      const auto N = [&](const pce::Vec12<long double>& y) { return norm_form(kind, y); };
      for (int a = 0; a < 12; ++a) {
        pce::Vec12<long double> xa = x, xb = x;
        xa[a] += h, xb[a] -= h;
        gfd[a] = (N(xa) - N(xb)) / (2 * h);
        for (int b = 0; b < 12; ++b) {
          auto pp = x, pm = x, mp = x, mm = x;
          pp[a] += h, pp[b] += h, pm[a] += h, pm[b] -= h, mp[a] -= h, mp[b] += h, mm[a] -= h, mm[b] -= h;
          Hfd(a, b) = (N(pp) - N(pm) - N(mp) + N(mm)) / (4 * h * h);
        }
      }
      EXPECT_NEAR(double(norm_form(kind, x)), double(pce::length_value(f, u)), 1e-15);
      EXPECT_LT(rel_error(g, gfd), 1e-7);
      EXPECT_LT(rel_error(H, Hfd), 1e-5);
    }
}

TEST(UnsignedLengthCoordinates, ProjectedHessianStaysBoundedAsLengthVanishes) {
  std::mt19937_64 rng(63);
  const pce::QuadraticPenalty pen{1.0, 0.1};
  double first = 0;
  for (double l : {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 0.0}) {
    std::mt19937_64 same(63);
    const pce::Vec12<double> x = random_configuration(PairKind::vertex_face, l, 1, 0, same).x;
    pce::PairEnergy<double> e;
    ASSERT_EQ(pce::pair_energy<pce::VertexFace>(x, pce::UnsignedLength{}, pen, e), pce::Status::ok);
    const double n = max_abs(pce::projected_hessian(e, pce::Projection::analytic));
    if (first == 0) first = n;
    EXPECT_LT(n, 2 * first) << "l = " << l;
    EXPECT_TRUE(std::isfinite(n));
  }
  (void)rng;
}

}  // namespace
