// SPDX-License-Identifier: MIT
// Hard cases stay numerically stable (docs/stability.md): every hard-case family of
// tests/support/hard_cases.hpp, swept over its severities, in float, double and long
// double. For each case: the expected status (degenerate where the frame does not exist);
// finite outputs; every PSD strategy PSD (λ_min ≥ −1e-12·max|λ| in double); value,
// gradient and Hessian within 16× the input-rounding bound + 256 roundoffs of the 50-digit
// evaluation of the same code at the same input (tests/support/stability_measure.hpp).
#include "support/stability_measure.hpp"

#include <gtest/gtest.h>

#include <set>

namespace {
using namespace pce_test;

struct FamilyScalar {
  std::string family;
  int scalar;  // 0 float, 1 double, 2 long double
};

std::vector<FamilyScalar> families() {
  std::set<std::string> names;
  for (const HardCase& hc : hard_cases()) names.insert(hc.family);
  std::vector<FamilyScalar> v;
  for (const std::string& n : names)
    for (int s = 0; s < 3; ++s) v.push_back({n, s});
  return v;
}

class HardCases : public testing::TestWithParam<FamilyScalar> {};

template <class S> void check_family(const std::string& family) {
  int n = 0;
  for (const HardCase& hc : hard_cases()) {
    if (hc.family != family) continue;
    ++n;
    const Measurement m = measure<S>(hc);
    SCOPED_TRACE(testing::Message() << family << " severity " << hc.severity << " " << name(hc.length));
    if (hc.degenerate) {
      EXPECT_EQ(m.status, pce::Status::degenerate);
      continue;
    }
    if (m.status != pce::Status::ok) {
      // Only where the rounded input itself is outside the domain or degenerate (float).
      EXPECT_TRUE(passes(hc, m)) << pce::to_string(m.status) << ", exact: " << pce::to_string(m.reference_status)
                                 << ", L " << m.length << " ± " << m.bound_length;
      if (!std::is_same_v<S, float>) {
        EXPECT_EQ(m.status, pce::Status::ok);
      }
      continue;
    }
    EXPECT_TRUE(m.finite);
    EXPECT_GE(m.worst_psd, psd_threshold(m.unit_roundoff));
    EXPECT_TRUE(within(m.err_value, m.bound_value, m.unit_roundoff))
        << "value error " << m.err_value << ", bound " << m.bound_value;
    EXPECT_TRUE(within(m.err_gradient, m.bound_gradient, m.unit_roundoff))
        << "gradient error " << m.err_gradient << ", bound " << m.bound_gradient;
    EXPECT_TRUE(within(m.err_hessian, m.bound_hessian, m.unit_roundoff))
        << "Hessian error " << m.err_hessian << ", bound " << m.bound_hessian;
    EXPECT_TRUE(passes(hc, m));
  }
  EXPECT_GT(n, 0);
}

TEST_P(HardCases, WithinInputRoundingBound) {
  const FamilyScalar p = GetParam();
  if (p.scalar == 0) check_family<float>(p.family);
  if (p.scalar == 1) check_family<double>(p.family);
  if (p.scalar == 2) check_family<long double>(p.family);
}

std::string family_name(const testing::TestParamInfo<FamilyScalar>& i) {
  static const char* const scalars[3] = {"float", "double", "long_double"};
  return i.param.family + "_" + scalars[i.param.scalar];
}

INSTANTIATE_TEST_SUITE_P(Families, HardCases, testing::ValuesIn(families()), family_name);

// The bound is not vacuous: where the problem is well conditioned it is a few roundoffs,
// so an algorithm losing digits there would fail.
TEST(HardCasesBound, TightWhereWellConditioned) {
  for (const HardCase& hc : hard_cases()) {
    if (hc.family != "vf_plane" || hc.length != LengthKind::signed_positive) continue;
    const Measurement m = measure<double>(hc);
    EXPECT_LT(m.bound_gradient, 1e-14) << hc.severity;
    EXPECT_LT(m.bound_hessian, 1e-14) << hc.severity;
    EXPECT_LT(m.err_hessian, 1e-14) << hc.severity;
  }
}

// Unsigned length: the projected Hessian stays bounded as L → 0 (from both sides).
TEST(HardCasesUnsigned, ProjectedHessianBoundedAsLengthVanishes) {
  double first = 0;
  for (const HardCase& hc : hard_cases()) {
    if (hc.family != "vf_plane" || hc.length != LengthKind::unsigned_) continue;
    with_penalty(hc.penalty, [&](const auto& pen) {
      pce::PairEnergy<double> e;
      EXPECT_EQ(pce::pair_energy<pce::VertexFace>(hc.x, pce::UnsignedLength{}, pen, e), pce::Status::ok);
      for (pce::Projection p : {pce::Projection::analytic, pce::Projection::abs, pce::Projection::numerical}) {
        const double n = max_abs(pce::projected_hessian(e, p));
        if (first == 0) first = n;
        EXPECT_LT(n, 3 * first) << hc.severity << " " << pce::to_string(p);
      }
      return 0;
    });
  }
}

}  // namespace
