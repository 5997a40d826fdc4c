// SPDX-License-Identifier: MIT
// Tests for lengths/signed_length.hpp: the side convention, and the length's gradient,
// Hessian and eigensystem pulled back to the 12 coordinates against finite differences
// (which also shows that the derivatives of α, β, γ contribute nothing: supplement Sec. 1).
#include "support/conformance.hpp"
#include "support/scalars.hpp"

#include <gtest/gtest.h>

namespace {
using namespace pce_test;

template <class S> class SignedLength : public testing::Test {};
TYPED_TEST_SUITE(SignedLength, Scalars);

TYPED_TEST(SignedLength, SideFlipsValueAndDerivatives) {
  using S = TypeParam;
  std::mt19937_64 rng(51);
  const pce::Vec12<S> x = cast12<S>(random_configuration(PairKind::vertex_face, 0.4, 1, 0, rng).x);
  pce::Frame<S> f;
  ASSERT_EQ(pce::vertex_face_frame(x, f), pce::Status::ok);
  const pce::SignedLength pos{pce::Side::positive}, neg{pce::Side::negative};
  EXPECT_EQ(pce::length_value(f, pos), f.l);
  EXPECT_EQ(pce::length_value(f, neg), -f.l);
  EXPECT_EQ(pce::length_gradient(f, neg), (-pce::length_gradient(f, pos)).eval());
  EXPECT_EQ(pce::length_hessian(f, neg), (-pce::length_hessian(f, pos)).eval());
  const auto ep = pce::length_eigensystem(f, pos), en = pce::length_eigensystem(f, neg);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(en.values[i], -ep.values[8 - i]);
  // Default side is positive.
  EXPECT_EQ(pce::length_value(f, pce::SignedLength{}), f.l);
}

TYPED_TEST(SignedLength, EigensystemOfTheLengthHessian) {
  using S = TypeParam;
  std::mt19937_64 rng(52);
  for (PairKind kind : {PairKind::vertex_face, PairKind::edge_edge})
    for (int i = 0; i < 20; ++i) {
      const pce::Vec12<S> x = cast12<S>(random_configuration(kind, 0.5 * (i % 5 - 2), 1, 0, rng).x);
      pce::Frame<S> f;
      ASSERT_EQ(with_pair(kind, [&](auto p) { return decltype(p)::frame(x, f); }), pce::Status::ok);
      const pce::SignedLength len{};
      const pce::Mat9<S> H = pce::length_hessian(f, len);
      const auto es = pce::length_eigensystem(f, len);
      EXPECT_LT(max_abs((es.vectors * es.values.asDiagonal() * es.vectors.transpose() - H).eval()) / max_abs(H),
                ulps<S>(64));
      // The gradient is an eigenvector with eigenvalue 0 (it is orthogonal to H's range).
      EXPECT_LT(max_abs((H * pce::length_gradient(f, len)).eval()), ulps<S>(64) * max_abs(H));
      int zeros = 0;
      for (int k = 0; k < 9; ++k) zeros += es.values[k] == S(0);
      EXPECT_EQ(zeros, 5);
    }
}

TEST(SignedLengthCoordinates, GradientAndHessianMatchFiniteDifferences) {
  std::mt19937_64 rng(53);
  for (PairKind kind : {PairKind::vertex_face, PairKind::edge_edge})
    for (int i = 0; i < 20; ++i) {
      const pce::Vec12<long double> x = cast12<long double>(random_configuration(kind, 0.5 * (i % 5 - 2), 1, 1, rng).x);
      const auto frame_of = [&](const pce::Vec12<long double>& y) {
        pce::Frame<long double> f;
        EXPECT_EQ(with_pair(kind, [&](auto p) { return decltype(p)::frame(y, f); }), pce::Status::ok);
        return f;
      };
      const pce::SignedLength len{};
      const auto L = [&](const pce::Vec12<long double>& y) { return pce::length_value(frame_of(y), len); };
      const auto gradL = [&](const pce::Vec12<long double>& y) {
        const auto f = frame_of(y);
        return pce::pullback(f, pce::length_gradient(f, len));
      };
      const auto f = frame_of(x);
      const pce::Vec12<long double> g = gradL(x);
      const pce::Mat12<long double> H = pce::pullback(f, pce::detail::frame_hessian_blocks(f, 1.0L, 0.0L));
      EXPECT_LT(rel_error(fd_gradient<long double>(L, x, 1e-6L), g), 1e-9);
      EXPECT_LT(rel_error(fd_jacobian<long double>(gradL, x, 1e-6L), H), 1e-8);
    }
}

}  // namespace
