// SPDX-License-Identifier: MIT
// The stable Neo-Hookean energy (volumes/stable_neo_hookean.hpp): its stress and Hessian
// against central differences in double and against the same templates in 50 digits, the
// closed-form eigensystem by its residuals, orthonormality and reconstruction, and the
// analytic projection against the numerical one, on random, near-inverted, inverted and flat
// deformation gradients; the rest state against linear elasticity; the tetrahedron's
// pull-back `Bᵀ H B` against B formed explicitly.
#include <pce/volumes/stable_neo_hookean.hpp>

#include "support/high_precision.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using pce::Mat3;
using pce::Mat9;
using pce::Vec9;
using HP = pce_test::HighPrecision;

const pce::StableNeoHookean kMaterial = pce::StableNeoHookean::from_young_poisson(1e5, 0.4);

/// Deformation gradients of every kind the solver meets: near the identity, large stretch and
/// compression, nearly inverted, inverted, flat (rank 2 and 1), zero, and with repeated
/// singular values.
std::vector<Mat3<double>> deformation_gradients(unsigned seed, int random_count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Mat3<double>> Fs;
  const auto rotation = [&]() {
    Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
    q.normalize();
    return Mat3<double>(q.toRotationMatrix());
  };
  for (int i = 0; i < random_count; ++i) {
    Mat3<double> F;
    for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = u(rng);
    Fs.push_back(F);
    Fs.push_back(Mat3<double>::Identity() + 0.1 * F);
    // SVD-built: σ = (a, b, c) with c near 0, negative, or equal to a or b
    const double a = std::exp(2 * u(rng)), b = std::exp(2 * u(rng));
    for (const double c : {1e-9, -1e-9, -0.5, 0.0, a, -b})
      Fs.push_back(rotation() * Eigen::Vector3d(a, b, c).asDiagonal() * rotation());
  }
  Fs.push_back(Mat3<double>::Identity());
  Fs.push_back(Mat3<double>::Zero());
  Fs.push_back(Eigen::Vector3d(1, 1, 0).asDiagonal());
  Fs.push_back(Eigen::Vector3d(2, 0, 0).asDiagonal());
  Fs.push_back(-Mat3<double>::Identity());
  return Fs;
}

double scale_of(const Mat3<double>& F) { return 1.0 + F.squaredNorm() + std::abs(F.determinant()); }

}  // namespace

TEST(StableNeoHookean, RestStateIsLinearElasticity) {
  const Mat3<double> I = Mat3<double>::Identity();
  EXPECT_EQ(pce::snh_energy_density(kMaterial, I), 0.0);
  EXPECT_LE(pce::snh_stress(kMaterial, I).norm(), 1e-12 * kMaterial.lambda);
  // μ(I + T) + λ_Lamé vec(I) vec(I)ᵀ, T the transposition of vec(F)
  const double mu = kMaterial.mu, lame = kMaterial.lambda - kMaterial.mu;
  Mat9<double> expected = mu * Mat9<double>::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) expected(3 * c + r, 3 * r + c) += mu;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) expected(4 * i, 4 * j) += lame;
  EXPECT_LE((pce::snh_hessian(kMaterial, I) - expected).norm(), 1e-12 * expected.norm());
}

TEST(StableNeoHookean, StressAndHessianMatchCentralDifferences) {
  int checked = 0;
  for (const Mat3<double>& F : deformation_gradients(1, 40)) {
    const Mat3<double> P = pce::snh_stress(kMaterial, F);
    const Mat9<double> H = pce::snh_hessian(kMaterial, F);
    const double h = 1e-6 * (1 + F.norm());
    for (int k = 0; k < 9; ++k) {
      Mat3<double> Fp = F, Fm = F;
      Fp.data()[k] += h;
      Fm.data()[k] -= h;
      const double dpsi = (pce::snh_energy_density(kMaterial, Fp) - pce::snh_energy_density(kMaterial, Fm)) / (2 * h);
      const Mat3<double> dP = (pce::snh_stress(kMaterial, Fp) - pce::snh_stress(kMaterial, Fm)) / (2 * h);
      const double tol = 1e-6 * kMaterial.lambda * scale_of(F);
      ASSERT_NEAR(P.data()[k], dpsi, tol) << "entry " << k << " of F =\n" << F;
      for (int i = 0; i < 9; ++i) ASSERT_NEAR(H(i, k), dP.data()[i], tol) << "H(" << i << ", " << k << ") at\n" << F;
    }
    ++checked;
  }
  EXPECT_GT(checked, 300);
}

TEST(StableNeoHookean, FiftyDigitsAgreeWithDouble) {
  pce::StableNeoHookean m = kMaterial;
  for (const Mat3<double>& F : deformation_gradients(2, 20)) {
    const Mat3<HP> Fh = F.cast<HP>();
    const double s = kMaterial.lambda * scale_of(F) * scale_of(F);
    const double eps = 1e-14;
    EXPECT_NEAR(pce::snh_energy_density(m, F), double(pce::snh_energy_density(m, Fh)), eps * s);
    EXPECT_LE((pce::snh_stress(m, F) - pce::snh_stress(m, Fh).cast<double>()).norm(), eps * s);
    EXPECT_LE((pce::snh_hessian(m, F) - pce::snh_hessian(m, Fh).cast<double>()).norm(), eps * s);
    const pce::SnhEigensystem<HP> e = pce::snh_eigensystem(m, Fh);
    const Mat9<HP> Hh = pce::snh_hessian(m, Fh);
    EXPECT_LE(double((Hh * e.vectors - e.vectors * e.values.asDiagonal()).norm()), 1e-40 * s);
  }
}

TEST(StableNeoHookean, ClosedFormEigensystemHasSmallResiduals) {
  int checked = 0;
  for (const Mat3<double>& F : deformation_gradients(3, 200)) {
    const pce::SnhEigensystem<double> e = pce::snh_eigensystem(kMaterial, F);
    const Mat9<double> H = pce::snh_hessian(kMaterial, F);
    const double norm = H.norm(), eps = std::numeric_limits<double>::epsilon();
    ASSERT_TRUE(e.values.allFinite() && e.vectors.allFinite()) << F;
    EXPECT_LE((e.vectors.transpose() * e.vectors - Mat9<double>::Identity()).norm(), 64 * eps) << F;
    for (int i = 0; i < 9; ++i)
      EXPECT_LE((H * e.vectors.col(i) - e.values[i] * e.vectors.col(i)).norm(), 256 * eps * norm)
          << "mode " << i << " of\n"
          << F;
    EXPECT_LE((e.vectors * e.values.asDiagonal() * e.vectors.transpose() - H).norm(), 256 * eps * norm) << F;
    ++checked;
  }
  EXPECT_GT(checked, 1500);
}

TEST(StableNeoHookean, AnalyticProjectionEqualsNumerical) {
  double worst = 0;
  for (const Mat3<double>& F : deformation_gradients(4, 200)) {
    const Mat9<double> a = pce::snh_projected_hessian(kMaterial, F, pce::VolumeProjection::analytic);
    const Mat9<double> n = pce::snh_projected_hessian(kMaterial, F, pce::VolumeProjection::numerical);
    const double norm = pce::snh_hessian(kMaterial, F).norm(), eps = std::numeric_limits<double>::epsilon();
    worst = std::max(worst, (a - n).norm() / (eps * norm));
    EXPECT_LE((a - n).norm(), 1024 * eps * norm) << F;
    EXPECT_EQ(a, a.transpose());
    const Eigen::SelfAdjointEigenSolver<Mat9<double>> es(a);
    EXPECT_GE(es.eigenvalues().minCoeff(), -64 * eps * norm) << F;
  }
  std::printf("worst |analytic - numerical| / (eps |H|): %.1f\n", worst);
}

TEST(StableNeoHookean, TetEnergyPullsBackThroughTheRestShape) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  pce::Vec12<double> X;
  X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  pce::TetRest<double> rest;
  ASSERT_EQ(pce::tet_rest(X, rest), pce::Status::ok);
  EXPECT_DOUBLE_EQ(rest.volume, 1.0 / 6);
  EXPECT_LE((pce::deformation_gradient(rest, X) - Mat3<double>::Identity()).norm(), 1e-15);
  // flat and inverted rest shapes are refused
  pce::Vec12<double> flat = X, inverted = X;
  flat[11] = 0;
  inverted[11] = -1;
  EXPECT_EQ(pce::tet_rest(flat, rest), pce::Status::degenerate);
  EXPECT_EQ(pce::tet_rest(inverted, rest), pce::Status::degenerate);
  pce::Vec12<double> nan = X;
  nan[4] = std::nan("");
  EXPECT_EQ(pce::tet_rest(nan, rest), pce::Status::invalid_input);
  for (int trial = 0; trial < 50; ++trial) {
    pce::Vec12<double> R, x;
    for (int i = 0; i < 12; ++i) R[i] = X[i] + 0.2 * u(rng);
    if (pce::tet_rest(R, rest) != pce::Status::ok) continue;
    for (int i = 0; i < 12; ++i) x[i] = R[i] + 0.3 * u(rng);
    double E = 0;
    pce::Vec12<double> g;
    pce::Mat12<double> H;
    ASSERT_EQ(pce::snh_tet_energy(kMaterial, rest, x, pce::VolumeProjection::none, E, &g, &H), pce::Status::ok);
    // translation invariance: the forces sum to zero
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(g[c] + g[3 + c] + g[6 + c] + g[9 + c], 0.0, 1e-9 * g.norm());
    const double h = 1e-6;
    for (int k = 0; k < 12; ++k) {
      pce::Vec12<double> xp = x, xm = x, gp, gm;
      xp[k] += h;
      xm[k] -= h;
      double Ep = 0, Em = 0;
      pce::snh_tet_energy<double>(kMaterial, rest, xp, pce::VolumeProjection::none, Ep, &gp, nullptr);
      pce::snh_tet_energy<double>(kMaterial, rest, xm, pce::VolumeProjection::none, Em, &gm, nullptr);
      const double tol = 1e-5 * (1 + g.norm() + H.norm());
      EXPECT_NEAR(g[k], (Ep - Em) / (2 * h), tol) << "trial " << trial << " coordinate " << k;
      EXPECT_LE((H.col(k) - (gp - gm) / (2 * h)).norm(), tol) << "trial " << trial << " coordinate " << k;
    }
    EXPECT_EQ(H, H.transpose());
    pce::Mat12<double> Ha;
    ASSERT_EQ(pce::snh_tet_energy<double>(kMaterial, rest, x, pce::VolumeProjection::analytic, E, nullptr, &Ha),
              pce::Status::ok);
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<pce::Mat12<double>>(Ha).eigenvalues().minCoeff(), -1e-9 * Ha.norm());
  }
}

// pull_back_hessian against scale·Bᵀ H B with B (vec(F) = B x) formed explicitly, on random
// rest shapes and random symmetric H: every block, vertex 0's (negated sums) included, and
// symmetric bit for bit.
TEST(StableNeoHookean, PullBackHessianIsBtHB) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-1, 1);
  int checked = 0;
  for (int trial = 0; trial < 400 && checked < 100; ++trial) {
    pce::Vec12<double> X, x;
    for (int i = 0; i < 12; ++i) X[i] = u(rng), x[i] = u(rng);
    pce::TetRest<double> rest;
    if (pce::tet_rest(X, rest) != pce::Status::ok) continue;
    Eigen::Matrix<double, 9, 12> B = Eigen::Matrix<double, 9, 12>::Zero();
    for (int j = 0; j < 4; ++j)
      for (int c = 0; c < 3; ++c) B.block<3, 3>(3 * c, 3 * j) = rest.G(j, c) * Mat3<double>::Identity();
    const Mat3<double> F = pce::deformation_gradient(rest, x);
    ASSERT_LE((Eigen::Map<const Vec9<double>>(F.data()) - B * x).norm(), 1e-13 * B.norm() * x.norm());
    Mat9<double> H;
    for (int k = 0; k < 81; ++k) H.data()[k] = u(rng);
    H = (H + H.transpose()).eval();
    const double scale = 0.5 + std::abs(u(rng));
    const pce::Mat12<double> expected = scale * B.transpose() * H * B;
    const pce::Mat12<double> got = pce::pull_back_hessian(rest, H, scale);
    EXPECT_LE((got - expected).norm(), 1e-13 * scale * B.squaredNorm() * H.norm()) << "trial " << trial;
    EXPECT_EQ(got, got.transpose());
    ++checked;
  }
  EXPECT_EQ(checked, 100);
}

TEST(StableNeoHookean, HardInputsGiveAStatusOrFiniteOutputs) {
  pce::Vec12<double> X;
  X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  pce::TetRest<double> rest;
  ASSERT_EQ(pce::tet_rest(X, rest), pce::Status::ok);
  double E = 7;
  pce::Vec12<double> g = pce::Vec12<double>::Constant(7);
  pce::Mat12<double> H;
  // huge: Ψ beyond double's range
  EXPECT_EQ(
      pce::snh_tet_energy(kMaterial, rest, pce::Vec12<double>(X * 1e110), pce::VolumeProjection::analytic, E, &g, &H),
      pce::Status::overflow);
  pce::Vec12<double> bad = X;
  bad[0] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(pce::snh_tet_energy(kMaterial, rest, bad, pce::VolumeProjection::analytic, E, &g, &H),
            pce::Status::invalid_input);
  EXPECT_EQ(pce::snh_tet_energy(pce::StableNeoHookean{-1, 1}, rest, X, pce::VolumeProjection::analytic, E, &g, &H),
            pce::Status::invalid_input);
  EXPECT_EQ(E, 7);  // nothing written
  EXPECT_EQ(g[0], 7);
  // collapsed to a point, a plane, a line; inverted through the origin
  for (const double s : {0.0, -1.0}) {
    pce::Vec12<double> x = s * X;
    ASSERT_EQ(pce::snh_tet_energy(kMaterial, rest, x, pce::VolumeProjection::analytic, E, &g, &H), pce::Status::ok);
    EXPECT_TRUE(std::isfinite(E) && g.allFinite() && H.allFinite());
  }
}

// Fuzzed deformation gradients through a unit tetrahedron (Dm = I, so F = Ds): random
// matrices over 16 decades of scale, inverted, flat (rank 2, 1, 0) and huge ones, each with
// every output of every projection. `ok` must give finite outputs, and only a Ψ beyond
// double's range may give `overflow`. PCE_SNH_FUZZ_COUNT sets the number of gradients (default
// 20 000; `PCE_SNH_FUZZ_COUNT=1000000 tests/test_stable_neo_hookean --gtest_filter=*Fuzz*`
// is the long run, docs/volumes.md).
TEST(StableNeoHookean, FuzzedDeformationGradientsStayFinite) {
  const char* env = std::getenv("PCE_SNH_FUZZ_COUNT");
  const long count = env ? std::atol(env) : 20000;
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> u(-1, 1), ex(-8, 8), pick(0, 1);
  pce::Vec12<double> X;
  X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  pce::TetRest<double> rest;
  ASSERT_EQ(pce::tet_rest(X, rest), pce::Status::ok);
  long ok = 0, overflow = 0, compared = 0;
  double worst = 0, worst_large = 0;
  Mat3<double> worst_F = Mat3<double>::Zero();
  for (long n = 0; n < count; ++n) {
    Mat3<double> F;
    for (int k = 0; k < 9; ++k) F.data()[k] = u(rng);
    const double what = pick(rng);
    if (what < 0.1)
      F.col(2) = u(rng) * F.col(0) + u(rng) * F.col(1);  // flat: rank 2
    else if (what < 0.15)
      F.col(1) = u(rng) * F.col(0), F.col(2) = u(rng) * F.col(0);  // a line: rank 1
    else if (what < 0.17)
      F.setZero();
    else if (what < 0.4)
      F = Mat3<double>::Identity() + 1e-3 * F;  // near rest
    if (pick(rng) < 0.3) F.col(0) = -F.col(0);  // inverted
    const bool huge = pick(rng) < 0.02;
    F *= huge ? std::pow(10.0, 40 + 80 * pick(rng)) : std::pow(10.0, ex(rng));
    pce::Vec12<double> x = pce::Vec12<double>::Zero();
    for (int c = 0; c < 3; ++c) x.segment<3>(3 * (c + 1)) = F.col(c);
    for (const pce::VolumeProjection how :
         {pce::VolumeProjection::none, pce::VolumeProjection::analytic, pce::VolumeProjection::numerical}) {
      double E = 0;
      pce::Vec12<double> g;
      pce::Mat12<double> H;
      const pce::Status s = pce::snh_tet_energy(kMaterial, rest, x, how, E, &g, &H);
      if (s == pce::Status::overflow) {
        ++overflow;
        ASSERT_GT(F.norm(), 1e30) << "overflow for a moderate F:\n" << F;
        continue;
      }
      ASSERT_EQ(s, pce::Status::ok) << F;
      ++ok;
      ASSERT_TRUE(std::isfinite(E) && g.allFinite() && H.allFinite()) << F;
    }
    if (!huge && n % 16 == 0) {  // the eigensystem itself, and analytic against numerical
      const pce::SnhEigensystem<double> e = pce::snh_eigensystem(kMaterial, F);
      ASSERT_TRUE(e.values.allFinite() && e.vectors.allFinite()) << F;
      const Mat9<double> a = pce::snh_projected_hessian(kMaterial, F, pce::VolumeProjection::analytic);
      const Mat9<double> nm = pce::snh_projected_hessian(kMaterial, F, pce::VolumeProjection::numerical);
      const double norm = pce::snh_hessian(kMaterial, F).norm();
      if (norm > 0) {
        const double r = (a - nm).norm() / (std::numeric_limits<double>::epsilon() * norm);
        if (F.norm() > 1e3) {
          worst_large = std::max(worst_large, r);  // reported, not asserted: see below
        } else if (r > worst) {
          worst = r;
          worst_F = F;
        }
      }
      ++compared;
    }
  }
  // Beyond |F| ~ 1e3 (a thousandfold stretch) det F and cof F, which the Hessian is built from,
  // carry errors of ε‖F‖³ and ε‖F‖² of their own, and nearly flat such F then make analytic
  // and numerical differ by more than rounding of ‖H‖ (1e6 runs: up to ~2e6 ε‖H‖ at
  // ‖F‖ ~ 8e7); both are then as good as H itself.
  std::printf(
      "fuzzed F: %ld, ok %ld, overflow %ld; analytic vs numerical on %ld: worst %.1f eps |H| (|F| <= 1e3), "
      "%.1f eps |H| (larger)\n",
      count, ok, overflow, compared, worst, worst_large);
  EXPECT_LE(worst, 1024) << "at F =\n" << worst_F;
}
