// SPDX-License-Identifier: MIT
// Tests for lengths/length_hessian.hpp: the closed-form eigenpairs of the 2×2 families
// (supplement Sec. 2) and the frame Hessian of the signed length (supplement Eqs. 13–37),
// both checked against independent computations.
#include "support/conformance.hpp"
#include "support/scalars.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {
using namespace pce_test;

template <class S> class LengthHessian : public testing::Test {};
TYPED_TEST_SUITE(LengthHessian, Scalars);

TYPED_TEST(LengthHessian, FamilyEigenpairsSolveTheTwoByTwoBlock) {
  using S = TypeParam;
  const double ratios[] = {0.0, -0.0, 1e-12, -1e-12, 1e-4, 0.3, -0.3, 2.0, -7.0, 1e6, -1e6, 1e15, -1e15};
  for (double a : {1e-3, 1.0, 1e3})
    for (double r : ratios) {
      const S aa = S(a), l = S(r * a);
      const pce::LengthFamily<S> F = pce::length_family(l, aa);
      // B = [[−l/a², −1/a], [−1/a, 0]]
      Eigen::Matrix<S, 2, 2> B;
      B << -(l / aa) / aa, -S(1) / aa, -S(1) / aa, S(0);
      const Eigen::Matrix<S, 2, 1> qb = F.big(), qs = F.small();
      const double scale = std::max(max_abs(B), 1e-300);
      const double tol = ulps<S>(16);
      EXPECT_LT(max_abs((B * qb - F.lambda_big * qb).eval()) / scale, tol) << "a=" << a << " l/a=" << r;
      EXPECT_LT(max_abs((B * qs - F.lambda_small * qs).eval()) / scale, tol) << "a=" << a << " l/a=" << r;
      EXPECT_NEAR(double(qb.norm()), 1.0, tol);
      EXPECT_NEAR(double(qs.norm()), 1.0, tol);
      EXPECT_NEAR(double(qb.dot(qs)), 0.0, tol);
      // λ_big λ_small = det B = −1/a², λ_big + λ_small = tr B = −l/a².
      EXPECT_NEAR(double(F.lambda_big * F.lambda_small * aa * aa), -1.0, tol * 4);
      EXPECT_LE(std::fabs(double(F.lambda_small)), std::fabs(double(F.lambda_big)));
      EXPECT_TRUE(std::isfinite(double(F.lambda_big)) && std::isfinite(double(F.lambda_small)));
    }
}

TEST(LengthHessianPaper, EigenvaluesMatchTheSupplementsFormula) {
  // Supplement Sec. 2 (main paper Sec. 4.3): λ = −l/(2a²) (1 ± √(1 + 4a²/|e2⊥|²)), |e2⊥| = |l|.
  for (double a : {0.5, 1.0, 3.0})
    for (double l : {-2.0, -0.1, 0.01, 0.7, 4.0}) {
      const long double A = a, Lv = l;
      const long double lp = -Lv / (2 * A * A) * (1 + std::sqrt(1 + 4 * A * A / (Lv * Lv)));
      const long double lm = -Lv / (2 * A * A) * (1 - std::sqrt(1 + 4 * A * A / (Lv * Lv)));
      const pce::LengthFamily<long double> F = pce::length_family(Lv, A);
      const long double big = std::fabs(lp) > std::fabs(lm) ? lp : lm, small = std::fabs(lp) > std::fabs(lm) ? lm : lp;
      EXPECT_NEAR(double(F.lambda_big), double(big), 1e-15 * std::fabs(double(big)));
      EXPECT_NEAR(double(F.lambda_small), double(small), 1e-12 * std::fabs(double(small)));
    }
}

TEST(LengthHessianPaper, SupplementReducedMatrixTypo) {
  // The e1 family's reduced 2×2 matrix is printed as (−l/|e1⊥|²)[[0,1],[|e1⊥|²,1]]; the
  // lower-left entry must be |e1⊥|²/|e2⊥|² (docs/math.md). Check both against B's spectrum.
  const double a = 0.7, l = 0.3;  // |e1⊥| = a, |e2⊥| = |l|
  const pce::LengthFamily<double> F = pce::length_family(l, a);
  auto eig = [](Eigen::Matrix2d M) {
    Eigen::EigenSolver<Eigen::Matrix2d> es(M);
    Eigen::Vector2d v = es.eigenvalues().real();
    std::sort(v.data(), v.data() + 2);
    return v;
  };
  Eigen::Matrix2d corrected, printed;
  corrected << 0, 1, (a * a) / (l * l), 1;
  printed << 0, 1, a * a, 1;
  corrected *= -l / (a * a);
  printed *= -l / (a * a);
  Eigen::Vector2d ours(std::min(F.lambda_big, F.lambda_small), std::max(F.lambda_big, F.lambda_small));
  EXPECT_LT((eig(corrected) - ours).norm(), 1e-12);
  EXPECT_GT((eig(printed) - ours).norm(), 1e-2);
}

/// l(c) = c2·(c0 × c1)/|c0 × c1| at an arbitrary (not necessarily orthogonal) c: the
/// definition, written independently of the library.
long double direct_length(const Eigen::Matrix<long double, 9, 1>& c) {
  const Eigen::Matrix<long double, 3, 1> c0 = c.segment<3>(0), c1 = c.segment<3>(3), c2 = c.segment<3>(6);
  const Eigen::Matrix<long double, 3, 1> m = c0.cross(c1);
  return c2.dot(m) / m.norm();
}

TEST(LengthHessianFrame, MatchesSecondDifferencesOfTheDefinition) {
  std::mt19937_64 rng(41);
  for (PairKind kind : {PairKind::vertex_face, PairKind::edge_edge})
    for (int i = 0; i < 20; ++i) {
      const pce::Vec12<long double> x =
          cast12<long double>(random_configuration(kind, 0.8 * ((i % 5) - 2) + 0.05, 1, 0, rng).x);
      pce::Frame<long double> f;
      ASSERT_EQ(with_pair(kind, [&](auto p) { return decltype(p)::frame(x, f); }), pce::Status::ok);
      Eigen::Matrix<long double, 9, 1> c;
      c << f.a0 * f.t0, f.a1 * f.t1, f.l * f.n;
      const long double h = 1e-4L;
      Eigen::Matrix<long double, 9, 9> Hfd;
      Eigen::Matrix<long double, 9, 1> gfd;
      for (int a = 0; a < 9; ++a) {
        auto ca = c;
        ca[a] += h;
        auto cb = c;
        cb[a] -= h;
        gfd[a] = (direct_length(ca) - direct_length(cb)) / (2 * h);
        for (int b = 0; b < 9; ++b) {
          auto pp = c, pm = c, mp = c, mm = c;
          pp[a] += h, pp[b] += h, pm[a] += h, pm[b] -= h, mp[a] -= h, mp[b] += h, mm[a] -= h, mm[b] -= h;
          Hfd(a, b) = (direct_length(pp) - direct_length(pm) - direct_length(mp) + direct_length(mm)) / (4 * h * h);
        }
      }
      const pce::SignedLength len{};
      EXPECT_LT(rel_error(pce::length_gradient(f, len), gfd), 1e-7);
      EXPECT_LT(rel_error(pce::length_hessian(f, len), Hfd), 1e-6);
    }
}

}  // namespace
