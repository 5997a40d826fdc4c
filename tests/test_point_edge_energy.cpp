// SPDX-License-Identifier: MIT
// frames/point_edge.hpp and energy/point_edge_energy.hpp: the frame's conventions, the
// conformance suite (tests/support/kind_conformance.hpp) on random configurations in
// float, double and long double, every status, and the hard cases (point near the line,
// far along it, tiny and huge scales, large offsets) against the 50-digit reference.
#include "support/kind_conformance.hpp"

#include <gtest/gtest.h>

namespace {
using namespace pce_test;
using Kind = DirectKind<pce::PointEdge>;

pce::Vec9<double> pe(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  pce::Vec9<double> x;
  x << p, a, b;
  return x;
}

TEST(PointEdgeFrame, Conventions) {
  pce::PointEdgeFrame<double> f;
  ASSERT_EQ(pce::PointEdge::frame(pe({0.5, 0.3, 0.4}, {0, 0, 0}, {2, 0, 0}), f), pce::Status::ok);
  EXPECT_DOUBLE_EQ(f.d, 0.5);
  EXPECT_DOUBLE_EQ(f.a, 2.0);
  EXPECT_DOUBLE_EQ(f.beta, 0.25);  // foot e0 + β e = (0.5, 0, 0)
  EXPECT_LT((f.t - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((f.u - Eigen::Vector3d(0, 0.6, 0.8)).norm(), 1e-15);  // from the line to p
  EXPECT_LT((f.n - f.t.cross(f.u)).norm(), 1e-15);                // right-handed (t, u, n)
  // c1 = r⊥ = Σ P(1,j) x_j = d û
  const pce::Vec9<double> x = pe({0.5, 0.3, 0.4}, {0, 0, 0}, {2, 0, 0});
  Eigen::Vector3d c1 = Eigen::Vector3d::Zero();
  for (int j = 0; j < 3; ++j) c1 += f.P(1, j) * x.segment<3>(3 * j);
  EXPECT_LT((c1 - f.d * f.u).norm(), 1e-15);
}

template <class S> class PointEdgeStatus : public testing::Test {};
TYPED_TEST_SUITE(PointEdgeStatus, Scalars);

TYPED_TEST(PointEdgeStatus, EveryFailureIsExplicitAndWritesNothing) {
  using S = TypeParam;
  const auto status = [](const pce::Vec9<double>& xd, auto len, auto pen) {
    pce::PairResult<S, 9, 6> out;
    out.value = S(-7);
    out.gradient.setConstant(S(-7));
    const pce::Status s = pce::evaluate<pce::PointEdge>(cast_vec<S>(xd), len, pen, pce::Projection::exact, out);
    if (s != pce::Status::ok) {
      EXPECT_EQ(out.value, S(-7));
      EXPECT_EQ(out.gradient, pce::Vec9<S>::Constant(S(-7)));
    }
    return s;
  };
  const pce::QuadraticPenalty quad{1.0, 1.0};
  const pce::UnsignedLength u;
  EXPECT_EQ(status(pe({0.5, 0.3, 0}, {0, 0, 0}, {1, 0, 0}), u, quad), pce::Status::ok);
  EXPECT_EQ(status(pe({0.5, 0.3, 0}, {0, 0, 0}, {1, 0, 0}), pce::SignedLength{}, quad), pce::Status::invalid_input)
      << "a point-edge distance has no side";
  EXPECT_EQ(status(pe({0.5, 0, 0}, {0, 0, 0}, {1, 0, 0}), u, quad), pce::Status::degenerate) << "p on the edge";
  EXPECT_EQ(status(pe({3, 0, 0}, {0, 0, 0}, {1, 0, 0}), u, quad), pce::Status::degenerate) << "p on the line";
  EXPECT_EQ(status(pe({0.5, 0.3, 0}, {1, 1, 1}, {1, 1, 1}), u, quad), pce::Status::degenerate) << "zero-length edge";
  pce::Vec9<double> bad = pe({0.5, 0.3, 0}, {0, 0, 0}, {1, 0, 0});
  bad[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(status(bad, u, quad), pce::Status::invalid_input);
  EXPECT_EQ(status(pe({0.5, 0.3, 0}, {0, 0, 0}, {1, 0, 0}), u, pce::QuadraticPenalty{-1.0, 1.0}),
            pce::Status::invalid_input);
  EXPECT_EQ(status(pe({0.5, -0.3, 0}, {0, 0, 0}, {1, 0, 0}), u, pce::LogBarrierPenalty{1.0, 0.2}), pce::Status::ok)
      << "inactive barrier: d = 0.3 > dhat";
  if constexpr (std::is_same_v<S, float>) {  // a point 1e30 edge lengths away does not fit in float
    EXPECT_EQ(status(pe({1e15, 1e15, 0}, {0, 0, 0}, {1e-15, 0, 0}), u, quad), pce::Status::overflow);
  }
}

// Found by the fuzzer: a distance below the smallest subnormal (here 2^-1134 in double,
// 2^-179 in float) rounded to d = 0 and the frame still said ok, so 1/d terms were infinite.
TEST(PointEdgeFrame, DistanceThatUnderflowsIsDegenerate) {
  const auto check = [](auto zero) {
    using S = decltype(zero);
    using L = std::numeric_limits<S>;
    const int m = L::min_exponent;  // -1021 (double), -125 (float)
    pce::Vec9<S> x;
    // edge (0,0,0)-(2^(m/2), 2^(m/2 - 60), 0), p = the smallest subnormal on the x axis
    x << L::denorm_min(), S(0), S(0), S(0), S(0), S(0), std::ldexp(S(1), m / 2), std::ldexp(S(1), m / 2 - 60), S(0);
    pce::PointEdgeFrame<S> f;
    f.d = S(-7);
    EXPECT_EQ(pce::PointEdge::frame(x, f), pce::Status::degenerate);
    EXPECT_EQ(f.d, S(-7)) << "nothing written";
  };
  check(0.0);
  check(0.0f);
}

TEST(PointEdgeEnergy, Conformance) {
  const ExactStats st = run_kind_suite<Kind>(draw_point_edge, 41);
  std::printf(
      "point_edge: exact vs numerical compared on %d configurations (worst %.2e), numerical inaccurate on %d; "
      "worst exact vs 50 digits %.2e\n",
      st.compared, st.worst_vs_numerical, st.numerical_inaccurate, st.worst_vs_reference);
  EXPECT_GT(st.compared, 100);
}

// Hard cases: each must be as accurate as its input rounding allows, in every scalar.
TEST(PointEdgeHardCases, PointApproachingTheLine) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  for (int k = 1; k <= 14; ++k) {
    const double d = std::pow(10.0, -k);
    for (double foot : {-0.5, 0.0, 0.4, 1.0, 3.0}) {
      SCOPED_TRACE(testing::Message() << "d " << d << " foot " << foot);
      const pce::Vec9<double> x =
          pe(R * Eigen::Vector3d(foot, d, 0), R * Eigen::Vector3d(0, 0, 0), R * Eigen::Vector3d(1, 0, 0));
      expect_stable_all_scalars<Kind>(x, pce::QuadraticPenalty{1.0, 2 * d});
    }
  }
}

TEST(PointEdgeHardCases, FarAlongTheLineScalesAndOffsets) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  for (double beta : {1e2, 1e4, 1e6, -1e6}) {
    SCOPED_TRACE(testing::Message() << "foot at " << beta << " edge lengths");
    expect_stable_all_scalars<Kind>(
        pe(R * Eigen::Vector3d(beta, 0.1, 0.05), R * Eigen::Vector3d(0, 0, 0), R * Eigen::Vector3d(1, 0, 0)),
        pce::QuadraticPenalty{1.0, 0.5});
  }
  for (int k = -8; k <= 8; k += 4) {
    const double s = std::pow(10.0, k);
    SCOPED_TRACE(testing::Message() << "scale " << s);
    expect_stable_all_scalars<Kind>(
        pe(R * Eigen::Vector3d(0.3 * s, 0.1 * s, 0), Eigen::Vector3d::Zero(), R * Eigen::Vector3d(s, 0, 0)),
        pce::QuadraticPenalty{1.0, 0.5 * s});
  }
  const Eigen::Vector3d o(1e6, -8e5, 6e5);
  SCOPED_TRACE("offset 1e6, feature 1e-3");
  expect_stable_all_scalars<Kind>(pe(o + R * Eigen::Vector3d(3e-4, 1e-4, 0), o, o + R * Eigen::Vector3d(1e-3, 0, 0)),
                                  pce::QuadraticPenalty{1.0, 5e-4});
}

}  // namespace
