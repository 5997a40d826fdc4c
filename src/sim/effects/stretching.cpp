// SPDX-License-Identifier: MIT
// Cloth membrane stretching, as-rigid-as-possible (ARAP) per triangle:
//   E = μ A ‖F − R‖²_F,   F = [x1 − x0, x2 − x0] D_m⁻¹ (3×2),   R = U Vᵀ (F = U Σ Vᵀ thin SVD),
// so E = μ A Σᵢ (σᵢ − 1)². The gradient ∂E/∂F = 2μA (F − R) follows from the envelope
// theorem (R minimises ‖F − R‖ over 3×2 matrices with orthonormal columns). The Hessian in
// F-space, 2μA (I − ∂R/∂F), is diagonal in an orthonormal basis of 3×2 matrices (the
// 2D analysis of Smith, de Goes & Kim 2019, "Analytic eigensystems for isotropic
// distortion energies", extended here to the out-of-plane directions of a 3×2 F):
//   U S Vᵀ, S symmetric (3 modes)       eigenvalue 1       (R does not change)
//   U [[0,−1],[1,0]] Vᵀ/√2 (twist)      1 − 2/(σ₁ + σ₂)
//   u₃ vᵢᵀ (u₃ the unit normal)         1 − 1/σᵢ          (R's column i tilts by 1/σᵢ)
// The projection clamps the three last eigenvalues at 0; the result maps to x-space with
// the constant dF/dx (F = X D, X = [x0 x1 x2], D the 3×2 matrix below).
#include "arguments.hpp"

#include <pce/core/orthogonal.hpp>
#include <pce/sim/effects.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

using Matrix32 = Eigen::Matrix<double, 3, 2>;
using Matrix9 = Eigen::Matrix<double, 9, 9>;
using Vector9 = Eigen::Matrix<double, 9, 1>;

struct RestTriangle {
  Matrix32 D;     ///< F = X D: row a holds ∂F(:, j)/∂x_a (rows 1, 2 are D_m⁻¹, row 0 their negated sum)
  double weight;  ///< μ A (rest area)
  std::array<int, 3> v;
};

/// The 9-vector vec(Q Dᵀ) (vertex-major), i.e. the x-space image (dF/dx)ᵀ vec(Q) of a 3×2 Q.
inline Vector9 pull_back(const Matrix32& Q, const Matrix32& D) {
  Vector9 g;
  for (int a = 0; a < 3; ++a) g.segment<3>(3 * a) = Q * D.row(a).transpose();
  return g;
}

/// One triangle: returns E = w Σ(σᵢ − 1)², adds ∂E/∂X (3×3, column a = vertex a) to `G`
/// and the projected Hessian to `H` when non-null. Degenerate F (σ₂ ≈ 0, even F = 0) uses
/// any orthonormal completion of the polar factor: finite, never NaN.
inline double arap_triangle(const Eigen::Matrix3d& X, const Matrix32& D, double w, Eigen::Matrix3d* G, Matrix9* H) {
  const Matrix32 F = X * D;
  // V and σ₁ from the 2×2 FᵀF = [[a, b], [b, c]]; σ₂ = |F₀ × F₁|/σ₁ avoids the cancellation
  // of √λ₂ for thin triangles.
  const double a = F.col(0).squaredNorm(), b = F.col(0).dot(F.col(1)), c = F.col(1).squaredNorm();
  // v₁ = (cos ϑ, sin ϑ) with tan 2ϑ = 2b/(a − c), by half-angle formulas (no trigonometry),
  // taking the larger of cos ϑ, sin ϑ from its square root to avoid cancellation.
  const double p = 0.5 * (a - c), r = std::sqrt(p * p + b * b);
  Eigen::Vector2d v1(1.0, 0.0);
  if (r > 0) {
    if (p >= 0) {
      v1[0] = std::sqrt(0.5 * (r + p) / r);
      v1[1] = b / (2 * r * v1[0]);
    } else {
      v1[1] = std::sqrt(0.5 * (r - p) / r);
      v1[0] = b / (2 * r * v1[1]);
    }
  }
  const Eigen::Vector2d v2(-v1[1], v1[0]);
  const double s1 = std::sqrt(0.5 * (a + c) + r);
  const Eigen::Vector3d n = F.col(0).cross(F.col(1));
  const double area2 = n.norm();
  const double s2 = s1 > 0 ? area2 / s1 : 0.0;
  const Eigen::Vector3d Fv1 = F * v1;
  const double fv1 = Fv1.norm();
  const Eigen::Vector3d u1 = fv1 > 0 ? Eigen::Vector3d(Fv1 / fv1) : Eigen::Vector3d::UnitX();
  Eigen::Vector3d u3;
  if (s2 > 1e-10 * s1) {
    u3 = n - n.dot(u1) * u1;  // exact orthogonality to u1
    u3.normalize();
  } else {
    u3 = pce::any_orthogonal<double>(u1);  // σ₂ ≈ 0: any completion is a closest orthonormal frame
  }
  const Eigen::Vector3d u2 = u3.cross(u1);  // F v₂ lies along u₃ × u₁ (σ₂ ≥ 0)
  const Matrix32 R = u1 * v1.transpose() + u2 * v2.transpose();
  const double energy = w * ((s1 - 1) * (s1 - 1) + (s2 - 1) * (s2 - 1));
  if (G) G->noalias() += (2 * w) * (F - R) * D.transpose();
  if (H) {
    // 2w [ (D Dᵀ ⊗ I₃) − Σₖ (1 − λₖ⁺) gₖ gₖᵀ ] over the twist and the two out-of-plane modes.
    const Eigen::Matrix3d DD = D * D.transpose();
    H->setZero();
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) H->block<3, 3>(3 * p, 3 * q).diagonal().setConstant(DD(p, q));
    const double sum = s1 + s2;
    const double c_twist = sum > 2 ? 2 / sum : 1.0;  // 1 − max(0, 1 − 2/(σ₁+σ₂))
    const double c_out1 = s1 > 1 ? 1 / s1 : 1.0;
    const double c_out2 = s2 > 1 ? 1 / s2 : 1.0;
    const Vector9 g_twist = pull_back((u2 * v1.transpose() - u1 * v2.transpose()) * std::sqrt(0.5), D);
    const Vector9 g_out1 = pull_back(u3 * v1.transpose(), D);
    const Vector9 g_out2 = pull_back(u3 * v2.transpose(), D);
    H->noalias() -= c_twist * g_twist * g_twist.transpose();
    H->noalias() -= c_out1 * g_out1 * g_out1.transpose();
    H->noalias() -= c_out2 * g_out2 * g_out2.transpose();
    *H *= 2 * w;
  }
  return energy;
}

class Stretching final : public Effect {
 public:
  explicit Stretching(std::vector<RestTriangle> triangles) : Effect("stretching"), triangles_(std::move(triangles)) {}
  void declare(Pattern& pattern) const override {
    for (const RestTriangle& t : triangles_) pattern.add(t.v);
  }
  /// E = Σ_t μ A_t ‖F_t − R_t‖²_F with the closed-form projected Hessian (file comment).
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    double energy = 0;
    Matrix9 H;
    for (const RestTriangle& t : triangles_) {
      Eigen::Matrix3d X;
      for (int a = 0; a < 3; ++a) X.col(a) = x.col(t.v[a]);
      Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
      energy += arap_triangle(X, t.D, t.weight, gradient ? &G : nullptr, hessian ? &H : nullptr);
      if (gradient)
        for (int a = 0; a < 3; ++a) gradient->col(t.v[a]) += G.col(a);
      if (hessian) hessian->add<3>(t.v, H);
    }
    return energy;
  }

 private:
  std::vector<RestTriangle> triangles_;
};

}  // namespace

std::unique_ptr<Effect> make_stretching(const Model& model, double stiffness) {
  const double mu = args::stiffness("stiffness", stiffness);
  std::vector<RestTriangle> triangles;
  triangles.reserve(static_cast<std::size_t>(model.triangles.cols()));
  for (Eigen::Index k = 0; k < model.triangles.cols(); ++k) {
    if (model.is_boundary_triangle(k)) continue;  // a volume's surface: its elasticity is the volume's
    RestTriangle t;
    for (int a = 0; a < 3; ++a) t.v[static_cast<std::size_t>(a)] = model.triangles(a, k);
    // D_m: the rest edges in the triangle's own orthonormal 2D frame (t₁ along edge 1).
    const Eigen::Vector3d e1 = model.rest.col(t.v[1]) - model.rest.col(t.v[0]);
    const Eigen::Vector3d e2 = model.rest.col(t.v[2]) - model.rest.col(t.v[0]);
    const Eigen::Vector3d normal = e1.cross(e2);
    const double l1 = e1.norm(), area2 = normal.norm();
    if (!(area2 > 1e-12 * l1 * e2.norm()))
      throw ArgumentError("", "triangle " + std::to_string(k) + " has zero rest area (stretching needs a rest shape)");
    const Eigen::Vector3d t1 = e1 / l1, t2 = (normal / area2).cross(t1);
    Eigen::Matrix2d Dm;
    Dm << l1, e2.dot(t1), 0.0, e2.dot(t2);
    const Eigen::Matrix2d Dinv = Dm.inverse();
    t.D.row(1) = Dinv.row(0);
    t.D.row(2) = Dinv.row(1);
    t.D.row(0) = -(Dinv.row(0) + Dinv.row(1));
    t.weight = mu * 0.5 * area2;
    triangles.push_back(t);
  }
  return std::make_unique<Stretching>(std::move(triangles));
}

}  // namespace pce::sim
