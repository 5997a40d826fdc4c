// SPDX-License-Identifier: MIT
// Tests for friction/lagged_friction.hpp: the mollifier's values and continuity, the
// closest-point weights and normals of every pair kind (plane frames, point-edge,
// point-point) and of a single vertex, and the potential's gradient and Hessian against
// central differences of the long double instantiation and against the 50-digit one, the
// Hessian positive semidefinite with the closed-form eigenpairs of its tangent block.
#include "support/eigensolvers.hpp"
#include "support/high_precision.hpp"

#include <pce/energy/closest_feature.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/friction/lagged_friction.hpp>
#include <pce/penalties/quadratic.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {
using namespace pce;
using HP = pce_test::HighPrecision;

template <class S, int N> LaggedFriction<S, N> cast(const LaggedFriction<double, N>& f) {
  LaggedFriction<S, N> g;
  g.weights = f.weights.template cast<S>();
  g.basis = f.basis.template cast<S>();
  g.offset = f.offset.template cast<S>();
  g.mu_lambda = S(f.mu_lambda);
  g.static_slip = S(f.static_slip);
  return g;
}

/// Gradient and Hessian of `f` at `dx` against central differences of the long double
/// energy and gradient, and against 50 digits; the Hessian PSD; the tangent block's
/// eigenpairs μλ f₁′ on T û, μλ f₁/y on T û⊥, 0 on the normal.
template <int N>
void check(const LaggedFriction<double, N>& f, const Eigen::Matrix<double, 3 * N, 1>& dx, const Vec3<double>& normal) {
  using V = Eigen::Matrix<double, 3 * N, 1>;
  using VL = Eigen::Matrix<long double, 3 * N, 1>;
  const auto fl = cast<long double>(f);
  const auto fh = cast<HP>(f);
  const V g = friction_gradient(f, dx);
  const Eigen::Matrix<double, 3 * N, 3 * N> H = friction_hessian(f, dx);
  const long double h = 1e-7L * static_cast<long double>(f.static_slip);
  const VL dxl = dx.template cast<long double>();
  const double gscale = f.mu_lambda * std::max(1.0, f.weights.cwiseAbs().maxCoeff());
  for (int i = 0; i < 3 * N; ++i) {
    VL p = dxl, m = dxl;
    p[i] += h;
    m[i] -= h;
    const double fd = static_cast<double>((friction_energy(fl, p) - friction_energy(fl, m)) / (2 * h));
    EXPECT_NEAR(g[i], fd, 1e-7 * gscale) << "gradient " << i;
    const VL gfd = (friction_gradient(fl, p) - friction_gradient(fl, m)) / (2 * h);
    for (int j = 0; j < 3 * N; ++j)
      EXPECT_NEAR(H(j, i), static_cast<double>(gfd[j]), 1e-6 * gscale / f.static_slip) << "hessian " << j << "," << i;
  }
  // 50 digits.
  const Eigen::Matrix<HP, 3 * N, 1> dxh = dx.template cast<HP>();
  EXPECT_NEAR(friction_energy(f, dx), static_cast<double>(friction_energy(fh, dxh)),
              1e-14 * std::abs(static_cast<double>(friction_energy(fh, dxh))));
  const Eigen::Matrix<HP, 3 * N, 1> gh = friction_gradient(fh, dxh);
  for (int i = 0; i < 3 * N; ++i) EXPECT_NEAR(g[i], static_cast<double>(gh[i]), 1e-13 * gscale);
  // PSD, and the tangent block's eigenpairs by their residuals.
  if constexpr (N == 4) {
    const double smallest = pce_test::min_eigenvalue<double, 12>(H);
    EXPECT_GE(smallest, -1e-12 * H.norm());
  }
  const Mat3<double> K = friction_tangent_block(f, dx);
  const Eigen::Vector2d u = friction_slip(f, dx);
  const double y = u.norm();
  const FrictionMollifier<double> mol = friction_mollifier(y, f.static_slip);
  EXPECT_LE((K * normal).norm(), 1e-12 * K.norm());
  if (y > 0) {
    const Vec3<double> along = f.basis * (u / y), across = normal.cross(along);
    EXPECT_NEAR((K * along - f.mu_lambda * mol.df1 * along).norm(), 0.0, 1e-12 * K.norm());
    EXPECT_NEAR((K * across - f.mu_lambda * mol.f1_over_y * across).norm(), 0.0, 1e-12 * K.norm());
  }
  EXPECT_GE(mol.df1, 0.0);
}

/// A random displacement of the pair whose slip spans both regimes: static (y < ε) and
/// sliding (y > ε).
template <int N> Eigen::Matrix<double, 3 * N, 1> displacement(std::mt19937& rng, double eps, int i) {
  std::normal_distribution<double> d(0.0, 1.0);
  Eigen::Matrix<double, 3 * N, 1> dx;
  for (int k = 0; k < 3 * N; ++k) dx[k] = d(rng);
  const double scale = (i % 3 == 0 ? 0.1 : i % 3 == 1 ? 0.7 : 5.0) * eps;  // below, near and above ε
  return scale * dx / dx.norm() * std::sqrt(double(N));
}

LaggedFriction<double, 4> frozen(const VecN<double, 4>& w, const Vec3<double>& n) {
  LaggedFriction<double, 4> f;
  f.weights = w;
  f.basis = tangent_basis<double>(n);
  f.mu_lambda = 0.35;
  f.static_slip = 1e-3;
  return f;
}

}  // namespace

TEST(FrictionMollifier, ValuesAndContinuityAtEpsilon) {
  const double eps = 2e-3;
  const auto zero = friction_mollifier(0.0, eps);
  EXPECT_DOUBLE_EQ(zero.f0, eps / 3);
  EXPECT_DOUBLE_EQ(zero.f1_over_y, 2 / eps);
  EXPECT_DOUBLE_EQ(zero.df1, 2 / eps);
  const auto below = friction_mollifier(eps * (1 - 1e-12), eps), above = friction_mollifier(eps, eps);
  EXPECT_NEAR(below.f0, above.f0, 1e-14);
  EXPECT_NEAR(below.f1_over_y * eps, above.f1_over_y * eps, 1e-10);  // f₁ = 1 from both sides
  EXPECT_NEAR(below.df1 * eps, 0.0, 1e-10);                          // f₁′ = 0 from both sides
  EXPECT_EQ(above.df1, 0.0);
  // f₀′ = f₁ by central differences on both regimes.
  for (double y : {0.1 * eps, 0.5 * eps, 0.9 * eps, 1.5 * eps, 10 * eps}) {
    const double h = 1e-7 * eps;
    const double fd = (friction_mollifier(y + h, eps).f0 - friction_mollifier(y - h, eps).f0) / (2 * h);
    EXPECT_NEAR(friction_mollifier(y, eps).f1_over_y * y, fd, 1e-7) << y;
  }
}

TEST(TangentBasis, OrthonormalAndOrthogonalToTheNormal) {
  std::mt19937 rng(3);
  std::normal_distribution<double> d;
  for (int i = 0; i < 200; ++i) {
    Vec3<double> n(d(rng), d(rng), d(rng));
    if (i < 3) n = Vec3<double>::Unit(i);
    n.normalize();
    const auto T = tangent_basis<double>(n);
    EXPECT_NEAR((T.transpose() * T - Eigen::Matrix2d::Identity()).norm(), 0.0, 1e-15);
    EXPECT_NEAR((T.transpose() * n).norm(), 0.0, 1e-15);
    EXPECT_NEAR(T.col(0).cross(T.col(1)).dot(n), 1.0, 1e-15);  // (t₀, t₁, n) right-handed
  }
}

TEST(LaggedFriction, PlaneKindsDerivativesAndWeights) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int checked[2] = {0, 0};
  for (int i = 0; i < 60; ++i) {
    Vec12<double> x;
    for (int k = 0; k < 12; ++k) x[k] = u(rng);
    const bool vf = i % 2 == 0;
    Frame<double> frame;
    if ((vf ? VertexFace::frame(x, frame) : EdgeEdge::frame(x, frame)) != Status::ok) continue;
    VecN<double, 4> w;
    Vec3<double> n;
    friction_geometry(frame, w, n);
    // Σ wⱼ xⱼ = e2⊥ = l n̂: the vector between the closest points of the plane (line) distance.
    Vec3<double> d = Vec3<double>::Zero();
    for (int j = 0; j < 4; ++j) d += w[j] * x.segment<3>(3 * j);
    EXPECT_NEAR((d - frame.l * n).norm(), 0.0, 1e-12);
    EXPECT_NEAR(w.sum(), 0.0, 1e-12);  // a common translation does not slip
    const auto f = frozen(w, n);
    SCOPED_TRACE(vf ? "vertex_face" : "edge_edge");
    check<4>(f, displacement<4>(rng, f.static_slip, i / 2), n);
    ++checked[vf ? 0 : 1];
  }
  EXPECT_GE(checked[0], 25);
  EXPECT_GE(checked[1], 25);
}

TEST(LaggedFriction, ClosestFeatureKindsDerivativesAndWeights) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int seen[4] = {0, 0, 0, 0};
  const QuadraticPenalty probe{1.0, 0.0};
  for (int i = 0; i < 400; ++i) {
    Vec12<double> x;
    for (int k = 0; k < 12; ++k) x[k] = u(rng);
    if (i % 4 == 0) x.head<3>() *= 3.0;  // vertex-face: the vertex often beside the triangle
    ClosestFeatureEnergy<double> ce;
    const Status s = i % 2 == 0 ? closest_feature_energy<VertexFace>(x, UnsignedLength{}, probe, ce)
                                : closest_feature_energy<EdgeEdge>(x, UnsignedLength{}, probe, ce);
    if (s != Status::ok) continue;
    VecN<double, 4> w;
    Vec3<double> n;
    ASSERT_TRUE(friction_geometry(ce, x, w, n));
    Vec3<double> d = Vec3<double>::Zero();
    for (int j = 0; j < 4; ++j) d += w[j] * x.segment<3>(3 * j);
    EXPECT_NEAR(d.norm(), ce.length, 1e-12 * std::max(1.0, ce.length)) << int(ce.feature);
    EXPECT_NEAR(std::abs(d.dot(n)), d.norm(), 1e-12);
    EXPECT_NEAR(w.sum(), 0.0, 1e-12);
    const int kind = static_cast<int>(ce.feature);
    if (seen[kind] >= 10) continue;
    ++seen[kind];
    const auto f = frozen(w, n);
    SCOPED_TRACE(kind);
    check<4>(f, displacement<4>(rng, f.static_slip, seen[kind]), n);
  }
  for (int k = 0; k < 4; ++k) EXPECT_EQ(seen[k], 10) << "feature " << k;
}

TEST(LaggedFriction, ASingleVertexOnAMovingSurface) {
  std::mt19937 rng(5);
  for (int i = 0; i < 12; ++i) {
    const Vec3<double> n = Vec3<double>(0.3, -0.2, 1.0).normalized();
    LaggedFriction<double, 1> f;
    f.weights << 1.0;
    f.basis = tangent_basis<double>(n);
    f.offset = Vec3<double>(2e-3, -1e-3, 5e-4);  // the surface point's motion over the step
    f.mu_lambda = 0.02;
    f.static_slip = 1e-3;
    const Vec3<double> dx = f.offset + displacement<1>(rng, f.static_slip, i);
    check<1>(f, dx, n);
  }
  // Moving with the surface, along the normal or not at all relative to it: no slip, no force.
  LaggedFriction<double, 1> f;
  f.weights << 1.0;
  const Vec3<double> n(0, 0, 1);
  f.basis = tangent_basis<double>(n);
  f.offset = Vec3<double>(0.01, 0.02, 0);
  f.mu_lambda = 1;
  f.static_slip = 1e-3;
  EXPECT_EQ(friction_gradient(f, Vec3<double>(0.01, 0.02, 0.3)).norm(), 0.0);
  EXPECT_DOUBLE_EQ(friction_energy(f, Vec3<double>(0.01, 0.02, 0.3)), f.mu_lambda * f.static_slip / 3);
  // Sliding: Coulomb's force μλ, opposite the slip.
  const Vec3<double> g = friction_gradient(f, Vec3<double>(0.01 + 0.5, 0.02, 0));
  EXPECT_NEAR((g - Vec3<double>(1, 0, 0)).norm(), 0.0, 1e-15);
}

TEST(LaggedFriction, TheModelForceIsTheGradientPlusTheHessianTimesTheStep) {
  // For every kind of contact and both regimes: Σⱼ wⱼ (∇D + ∇²D · ddx)ⱼ = (Σⱼ wⱼ²) T φ, φ the
  // model's tangential force; with ddx = 0, φ is the force at u (|φ| ≤ μλ); and φ less the
  // true force after the step is second order in the step.
  std::mt19937 rng(11);
  for (int i = 0; i < 30; ++i) {
    const LaggedFriction<double, 4> f =
        frozen(VecN<double, 4>(0.3, 0.7, -0.6, -0.4), Vec3<double>(0.2, 0.1, 1).normalized());
    const VecN<double, 12> dx = displacement<4>(rng, f.static_slip, i),
                           ddx = displacement<4>(rng, f.static_slip, i + 1);
    const VecN<double, 12> model = friction_gradient(f, dx) + friction_hessian(f, dx) * ddx;
    Vec3<double> sum = Vec3<double>::Zero();
    for (int j = 0; j < 4; ++j) sum += f.weights[j] * model.segment<3>(3 * j);
    const Eigen::Vector2d phi = friction_model_force(f, dx, ddx);
    EXPECT_NEAR((sum - f.weights.squaredNorm() * (f.basis * phi)).norm(), 0.0, 1e-12 * f.mu_lambda) << i;
    EXPECT_LE(friction_model_force(f, dx, VecN<double, 12>(VecN<double, 12>::Zero())).norm(),
              f.mu_lambda * (1 + 1e-15));
    // The true force F: Σⱼ wⱼ ∇Dⱼ = (Σⱼ wⱼ²) T F, |F| ≤ μλ; the model's error over a step,
    // φ(dx, t·ddx) − F(dx + t·ddx), shrinks as t² (F is C¹ with a Lipschitz derivative: f₁′
    // is continuous at ε).
    const VecN<double, 12> g = friction_gradient(f, dx);
    Vec3<double> gsum = Vec3<double>::Zero();
    for (int j = 0; j < 4; ++j) gsum += f.weights[j] * g.segment<3>(3 * j);
    const Eigen::Vector2d F = friction_force(f, dx);
    EXPECT_NEAR((gsum - f.weights.squaredNorm() * (f.basis * F)).norm(), 0.0, 1e-12 * f.mu_lambda) << i;
    EXPECT_LE(F.norm(), f.mu_lambda * (1 + 1e-15));
    const auto error = [&](double t) {
      const VecN<double, 12> step = t * ddx;
      return (friction_model_force(f, dx, step) - friction_force(f, VecN<double, 12>(dx + step))).norm();
    };
    const double e1 = error(1e-3), e2 = error(5e-4);
    if (e1 > 1e-12 * f.mu_lambda) {
      EXPECT_LT(e2, 0.3 * e1) << i;
    }
  }
  // From rest (u = 0) the model is the static spring 2μλ/ε: a slip of ε/2 asks exactly μλ of
  // it, the most Coulomb allows; a slip of 0.9 ε asks 1.8 μλ (the true force is 0.99 μλ).
  LaggedFriction<double, 1> f;
  f.weights << 1.0;
  f.basis = tangent_basis<double>(Vec3<double>(0, 0, 1));
  f.mu_lambda = 0.5;
  f.static_slip = 2e-5;
  const Vec3<double> rest = Vec3<double>::Zero();
  for (const double s : {0.5, 0.9}) {
    const Vec3<double> step = s * f.static_slip * (f.basis * Eigen::Vector2d(0.6, 0.8));
    EXPECT_NEAR(friction_model_force(f, rest, step).norm(), 2 * s * f.mu_lambda, 1e-14);
    EXPECT_NEAR(friction_gradient(f, step).norm(), (2 * s - s * s) * f.mu_lambda, 1e-14);
  }
  // Sliding (y > ε): only the direction turns, so a step along the slip keeps |φ| = μλ.
  const Vec3<double> slid = 3 * f.static_slip * f.basis.col(0);
  EXPECT_NEAR(friction_model_force(f, slid, Vec3<double>(f.static_slip * f.basis.col(0))).norm(), f.mu_lambda, 1e-15);
}

TEST(LaggedFriction, TheMajorizerBlockBoundsTheHessianAndThePotential) {
  // μλ (f₁/y) T Tᵀ ⪰ the Hessian's tangent block, and the quadratic with it (and the
  // gradient) lies above D for a move of one vertex, in both regimes and across y = 0.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  int crossed = 0;
  for (int i = 0; i < 60; ++i) {
    const LaggedFriction<double, 4> f =
        frozen(VecN<double, 4>(0.3, 0.7, -0.6, -0.4), Vec3<double>(0.2, 0.1, 1).normalized());
    const VecN<double, 12> dx = displacement<4>(rng, f.static_slip, i);
    const Mat3<double> K = friction_majorizer_block(f, dx), T = friction_tangent_block(f, dx);
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat3<double>>(K - T).eigenvalues().minCoeff(), -1e-12 * K.norm()) << i;
    const int j = i % 4;
    const double w = f.weights[j];
    const VecN<double, 12> g = friction_gradient(f, dx);
    for (int t = 0; t < 20; ++t) {
      const Vec3<double> step = (0.2 + 3 * std::abs(u(rng))) * f.static_slip * Vec3<double>(u(rng), u(rng), u(rng));
      VecN<double, 12> moved = dx;
      moved.segment<3>(3 * j) += step;
      const double bound = friction_energy(f, dx) + g.segment<3>(3 * j).dot(step) + 0.5 * w * w * step.dot(K * step);
      EXPECT_LE(friction_energy(f, moved), bound + 1e-12 * f.mu_lambda * f.static_slip) << i << " " << t;
      crossed += friction_slip(f, moved).dot(friction_slip(f, dx)) < 0;
    }
  }
  EXPECT_GT(crossed, 10);  // moves that reverse the slip were among them
}
