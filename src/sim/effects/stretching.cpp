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
#include "local_terms.hpp"

#include <pce/core/orthogonal.hpp>
#include <pce/sim/effects.hpp>

#include <algorithm>
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

/// The thin SVD of F = X D (3×2), F = σ₁ u₁v₁ᵀ + σ₂ u₂v₂ᵀ, with u₃ the unit normal, and its
/// polar factor R = u₁v₁ᵀ + u₂v₂ᵀ: what the energy, the gradient and the Hessian share.
/// Degenerate F (σ₂ ≈ 0, even F = 0) uses any orthonormal completion of the polar factor:
/// finite, never NaN.
struct ArapFrame {
  Matrix32 F, R;
  double s1, s2;
  Eigen::Vector3d u1, u2, u3;
  Eigen::Vector2d v1, v2;
};

/// F's polar factor R = F (√S)⁻¹ in closed form, S = FᵀF = [[A, b], [b, C]], s = √det S =
/// σ₁σ₂ = |F₀ × F₁|, t = σ₁ + σ₂: √S = (S + s I)/t, so R = F adj(S + s I)/(s t). For a
/// well-shaped F only (`well_shaped`), where adj(S + s I)'s cancellation costs no digits.
inline Matrix32 closed_form_polar(const Matrix32& F, double A, double b, double C, double s, double t) {
  Eigen::Matrix2d adj;
  adj << C + s, -b, -b, A + s;
  return (1 / (s * t)) * (F * adj);
}

/// Whether F is well shaped for `closed_form_polar`: s > 10⁻² (A + C), i.e. σ₂ above about
/// 10⁻² σ₁.
inline bool well_shaped(double A, double C, double s) { return s > 1e-2 * (A + C); }

/// The frame of F = X D (its R by `closed_form_polar` where F is well shaped, the same R
/// `arap_vertex` uses).
inline ArapFrame arap_frame(const Eigen::Matrix3d& X, const Matrix32& D) {
  ArapFrame f;
  f.F = X * D;
  const Matrix32& F = f.F;
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
  f.v1 = v1;
  f.v2 = Eigen::Vector2d(-v1[1], v1[0]);
  f.s1 = std::sqrt(0.5 * (a + c) + r);
  const Eigen::Vector3d n = F.col(0).cross(F.col(1));
  const double area2 = n.norm();
  f.s2 = f.s1 > 0 ? area2 / f.s1 : 0.0;
  const Eigen::Vector3d Fv1 = F * v1;
  const double fv1 = Fv1.norm();
  f.u1 = fv1 > 0 ? Eigen::Vector3d(Fv1 / fv1) : Eigen::Vector3d::UnitX();
  if (f.s2 > 1e-10 * f.s1) {
    f.u3 = n - n.dot(f.u1) * f.u1;  // exact orthogonality to u1
    f.u3.normalize();
  } else {
    f.u3 = pce::any_orthogonal<double>(f.u1);  // σ₂ ≈ 0: any completion is a closest orthonormal frame
  }
  f.u2 = f.u3.cross(f.u1);  // F v₂ lies along u₃ × u₁ (σ₂ ≥ 0)
  if (well_shaped(a, c, area2))
    f.R = closed_form_polar(F, a, b, c, area2, f.s1 + f.s2);
  else
    f.R = f.u1 * f.v1.transpose() + f.u2 * f.v2.transpose();
  return f;
}

/// The three F-space modes the projection changes (twist, two out of plane; unit 3×2
/// directions Q_k) and c_k = 1 − λ_k⁺, the part of the identity each removes: the
/// projected Hessian is 2w [(D Dᵀ ⊗ I₃) − Σₖ c_k g_k g_kᵀ] with g_k = pull_back(Q_k, D).
struct ArapModes {
  std::array<Matrix32, 3> Q;
  std::array<double, 3> c;
};

/// The modes at frame `f`.
inline ArapModes arap_modes(const ArapFrame& f) {
  ArapModes m;
  const double sum = f.s1 + f.s2;
  m.Q[0] = (f.u2 * f.v1.transpose() - f.u1 * f.v2.transpose()) * std::sqrt(0.5);
  m.c[0] = sum > 2 ? 2 / sum : 1.0;  // 1 − max(0, 1 − 2/(σ₁+σ₂))
  m.Q[1] = f.u3 * f.v1.transpose();
  m.c[1] = f.s1 > 1 ? 1 / f.s1 : 1.0;
  m.Q[2] = f.u3 * f.v2.transpose();
  m.c[2] = f.s2 > 1 ? 1 / f.s2 : 1.0;
  return m;
}

/// w Σ(σᵢ − 1)².
inline double arap_energy(const ArapFrame& f, double w) {
  return w * ((f.s1 - 1) * (f.s1 - 1) + (f.s2 - 1) * (f.s2 - 1));
}

/// One triangle: returns E = w Σ(σᵢ − 1)², adds ∂E/∂X = 2w (F − R) Dᵀ (3×3, column a =
/// vertex a) to `G` and sets `H` to the projected Hessian when non-null.
inline double arap_triangle(const Eigen::Matrix3d& X, const Matrix32& D, double w, Eigen::Matrix3d* G, Matrix9* H) {
  const ArapFrame f = arap_frame(X, D);
  if (G) G->noalias() += (2 * w) * (f.F - f.R) * D.transpose();
  if (H) {
    // 2w [ (D Dᵀ ⊗ I₃) − Σₖ c_k gₖ gₖᵀ ] over the twist and the two out-of-plane modes.
    const Eigen::Matrix3d DD = D * D.transpose();
    H->setZero();
    for (int p = 0; p < 3; ++p)
      for (int q = 0; q < 3; ++q) H->block<3, 3>(3 * p, 3 * q).diagonal().setConstant(DD(p, q));
    const ArapModes m = arap_modes(f);
    const Vector9 g0 = pull_back(m.Q[0], D), g1 = pull_back(m.Q[1], D), g2 = pull_back(m.Q[2], D);
    H->noalias() -= m.c[0] * g0 * g0.transpose();
    H->noalias() -= m.c[1] * g1 * g1.transpose();
    H->noalias() -= m.c[2] * g2 * g2.transpose();
    *H *= 2 * w;
  }
  return arap_energy(f, w);
}

/// One triangle's terms at its vertex `a` alone: adds column a of ∂E/∂X, 2w (F − R) dₐ (dₐ
/// = D.row(a)ᵀ), to `g` and the block (a, a) of arap_triangle's projected Hessian,
/// 2w [|dₐ|² I − Σₖ c_k (Q_k dₐ)(Q_k dₐ)ᵀ] (slot a of g_k is Q_k dₐ), to `B`.
///
/// Block descent calls it once per triangle and vertex in every sweep, so a well-shaped F
/// takes a closed form without the SVD's vectors: R by `closed_form_polar` (as arap_frame),
/// the twist's Q₀dₐ = R J dₐ/√2 (J the quarter turn: R J = u₂v₁ᵀ − u₁v₂ᵀ), and the
/// out-of-plane pair's sum u₃u₃ᵀ (c₁(v₁·dₐ)² + c₂(v₂·dₐ)²), u₃ = (F₀ × F₁)/s, with the bracket
/// dₐᵀ(√S)⁻¹dₐ when both σ > 1, |dₐ|² when neither, and |dₐ|² − (1 − 1/σ₁)(v₁·dₐ)² between,
/// (v₁·dₐ)² = dₐᵀ(S − σ₂² I)dₐ/(σ₁² − σ₂²). Other triangles use the frame and its modes.
inline void arap_vertex(const Eigen::Matrix3d& X, const Matrix32& D, double w, int a, Eigen::Vector3d& g,
                        Eigen::Matrix3d& B) {
  const Eigen::Vector2d d = D.row(a).transpose();
  const Matrix32 F = X * D;
  const double A = F.col(0).squaredNorm(), b = F.col(0).dot(F.col(1)), C = F.col(1).squaredNorm();
  const Eigen::Vector3d n = F.col(0).cross(F.col(1));
  const double s = n.norm();
  if (!well_shaped(A, C, s)) {
    const ArapFrame f = arap_frame(X, D);
    g.noalias() += (2 * w) * ((f.F - f.R) * d);
    const ArapModes m = arap_modes(f);
    Eigen::Matrix3d Ba = d.squaredNorm() * Eigen::Matrix3d::Identity();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d q = m.Q[static_cast<std::size_t>(k)] * d;
      Ba.noalias() -= m.c[static_cast<std::size_t>(k)] * q * q.transpose();
    }
    B += (2 * w) * Ba;
    return;
  }
  // σ₁ and σ₂ as arap_frame has them (no cancellation); σ₁² − σ₂² = 2r.
  const double p = 0.5 * (A - C), r = std::sqrt(p * p + b * b);
  const double s1 = std::sqrt(0.5 * (A + C) + r), s2 = s / s1, sum = s1 + s2;
  const Matrix32 R = closed_form_polar(F, A, b, C, s, sum);
  g.noalias() += (2 * w) * ((F - R) * d);
  const Eigen::Vector3d q0 = std::sqrt(0.5) * (R * Eigen::Vector2d(-d[1], d[0]));
  const double c0 = sum > 2 ? 2 / sum : 1.0;
  const double dd = d.squaredNorm();
  double kappa = dd;  // neither σ above 1
  if (s2 > 1) {
    // dₐᵀ(√S)⁻¹dₐ = dₐᵀ adj(S + s I) dₐ/(s t)
    kappa = ((C + s) * d[0] * d[0] - 2 * b * d[0] * d[1] + (A + s) * d[1] * d[1]) / (s * sum);
  } else if (s1 > 1) {
    // (v₁·dₐ)² = [(r + p) d₀² + 2b d₀d₁ + (r − p) d₁²]/(2r), the smaller of r ± p as b²/(r + |p|)
    const double big = r + std::abs(p), small = big > 0 ? b * b / big : 0.0;
    const double rp = p >= 0 ? big : small, rm = p >= 0 ? small : big;
    const double v1d2 =
        r > 0 ? std::clamp((rp * d[0] * d[0] + 2 * b * d[0] * d[1] + rm * d[1] * d[1]) / (2 * r), 0.0, dd) : 0.5 * dd;
    kappa = dd - (1 - 1 / s1) * v1d2;
  }
  const Eigen::Vector3d u3 = n / s;
  Eigen::Matrix3d Ba = dd * Eigen::Matrix3d::Identity();
  Ba.noalias() -= c0 * q0 * q0.transpose();
  Ba.noalias() -= kappa * u3 * u3.transpose();
  B += (2 * w) * Ba;
}

class Stretching final : public Effect {
 public:
  Stretching(int vertex_count, std::vector<RestTriangle> triangles)
      : Effect("stretching"), triangles_(std::move(triangles)) {
    incidence_.build(vertex_count, triangles_.size(), [this](std::size_t e) { return triangles_[e].v; });
  }
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
  /// Per listed vertex, the sum over its triangles of their gradient column and diagonal
  /// Hessian block at it (arap_vertex, the same frame and modes as `evaluate`).
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    add_local_terms(incidence_, vertices, terms, [&](const Incident& u, Eigen::Vector3d& g, Eigen::Matrix3d& B) {
      const RestTriangle& t = triangles_[static_cast<std::size_t>(u.item)];
      Eigen::Matrix3d X;
      for (int a = 0; a < 3; ++a) X.col(a) = x.col(t.v[a]);
      arap_vertex(X, t.D, t.weight, u.slot, g, B);
      return true;
    });
  }

 private:
  std::vector<RestTriangle> triangles_;
  VertexIncidence incidence_;  ///< per vertex, its triangles
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
  return std::make_unique<Stretching>(model.vertex_count(), std::move(triangles));
}

}  // namespace pce::sim
