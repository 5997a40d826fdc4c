// SPDX-License-Identifier: MIT
// Tests for penalties/{quadratic,cubic,log_barrier}.hpp and the penalty concept in
// penalties/penalty.hpp: ψ′ and ψ″ against finite differences and against the 50-digit
// instantiation, one-sidedness, smoothness at the activation length, domain and
// parameter checks.
#include "support/conformance.hpp"
#include "support/high_precision.hpp"
#include "support/scalars.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace {
using namespace pce_test;
using HP = HighPrecision;

template <class P> void check_derivatives(const P& pen, double lo, double hi, const char* what) {
  SCOPED_TRACE(what);
  for (int i = 0; i <= 40; ++i) {
    const long double L = lo + (hi - lo) * (i + 0.5) / 41.0;
    const long double h = 1e-6L * std::max(1.0L, std::fabs(L));
    const auto c = pen.template evaluate<long double>(L);
    const auto p = pen.template evaluate<long double>(L + h), m = pen.template evaluate<long double>(L - h);
    const double d1 = double((p.value - m.value) / (2 * h)), d2 = double((p.first - m.first) / (2 * h));
    EXPECT_NEAR(double(c.first), d1, 1e-7 * std::max(1.0, std::fabs(d1))) << "L = " << double(L);
    EXPECT_NEAR(double(c.second), d2, 1e-7 * std::max(1.0, std::fabs(d2))) << "L = " << double(L);
    // The double instantiation agrees with 50 digits.
    const auto r = pen.template evaluate<HP>(HP(double(L)));
    const auto d = pen.template evaluate<double>(double(L));
    for (auto [a, b] : {std::pair{d.value, r.value}, std::pair{d.first, r.first}, std::pair{d.second, r.second}})
      EXPECT_NEAR(a, double(b), 1e-14 * std::max(1e-300, std::fabs(double(b))) + 1e-300);
  }
}

TEST(Quadratic, DerivativesOneSidedAndC1) {
  const pce::QuadraticPenalty q{3.0, 0.5};
  check_derivatives(q, -2.0, 0.49, "quadratic");
  const auto at = q.evaluate(0.5), above = q.evaluate(0.7);
  EXPECT_EQ(at.value, 0.0);
  EXPECT_EQ(at.first, 0.0);
  EXPECT_EQ(above.value, 0.0);
  EXPECT_EQ(above.second, 0.0);
  EXPECT_EQ(q.evaluate(0.5 - 1e-9).second, 6.0);  // ψ″ jumps: C¹, documented
  EXPECT_TRUE(q.valid());
  EXPECT_FALSE((pce::QuadraticPenalty{-1.0, 0.5}.valid()));
  EXPECT_FALSE((pce::QuadraticPenalty{std::nan(""), 0.5}.valid()));
  EXPECT_FALSE((pce::QuadraticPenalty{1.0, std::numeric_limits<double>::infinity()}.valid()));
}

TEST(Cubic, DerivativesOneSidedAndSmoothing) {
  const pce::CubicPenalty c{2.0, 0.3, 0.01};
  check_derivatives(c, -3.0, 0.29, "cubic, delta > 0");
  check_derivatives(pce::CubicPenalty{2.0, 0.3, 0.0}, -3.0, 0.29, "cubic, delta = 0");
  EXPECT_EQ(c.evaluate(0.3).value, 0.0);
  EXPECT_EQ(c.evaluate(0.3).first, 0.0);
  // ψ″ just below ε tends to 2k√δ (C¹ for δ > 0) and to 0 for δ = 0 (C²).
  EXPECT_NEAR(c.evaluate(0.3 - 1e-12).second, 2 * 2.0 * 0.1, 1e-9);
  EXPECT_NEAR((pce::CubicPenalty{2.0, 0.3, 0.0}.evaluate(0.3 - 1e-12).second), 0.0, 1e-9);
  // No 0/0 at d = δ = 0, no overflow at huge |d|.
  const auto z = pce::CubicPenalty{1.0, 0.0, 0.0}.evaluate(-0.0);
  EXPECT_TRUE(std::isfinite(z.value) && std::isfinite(z.first) && std::isfinite(z.second));
  const auto big = pce::CubicPenalty{1.0, 0.0, 0.0}.evaluate(-1e100);
  EXPECT_NEAR(big.value, 1e300, 1e286);
  EXPECT_FALSE((pce::CubicPenalty{1.0, 0.0, -1e-3}.valid()));
}

TEST(LogBarrier, DerivativesDomainAndC2AtDhat) {
  const pce::LogBarrierPenalty b{1.5, 0.2};
  check_derivatives(b, 1e-3, 0.1999, "log barrier");
  EXPECT_FALSE(b.in_domain(0.0));
  EXPECT_FALSE(b.in_domain(-1e-3));
  EXPECT_TRUE(b.in_domain(1e-300));
  EXPECT_TRUE(pce::penalty_in_domain(b, 0.3));
  const auto at = b.evaluate(0.2), beyond = b.evaluate(0.5);
  EXPECT_EQ(at.value, 0.0);
  EXPECT_EQ(at.first, 0.0);
  EXPECT_EQ(at.second, 0.0);
  EXPECT_EQ(beyond.second, 0.0);
  EXPECT_NEAR(b.evaluate(0.2 * (1 - 1e-9)).second, 0.0, 1e-7);  // C² at d̂
  EXPECT_FALSE((pce::LogBarrierPenalty{1.0, 0.0}.valid()));
  EXPECT_FALSE((pce::LogBarrierPenalty{1.0, -1.0}.valid()));
}

TEST(LogBarrier, AccurateNearDhat) {
  // ln(L/d̂) for L/d̂ = 1 − 1e-12: log1p keeps all digits (docs/stability.md).
  const pce::LogBarrierPenalty b{1.0, 1.0};
  for (double r : {1e-12, 1e-9, 1e-6, 1e-3}) {
    const double L = 1.0 - r;
    const auto d = b.evaluate(L);
    const auto ref = b.evaluate(HP(L));
    EXPECT_NEAR(d.second, double(ref.second), 1e-13 * std::fabs(double(ref.second))) << r;
    EXPECT_NEAR(d.first, double(ref.first), 1e-13 * std::fabs(double(ref.first))) << r;
  }
}

struct Minimal {
  template <class S> pce::PenaltyDerivatives<S> evaluate(S L) const { return {L * L, 2 * L, S(2)}; }
};

TEST(PenaltyConcept, DefaultsForUserPenalties) {
  EXPECT_TRUE(pce::penalty_valid(Minimal{}));
  EXPECT_TRUE(pce::penalty_in_domain(Minimal{}, -5.0));
  EXPECT_FALSE(pce::penalty_in_domain(pce::LogBarrierPenalty{}, -5.0));
  EXPECT_FALSE(pce::penalty_valid(pce::LogBarrierPenalty{1.0, 0.0}));
}

template <class S> class PenaltyScalars : public testing::Test {};
TYPED_TEST_SUITE(PenaltyScalars, Scalars);

TYPED_TEST(PenaltyScalars, FiniteAcrossTheActiveRange) {
  using S = TypeParam;
  const pce::QuadraticPenalty q{1.0, 1.0};
  const pce::CubicPenalty c{1.0, 1.0, 1e-6};
  const pce::LogBarrierPenalty b{1.0, 1.0};
  // (ψ″ ~ k/L² of the barrier exceeds float's range below L ~ 1e-19: pair_energy reports
  // that as `overflow`, tested in test_pair_energy.)
  for (double L : {-1e3, -1.0, 0.0, 1e-15, 1e-6, 0.5, 1.0 - 1e-7, 1.0, 2.0}) {
    for (const auto& d : {q.evaluate(S(L)), c.evaluate(S(L))})
      EXPECT_TRUE(std::isfinite(double(d.value)) && std::isfinite(double(d.first)) && std::isfinite(double(d.second)));
    if (L > 0) {
      const auto d = b.evaluate(S(L));
      EXPECT_TRUE(std::isfinite(double(d.value)) && std::isfinite(double(d.first)) && std::isfinite(double(d.second)))
          << L;
    }
  }
}

}  // namespace
