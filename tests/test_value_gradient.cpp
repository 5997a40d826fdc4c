// SPDX-License-Identifier: MIT
// Tests of energy/value_gradient.hpp: `value_only` and `value_gradient` give the status, value
// and gradient of `pair_energy` + `energy_gradient` bit for bit, on every kind, length and
// penalty, in float and double, on random pairs and on hard ones (degenerate, invalid, out of
// the penalty's domain, tiny and huge primitives that take the rescaled path, nearly parallel
// edges); and the same functions in 50 digits agree with double to rounding.
#include <pce/energy/value_gradient.hpp>
#include <pce/penalties/cubic.hpp>
#include <pce/penalties/log_barrier.hpp>
#include <pce/penalties/quadratic.hpp>

#include "support/high_precision.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace {

template <class Scalar, int N> bool same_bits(const pce::VecN<Scalar, N>& a, const pce::VecN<Scalar, N>& b) {
  return std::memcmp(a.data(), b.data(), sizeof(Scalar) * N) == 0;
}

/// Random pairs near each other (most within the penalties' reach) and hard ones.
template <class Pair, class Scalar, int D = Pair::dofs> std::vector<pce::VecN<Scalar, D>> cases(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<pce::VecN<Scalar, D>> xs;
  for (int i = 0; i < 300; ++i) {
    pce::VecN<Scalar, D> x;
    for (int c = 0; c < D; ++c) x[c] = static_cast<Scalar>(u(rng));
    xs.push_back(x);
  }
  const int n = static_cast<int>(xs.size());
  for (int i = 0; i < n; i += 10) {
    pce::VecN<Scalar, D> x = xs[static_cast<std::size_t>(i)];
    xs.push_back(x * Scalar(std::ldexp(1.0, -30)));  // rescaled in float
    xs.push_back(x * Scalar(std::ldexp(1.0, 30)));
    xs.push_back(x * Scalar(std::ldexp(1.0, -140)));  // rescaled in double (or zero in float)
    pce::VecN<Scalar, D> y = x;
    y.template segment<3>(3) = y.template segment<3>(D - 3);  // repeated point
    xs.push_back(y);
    y = x;
    y[1] = std::numeric_limits<Scalar>::quiet_NaN();
    xs.push_back(y);
    if constexpr (D == 12) {
      // nearly parallel: e1 = 0.37 e0 + δ (1, 2, 3) (vertex-face: a sliver triangle; edge-edge:
      // parallel edges), δ = 2^-20 … 2^-60 relative. Near the scalar's rounding the normal is
      // mostly rounding error, and some of these need a second Gram–Schmidt pass (or are
      // degenerate).
      const int tail = std::is_same_v<Pair, pce::VertexFace> ? 3 : 6,
                e0 = std::is_same_v<Pair, pce::VertexFace> ? 3 : 0;
      for (int ex = -20; ex >= -60; --ex) {
        y = x;
        y.template segment<3>(9) = y.template segment<3>(tail) +
                                   Scalar(0.37) * (y.template segment<3>(e0 + 3) - y.template segment<3>(e0)) +
                                   pce::Vec3<Scalar>(1, 2, 3) * Scalar(std::ldexp(1.0, ex));
        xs.push_back(y);
      }
    }
  }
  return xs;
}

template <class Pair, class Scalar, class Length, class Penalty>
void check(const Length& length, const Penalty& penalty, int& ok_rows, int& statuses) {
  constexpr int D = Pair::dofs;
  for (const pce::VecN<Scalar, D>& x : cases<Pair, Scalar>(5)) {
    typename Pair::template Energy<Scalar> e;
    const pce::Status s = pce::pair_energy<Pair>(x, length, penalty, e);
    Scalar v = Scalar(-7), w = Scalar(-7);
    pce::VecN<Scalar, D> g = pce::VecN<Scalar, D>::Constant(Scalar(-7));
    const pce::Status sv = pce::value_only<Pair>(x, length, penalty, v);
    const pce::Status sg = pce::value_gradient<Pair>(x, length, penalty, w, g);
    statuses |= 1 << static_cast<int>(s);
    ASSERT_EQ(sv, s) << Pair::name << " " << x.transpose();
    if (s != pce::Status::ok) {
      ASSERT_EQ(sg, s);
      EXPECT_EQ(v, Scalar(-7));  // nothing written
      EXPECT_EQ(w, Scalar(-7));
      EXPECT_EQ(g[0], Scalar(-7));
      continue;
    }
    const pce::VecN<Scalar, D> ge = pce::energy_gradient(e);
    ASSERT_EQ(sg, pce::detail::all_finite(ge) ? pce::Status::ok : pce::Status::overflow);
    ++ok_rows;
    EXPECT_TRUE(std::memcmp(&v, &e.psi.value, sizeof v) == 0) << Pair::name;
    EXPECT_TRUE(std::memcmp(&w, &e.psi.value, sizeof w) == 0) << Pair::name;
    if (sg == pce::Status::ok) {
      EXPECT_TRUE(same_bits(g, ge)) << Pair::name << "\n" << g.transpose() << "\n" << ge.transpose();
    }
  }
}

template <class Pair, class Scalar> void check_kind(int& ok_rows, int& statuses) {
  const pce::QuadraticPenalty quadratic{10.0, 0.2};
  const pce::CubicPenalty cubic{10.0, 0.2, 1e-3};
  const pce::LogBarrierPenalty barrier{10.0, 0.2};
  check<Pair, Scalar>(pce::UnsignedLength{}, quadratic, ok_rows, statuses);
  check<Pair, Scalar>(pce::UnsignedLength{}, cubic, ok_rows, statuses);
  check<Pair, Scalar>(pce::UnsignedLength{}, barrier, ok_rows, statuses);
  if constexpr (Pair::dofs == 12) {
    check<Pair, Scalar>(pce::SignedLength{pce::Side::negative}, quadratic, ok_rows, statuses);
    check<Pair, Scalar>(pce::SignedLength{pce::Side::positive}, barrier, ok_rows, statuses);
  }
}

template <class Scalar> void check_all() {
  int ok_rows = 0, statuses = 0;
  check_kind<pce::VertexFace, Scalar>(ok_rows, statuses);
  check_kind<pce::EdgeEdge, Scalar>(ok_rows, statuses);
  check_kind<pce::PointEdge, Scalar>(ok_rows, statuses);
  check_kind<pce::PointPoint, Scalar>(ok_rows, statuses);
  EXPECT_GT(ok_rows, 2000);
  // ok, invalid_input, degenerate and out_of_domain all occurred
  EXPECT_EQ(statuses & 0xF, 0xF);
}

TEST(ValueGradient, EqualsPairEnergyAndEnergyGradientBitForBitDouble) { check_all<double>(); }
TEST(ValueGradient, EqualsPairEnergyAndEnergyGradientBitForBitFloat) { check_all<float>(); }

TEST(ValueGradient, FiftyDigitsAgreeWithDouble) {
  using HP = pce_test::HighPrecision;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  const pce::LogBarrierPenalty barrier{1.0, 0.5};
  int compared = 0;
  for (int i = 0; i < 200; ++i) {
    pce::Vec12<double> x;
    for (int c = 0; c < 12; ++c) x[c] = u(rng);
    double v;
    pce::Vec12<double> g;
    if (pce::value_gradient<pce::VertexFace>(x, pce::UnsignedLength{}, barrier, v, g) != pce::Status::ok) continue;
    HP vh;
    pce::Vec12<HP> gh;
    ASSERT_EQ(
        pce::value_gradient<pce::VertexFace>(pce::Vec12<HP>(x.cast<HP>()), pce::UnsignedLength{}, barrier, vh, gh),
        pce::Status::ok);
    // relative to the gradient's size, a few hundred ulps (the log barrier's ψ′ near L = 0)
    const double scale = g.norm();
    EXPECT_NEAR(v, static_cast<double>(vh), 1e-12 * std::abs(v) + 1e-300);
    for (int c = 0; c < 12; ++c) EXPECT_NEAR(g[c], static_cast<double>(gh[c]), 1e-11 * scale);
    ++compared;
  }
  EXPECT_GT(compared, 20);
}

}  // namespace
