// SPDX-License-Identifier: MIT
// Tests for energy/mollified_energy.hpp, the opt-in continuous way through degenerate
// frames: identical to the plain energy above the threshold; derivatives against finite
// differences and the 50-digit instantiation inside the mollified band; closed-form
// eigenpairs of the frame Hessian; PSD strategies; and sweeps across both transitions
// (X = X̂ and X → 0: nearly parallel edges, collapsing triangles) showing a C¹ energy that
// reaches E = 0, ∇E = 0 at exactly degenerate input, where the plain energy says `degenerate`.
#include "support/conformance.hpp"
#include "support/high_precision.hpp"

#include <gtest/gtest.h>

namespace {
using namespace pce_test;
using HP = HighPrecision;

/// Edges at angle θ (ea along x, eb rotated by θ in a plane tilted by `tilt`), offset 0.1.
pce::Vec12<double> edges_at(double th, double tilt = 0.3) {
  const Eigen::Vector3d d(std::cos(th), std::sin(th) * std::cos(tilt), std::sin(th) * std::sin(tilt));
  const Eigen::Vector3d c(0.05, 0.3, 0.1);
  pce::Vec12<double> x;
  x << -1, 0, 0, 1, 0, 0, c - d, c + d;
  return x;
}

/// Triangle of height a over edge t0t1 (a → 0 collapses it), vertex above.
pce::Vec12<double> sliver(double a) {
  pce::Vec12<double> x;
  x << 0.3, 0.2, 0.1, 0, 0, 0, 1, 0, 0, 0.4, a, 0;
  return x;
}

const pce::QuadraticPenalty kQuad{2.0, 0.5};
// X̂ = 1e-3 |e0|²|e1|² at rest (parallelogram of unit-ish edges).
template <class Pair> pce::Mollifier rest_mollifier(const pce::Vec12<double>& rest) {
  return {pce::mollifier_threshold<Pair>(rest)};
}

TEST(MollifiedEnergy, EqualsPlainEnergyAboveThreshold) {
  const pce::Vec12<double> x = edges_at(0.8);
  const pce::Mollifier mol = rest_mollifier<pce::EdgeEdge>(edges_at(1.2));
  pce::MollifiedEnergy<double> m;
  pce::PairEnergy<double> p;
  ASSERT_EQ(pce::mollified_pair_energy<pce::EdgeEdge>(x, pce::UnsignedLength{}, kQuad, mol, m), pce::Status::ok);
  ASSERT_EQ(pce::pair_energy<pce::EdgeEdge>(x, pce::UnsignedLength{}, kQuad, p), pce::Status::ok);
  EXPECT_EQ(m.mollifier, 1.0);
  EXPECT_EQ(m.value, p.psi.value);
  EXPECT_EQ(pce::energy_gradient(m), pce::energy_gradient(p));
  EXPECT_EQ(pce::energy_hessian(m), pce::energy_hessian(p));
  EXPECT_EQ(pce::projected_hessian(m, pce::Projection::analytic), pce::projected_hessian(p, pce::Projection::analytic));
}

template <class Pair>
void check_in_band(const pce::Vec12<double>& x, const pce::Mollifier& mol, double expect_m_below) {
  for (LengthKind lk : {LengthKind::signed_positive, LengthKind::unsigned_}) {
    with_length(lk, [&](const auto& len) {
      SCOPED_TRACE(name(lk));
      pce::MollifiedEnergy<long double> e;
      const pce::Vec12<long double> xl = cast12<long double>(x);
      EXPECT_EQ(pce::mollified_pair_energy<Pair>(xl, len, kQuad, mol, e), pce::Status::ok);
      EXPECT_LT(double(e.mollifier), expect_m_below);
      EXPECT_GT(double(e.mollifier), 0.0);
      const pce::Vec12<long double> g = pce::energy_gradient(e);
      const pce::Mat12<long double> H = pce::energy_hessian(e);
      // Finite differences (long double, best of three steps).
      const auto value = [&](const pce::Vec12<long double>& y) {
        pce::MollifiedEnergy<long double> ey;
        EXPECT_EQ(pce::mollified_pair_energy<Pair>(y, len, kQuad, mol, ey), pce::Status::ok);
        return ey.value;
      };
      const auto grad = [&](const pce::Vec12<long double>& y) {
        pce::MollifiedEnergy<long double> ey;
        EXPECT_EQ(pce::mollified_pair_energy<Pair>(y, len, kQuad, mol, ey), pce::Status::ok);
        return pce::energy_gradient(ey);
      };
      double eg = 1e300, eh = 1e300;
      for (long double h : {1e-5L, 1e-6L, 1e-7L}) {
        eg = std::min(eg, rel_error(fd_gradient<long double>(value, xl, h), g));
        eh = std::min(eh, rel_error(fd_jacobian<long double>(grad, xl, h), H));
      }
      EXPECT_LT(eg, 1e-7);
      EXPECT_LT(eh, 1e-6);
      // 50-digit instantiation of the same code.
      pce::MollifiedEnergy<HP> r;
      EXPECT_EQ(pce::mollified_pair_energy<Pair>(cast12<HP>(xl), len, kQuad, mol, r), pce::Status::ok);
      EXPECT_LT(rel_error(g, pce::energy_gradient(r)), 1e-14);
      EXPECT_LT(rel_error(H, pce::energy_hessian(r)), 1e-14);
      // Closed-form eigensystem of the frame Hessian.
      for (int sc = 0; sc < 2; ++sc) {
        const pce::Mat9<long double> Hc = pce::energy_frame_hessian(e);
        const pce::FrameEigensystem<long double> es = pce::energy_eigensystem(e);
        const double n = max_abs(Hc), tol = 1e-13;
        EXPECT_LT(max_abs((es.vectors * es.values.asDiagonal() * es.vectors.transpose() - Hc).eval()) / n, tol);
        EXPECT_LT(max_abs((es.vectors.transpose() * es.vectors - pce::Mat9<long double>::Identity()).eval()), tol);
        for (int i = 0; i < 9; ++i) {
          EXPECT_LT(max_abs((Hc * es.vectors.col(i) - es.values[i] * es.vectors.col(i)).eval()) / n, tol);
          if (i > 0) {
            EXPECT_LE(es.values[i - 1], es.values[i]);
          }
        }
        EXPECT_LT(max_abs((symmetric_eigen(Hc).values - es.values).eval()) / n, tol);
      }
      // Every strategy PSD; analytic ⪰ exact.
      for (pce::Projection p : {pce::Projection::analytic, pce::Projection::abs, pce::Projection::numerical,
                                pce::Projection::gauss_newton}) {
        const pce::Mat12<long double> P = pce::projected_hessian(e, p);
        EXPECT_GE(min_eigenvalue(P), -1e-15 * std::max(max_abs(P), max_abs(H))) << pce::to_string(p);
      }
      EXPECT_GE(min_eigenvalue((pce::projected_hessian(e, pce::Projection::analytic) - H).eval()), -1e-15 * max_abs(H));
      return 0;
    });
  }
}

TEST(MollifiedEnergy, DerivativesAndEigensystemInsideTheBand) {
  const pce::Mollifier ee = rest_mollifier<pce::EdgeEdge>(edges_at(1.2));
  for (double th : {0.03, 0.01, 1e-3}) check_in_band<pce::EdgeEdge>(edges_at(th), ee, 1.0);
  const pce::Mollifier vf = rest_mollifier<pce::VertexFace>(sliver(0.9));
  for (double a : {0.02, 1e-3}) check_in_band<pce::VertexFace>(sliver(a), vf, 1.0);
}

TEST(MollifiedEnergy, ContinuousThroughParallelEdges) {
  // Sweep θ from inside the plain regime down to exactly parallel: E and ∇E go to zero
  // continuously, ∇²E stays bounded; the plain energy reports `degenerate` at θ = 0.
  const pce::Mollifier mol = rest_mollifier<pce::EdgeEdge>(edges_at(1.2));
  double prevE = -1, maxH = 0;
  for (int i = 0; i <= 90; ++i) {
    const double th = i == 90 ? 0.0 : 0.2 * std::pow(10.0, -i / 6.0);
    for (LengthKind lk : {LengthKind::signed_positive, LengthKind::unsigned_}) {
      with_length(lk, [&](const auto& len) {
        pce::MollifiedEnergy<double> e;
        EXPECT_EQ(pce::mollified_pair_energy<pce::EdgeEdge>(edges_at(th), len, kQuad, mol, e), pce::Status::ok);
        const double E = e.value, G = max_abs(pce::energy_gradient(e));
        double H = 0;
        for (pce::Projection p : {pce::Projection::none, pce::Projection::analytic, pce::Projection::abs,
                                  pce::Projection::numerical, pce::Projection::gauss_newton}) {
          const double Hp = max_abs(pce::projected_hessian(e, p));
          EXPECT_LT(Hp, 1e4) << "θ = " << th << ", " << pce::to_string(p);
          H = std::max(H, Hp);
        }
        EXPECT_TRUE(std::isfinite(E) && std::isfinite(G) && std::isfinite(H)) << th;
        maxH = std::max(maxH, H);
        if (th < 1e-4) {  // deep in the band: E ~ θ², ∇E ~ θ
          EXPECT_LT(E, 1e3 * th * th + 1e-300) << th;
          EXPECT_LT(G, 1e3 * th + 1e-300) << th;
        }
        if (lk == LengthKind::unsigned_) {
          if (prevE >= 0 && th < 1e-2) {
            EXPECT_LE(E, prevE * 1.0001 + 1e-300) << "monotone fade at " << th;
          }
          prevE = E;
        }
        if (th == 0.0) {
          EXPECT_EQ(e.mollifier, 0.0);
          EXPECT_EQ(E, 0.0);
          EXPECT_EQ(G, 0.0);
          pce::PairEnergy<double> plain;
          EXPECT_EQ(pce::pair_energy<pce::EdgeEdge>(edges_at(th), len, kQuad, plain), pce::Status::degenerate);
        }
        return 0;
      });
    }
  }
  EXPECT_LT(maxH, 1e4);
}

TEST(MollifiedEnergy, C1AtTheThreshold) {
  // Across X = X̂ value and gradient are continuous (the mollifier is C¹).
  const pce::Vec12<double> x = edges_at(0.05);
  pce::MollifiedEnergy<double> e0;
  ASSERT_EQ(pce::mollified_pair_energy<pce::EdgeEdge>(x, pce::UnsignedLength{}, kQuad, pce::Mollifier{1.0}, e0),
            pce::Status::ok);
  const double Xh = e0.X;  // put the threshold exactly at this configuration
  for (double f : {1 - 1e-7, 1 + 1e-7}) {
    pce::MollifiedEnergy<double> e;
    ASSERT_EQ(pce::mollified_pair_energy<pce::EdgeEdge>(x, pce::UnsignedLength{}, kQuad, pce::Mollifier{Xh * f}, e),
              pce::Status::ok);
    pce::PairEnergy<double> p;
    ASSERT_EQ(pce::pair_energy<pce::EdgeEdge>(x, pce::UnsignedLength{}, kQuad, p), pce::Status::ok);
    EXPECT_NEAR(e.value, p.psi.value, 1e-6 * p.psi.value);
    EXPECT_LT(rel_error(pce::energy_gradient(e), pce::energy_gradient(p)), 1e-5);
  }
}

TEST(MollifiedEnergy, CollapsingTriangleAndBadInput) {
  const pce::Mollifier mol = rest_mollifier<pce::VertexFace>(sliver(0.9));
  pce::MollifiedEnergy<double> e;
  EXPECT_EQ(pce::mollified_pair_energy<pce::VertexFace>(sliver(0.0), pce::UnsignedLength{}, kQuad, mol, e),
            pce::Status::ok);
  EXPECT_FALSE(e.has_frame);
  EXPECT_EQ(e.value, 0.0);
  EXPECT_EQ(pce::energy_eigensystem(e).values, pce::Vec9<double>::Zero());
  pce::Vec12<double> bad = sliver(0.1);
  bad[2] = std::nan("");
  EXPECT_EQ(pce::mollified_pair_energy<pce::VertexFace>(bad, pce::UnsignedLength{}, kQuad, mol, e),
            pce::Status::invalid_input);
  EXPECT_EQ(
      pce::mollified_pair_energy<pce::VertexFace>(sliver(0.1), pce::UnsignedLength{}, kQuad, pce::Mollifier{0.0}, e),
      pce::Status::invalid_input);
  EXPECT_EQ(pce::mollified_pair_energy<pce::VertexFace>(sliver(0.1), pce::UnsignedLength{}, kQuad,
                                                        pce::Mollifier{std::nan("")}, e),
            pce::Status::invalid_input);
}

}  // namespace
