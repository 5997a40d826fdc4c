// SPDX-License-Identifier: MIT
// The measurement behind pce-accuracy (tests/support/accuracy_measure.hpp), checked so that
// a broken reference or a broken distance cannot go unnoticed:
//  * the 50-digit reference P* is the nearest PSD matrix of H*: P* ⪰ 0, P* − H* ⪰ 0 and
//    P*(P* − H*) = 0 (together these characterise H₊ uniquely), and P* = H* where H* is PSD;
//  * `numerical` and `exact` in double are within 1e-12 of P* on random pairs, so the
//    rounding, the dispatch and the distance are consistent;
//  * the measure does flag what is not the projection: the unprojected Hessian is far from
//    P* and fails the PSD test; the ‖P*‖ = 0 rule and the PSD ratio on known matrices.
#include "support/accuracy_measure.hpp"

#include <gtest/gtest.h>

namespace {
using namespace pce_test;

std::vector<Sample> all_random_samples(LengthDraw draw, int count) {
  std::vector<Sample> out;
  for (AnyPair pair : {AnyPair::vertex_face, AnyPair::edge_edge, AnyPair::point_edge, AnyPair::point_point})
    for (LengthKind len : {LengthKind::signed_positive, LengthKind::unsigned_}) {
      if (!is_plane(pair) && len != LengthKind::unsigned_) continue;
      for (PenaltyKind pen : {PenaltyKind::quadratic, PenaltyKind::cubic, PenaltyKind::log_barrier}) {
        const auto s = generated_samples(pair, len, pen, draw, count, 77 + 10 * out.size());
        out.insert(out.end(), s.begin(), s.end());
      }
    }
  return out;
}

std::string describe_for_test(const Sample& s) {
  return std::string(name(s.pair)) + " " + name(s.length) + " " + name(s.penalty.kind) + " " + s.family + " " +
         s.severity;
}

void expect_nearest_psd(const Reference& r, const std::string& what, double min_clamped = 1e-8) {
  SCOPED_TRACE(what);
  ASSERT_EQ(r.status, pce::Status::ok);
  const int n = r.n;
  const long double h = r.hessian_norm;
  ASSERT_GT(h, 0);
  // P* ⪰ 0 (relative to its own scale), P* − H* ⪰ 0 (relative to ‖H*‖), P*(P* − H*) = 0.
  const double tol = 1e-16;  // long double copies of 50-digit results: ~1e-19 relative
  EXPECT_GE(psd_ratio(r.projection, n), -tol) << "P* is PSD";
  const pce::Mat12<long double> N = r.projection - r.hessian;
  const double rn = psd_ratio(N, n);
  EXPECT_GE(rn * static_cast<double>(frobenius(N, n) / h), -tol) << "P* - H* is PSD";
  const long double comp = frobenius((r.projection * N).eval(), n);
  EXPECT_LE(static_cast<double>(comp / (h * h)), tol) << "P*(P* - H*) = 0";
  // The clamped part is real: the active Hessian of these penalties is indefinite (ψ′ ≠ 0
  // times the length's indefinite Hessian), so P* ≠ H* (on the hard cases the negative
  // part can be 1e-18 of ‖H*‖: the barrier at L/d̂ = 1e-14 or 1 − 1e-14) …
  EXPECT_GT(static_cast<double>(frobenius(N, n) / h), min_clamped) << "H* indefinite, P* != H*";
  // … and P* keeps the PSD part: ‖P*‖ > 0 (ψ″ > 0 on the active range).
  EXPECT_GT(r.projection_norm, 0) << "P* != 0";
}

TEST(AccuracyReference, IsTheNearestPsdMatrixOnRandomPairs) {
  int checked = 0;
  for (LengthDraw draw : {LengthDraw::spread, LengthDraw::near_contact})
    for (const Sample& s : all_random_samples(draw, 6)) {
      expect_nearest_psd(reference_at(s, rounded<double>(s.x)), describe_for_test(s));
      ++checked;
    }
  EXPECT_EQ(checked, 2 * 18 * 6);
}

TEST(AccuracyReference, IsTheNearestPsdMatrixOnHardCases) {
  int checked = 0;
  for (PenaltyKind pen : {PenaltyKind::quadratic, PenaltyKind::log_barrier})
    for (const Sample& s : hard_samples(pen)) {
      const Reference r = reference_at(s, rounded<double>(s.x));
      if (s.degenerate) {
        EXPECT_EQ(r.status, pce::Status::degenerate) << describe_for_test(s);
        continue;
      }
      if (r.status != pce::Status::ok) {  // the barrier at L <= 0 only
        EXPECT_EQ(r.status, pce::Status::out_of_domain) << describe_for_test(s);
        EXPECT_EQ(pen, PenaltyKind::log_barrier);
        continue;
      }
      expect_nearest_psd(r, describe_for_test(s), 0.0);
      ++checked;
    }
  EXPECT_GT(checked, 400);
}

TEST(AccuracyReference, EqualsTheHessianWhereItIsPsd) {
  // In the active range of these penalties H* is never PSD (ψ′ ≠ 0 times the length's
  // indefinite Hessian; the complementarity tests above cover it). Beyond the range H* = 0
  // is PSD: the reference must be exactly H*, and every strategy's distance is measured by
  // the ‖P*‖ = ‖H*‖ = 0 rule (0 for P = 0).
  for (Sample s : all_random_samples(LengthDraw::spread, 2)) {
    s.penalty = penalty_with_range(s.penalty.kind, 1e-3 * active_range(s.penalty));  // L > range
    const Reference r = reference_at(s, rounded<double>(s.x));
    ASSERT_EQ(r.status, pce::Status::ok);
    EXPECT_EQ(r.projection, r.hessian);
    EXPECT_EQ(r.hessian_norm, 0);
    const SampleOutcome o = measure_sample<double>(s);
    for (const StrategyOutcome& so : o.strategies) EXPECT_EQ(so.rel_dist, 0);
  }
}

TEST(AccuracyMeasure, NumericalAndExactInDoubleMatchTheReference) {
  double worst_numerical = 0, worst_exact = 0;
  for (const Sample& s : all_random_samples(LengthDraw::spread, 12)) {
    const SampleOutcome o = measure_sample<double>(s);
    ASSERT_EQ(o.status, pce::Status::ok);
    ASSERT_EQ(o.reference_status, pce::Status::ok);
    for (std::size_t k = 0; k < kStrategies.size(); ++k) {
      const StrategyOutcome& so = o.strategies[k];
      EXPECT_TRUE(so.finite);
      EXPECT_FALSE(so.psd_violation) << pce::to_string(kStrategies[k]) << " " << describe_for_test(s);
      if (kStrategies[k] == pce::Projection::numerical) worst_numerical = std::max(worst_numerical, so.rel_dist);
      if (kStrategies[k] == pce::Projection::exact) worst_exact = std::max(worst_exact, so.rel_dist);
    }
  }
  EXPECT_LT(worst_numerical, 1e-12);
  EXPECT_LT(worst_exact, 1e-12);
  EXPECT_GT(worst_numerical, 0) << "a distance of exactly 0 everywhere means nothing was compared";
}

TEST(AccuracyMeasure, FloatIsMeasuredAtItsOwnRoundedInput) {
  // float's `numerical` agrees with the reference at float's rounded input to a few
  // hundred roundoffs on well-shaped pairs; against the double input it would not in general.
  double worst = 0;
  for (const Sample& s : all_random_samples(LengthDraw::spread, 6)) {
    const SampleOutcome o = measure_sample<float>(s);
    ASSERT_EQ(o.status, pce::Status::ok);
    worst = std::max(worst, o.strategies[4].rel_dist);
  }
  ASSERT_EQ(kStrategies[4], pce::Projection::numerical);
  EXPECT_LT(worst, 1e-4);
}

TEST(AccuracyMeasure, FlagsTheUnprojectedHessian) {
  for (const Sample& s : all_random_samples(LengthDraw::spread, 3)) {
    const Reference r = reference_at(s, rounded<double>(s.x));
    ASSERT_EQ(r.status, pce::Status::ok);
    // H* is not P*: the measure sees a large distance and a PSD violation.
    EXPECT_GT(rel_dist(r.hessian, r), 1e-6) << describe_for_test(s);
    EXPECT_LT(psd_ratio(r.hessian, r.n), -psd_tolerance<double>(r.n)) << describe_for_test(s);
  }
}

TEST(AccuracyMeasure, DistanceAndPsdRatioOnKnownMatrices) {
  Reference r;
  r.status = pce::Status::ok;
  r.n = 6;
  pce::Mat12<long double> P = pce::Mat12<long double>::Zero();
  EXPECT_EQ(rel_dist(P, r), 0.0) << "both zero";
  P(0, 0) = 1;
  EXPECT_TRUE(std::isinf(rel_dist(P, r))) << "P != 0 against a zero reference";
  r.hessian(0, 0) = -2;
  r.hessian_norm = 2;
  EXPECT_DOUBLE_EQ(rel_dist(P, r), 0.5) << "‖P*‖ = 0: relative to ‖H*‖";
  r.projection(1, 1) = 4;
  r.projection_norm = 4;
  EXPECT_DOUBLE_EQ(rel_dist(P, r), std::sqrt(17.0) / 4);
  pce::Mat12<long double> D = pce::Mat12<long double>::Zero();
  D.diagonal().head<9>() << 2, 1, 0, 0, -1e-3L, 0, 0, 0, 0;
  EXPECT_DOUBLE_EQ(psd_ratio(D, 9), -5e-4);
  EXPECT_DOUBLE_EQ(psd_ratio(D, 12), -5e-4);
  D(4, 4) = 0;
  EXPECT_EQ(psd_ratio(D, 6), 0.0);
  EXPECT_NEAR(psd_tolerance<float>(12), 12 * 1.1920929e-7, 1e-12);
}

}  // namespace
