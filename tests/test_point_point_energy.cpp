// SPDX-License-Identifier: MIT
// frames/point_point.hpp and energy/point_point_energy.hpp: conventions, the conformance
// suite (tests/support/kind_conformance.hpp), statuses, analytic = exact for this kind,
// and the hard cases (nearly coincident points, scales, offsets).
#include "support/kind_conformance.hpp"

#include <gtest/gtest.h>

namespace {
using namespace pce_test;
using Kind = DirectKind<pce::PointPoint>;

pce::Vec6<double> pp(const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
  pce::Vec6<double> x;
  x << p, q;
  return x;
}

TEST(PointPointFrame, Conventions) {
  pce::PointPointFrame<double> f;
  ASSERT_EQ(pce::PointPoint::frame(pp({1, 2, 3}, {1, 2 - 0.6, 3 - 0.8}), f), pce::Status::ok);
  EXPECT_DOUBLE_EQ(f.d, 1.0);
  EXPECT_LT((f.u - Eigen::Vector3d(0, 0.6, 0.8)).norm(), 1e-15);  // from q to p
  EXPECT_NEAR(f.u.dot(f.v), 0.0, 1e-16);
  EXPECT_NEAR(f.v.norm(), 1.0, 1e-15);
  EXPECT_LT((f.w - f.u.cross(f.v)).norm(), 1e-15);
}

template <class S> class PointPointStatus : public testing::Test {};
TYPED_TEST_SUITE(PointPointStatus, Scalars);

TYPED_TEST(PointPointStatus, EveryFailureIsExplicitAndWritesNothing) {
  using S = TypeParam;
  const auto status = [](const pce::Vec6<double>& xd, auto len, auto pen) {
    pce::PairResult<S, 6, 3> out;
    out.value = S(-7);
    const pce::Status s = pce::evaluate<pce::PointPoint>(cast_vec<S>(xd), len, pen, pce::Projection::exact, out);
    if (s != pce::Status::ok) {
      EXPECT_EQ(out.value, S(-7));
    }
    return s;
  };
  const pce::QuadraticPenalty quad{1.0, 1.0};
  EXPECT_EQ(status(pp({0, 0, 0.5}, {0, 0, 0}), pce::UnsignedLength{}, quad), pce::Status::ok);
  EXPECT_EQ(status(pp({0, 0, 0.5}, {0, 0, 0}), pce::SignedLength{}, quad), pce::Status::invalid_input);
  EXPECT_EQ(status(pp({1, 2, 3}, {1, 2, 3}), pce::UnsignedLength{}, quad), pce::Status::degenerate);
  EXPECT_EQ(status(pp({0, std::numeric_limits<double>::infinity(), 0}, {0, 0, 0}), pce::UnsignedLength{}, quad),
            pce::Status::invalid_input);
  EXPECT_EQ(status(pp({0, 0, 0.5}, {0, 0, 0}), pce::UnsignedLength{}, pce::LogBarrierPenalty{1.0, 0.0}),
            pce::Status::invalid_input);
}

TEST(PointPointEnergy, AnalyticIsExactForThisKind) {
  pce::PointPointEnergy<double> e;
  ASSERT_EQ(pce::pair_energy<pce::PointPoint>(pp({0.1, 0.2, 0.3}, {0.0, -0.1, 0.25}), pce::UnsignedLength{},
                                              pce::LogBarrierPenalty{1.0, 1.0}, e),
            pce::Status::ok);
  EXPECT_EQ(pce::projected_hessian(e, pce::Projection::analytic), pce::projected_hessian(e, pce::Projection::exact));
  const double d = rel_frobenius<double, 6>(pce::projected_hessian(e, pce::Projection::exact),
                                            pce::projected_hessian(e, pce::Projection::numerical));
  EXPECT_LT(d, 1e-14);
}

TEST(PointPointEnergy, Conformance) {
  const ExactStats st = run_kind_suite<Kind>(draw_point_point, 43);
  std::printf(
      "point_point: exact vs numerical compared on %d configurations (worst %.2e), numerical inaccurate on %d; "
      "worst exact vs 50 digits %.2e\n",
      st.compared, st.worst_vs_numerical, st.numerical_inaccurate, st.worst_vs_reference);
  EXPECT_GT(st.compared, 100);
}

TEST(PointPointHardCases, NearlyCoincidentScalesOffsets) {
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  for (int k = 0; k <= 14; k += 2) {
    const double d = std::pow(10.0, -k);
    SCOPED_TRACE(testing::Message() << "d " << d);
    expect_stable_all_scalars<Kind>(pp(Eigen::Vector3d(0.3, 0.2, 0.1) + d * dir, Eigen::Vector3d(0.3, 0.2, 0.1)),
                                    pce::QuadraticPenalty{1.0, 2 * d});
  }
  for (int k = -8; k <= 8; k += 4) {
    const double s = std::pow(10.0, k);
    SCOPED_TRACE(testing::Message() << "scale " << s);
    expect_stable_all_scalars<Kind>(pp(s * dir, Eigen::Vector3d::Zero()), pce::CubicPenalty{1.0, 2 * s, 0.0});
  }
  const Eigen::Vector3d o(1e6, -8e5, 6e5);
  SCOPED_TRACE("offset 1e6, distance 1e-3");
  expect_stable_all_scalars<Kind>(pp(o + 1e-3 * dir, o), pce::QuadraticPenalty{1.0, 2e-3});
}

}  // namespace
