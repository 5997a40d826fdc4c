// SPDX-License-Identifier: MIT
// Strand bending at each joint x1 of two consecutive segments e1 = x1 − x0, e2 = x2 − x1:
//   E = k (φ − φ₀)²/ℓ̄,   φ = atan2(|e1 × e2|, e1·e2) ∈ [0, π]  (the turning angle),
// φ₀ its rest value and ℓ̄ = (L1 + L2)/2 the mean rest length (the discrete curvature φ/ℓ̄
// integrated over the Voronoi length ℓ̄, as in Bergou et al. 2008, "Discrete elastic rods",
// with the angle in place of 2 tan(φ/2)). With t_i = e_i/|e_i| and b̂ the unit binormal
// (t1 × t2)/|t1 × t2|:   ∂φ/∂e1 = −(b̂ × t1)/|e1|,   ∂φ/∂e2 = (b̂ × t2)/|e2|.
// When the strand is straight or folded back (|t1 × t2| ≈ 0) the binormal is not defined
// and any unit vector ⟂ t1 is used: ∇φ stays bounded (norm 1/|e|), so gradient and Hessian
// stay finite; with φ₀ = 0 the gradient 2k/ℓ̄ φ ∇φ → 0 continuously.
// Hessian: 2k/ℓ̄ [∇φ∇φᵀ + (φ − φ₀) ∇²φ|_out-of-plane, projected]. Out of the bending plane
// (displacements wᵢ b̂, tilts a1 = (w1 − w0)/|e1|, a2 = (w2 − w1)/|e2|) φ is even and
//   δφ = [cos φ (a1² + a2²) − 2 a1 a2]/(2 sin φ),
// with eigenvalues cot(φ/2) for (a1 − a2)/√2 and −tan(φ/2) for (a1 + a2)/√2; each is kept
// when (φ − φ₀) times it is positive. This term is what keeps a straight strand stiff in
// both bending directions (φ cot(φ/2) → 2 as φ → 0: the Hessian of k φ²/ℓ̄ is isotropic
// there). The in-plane part of (φ − φ₀)∇²φ is dropped; it vanishes at the rest angle.
#include "arguments.hpp"
#include "local_terms.hpp"

#include <pce/core/orthogonal.hpp>
#include <pce/core/types.hpp>
#include <pce/sim/effects.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

using Vector9 = Eigen::Matrix<double, 9, 1>;
using Matrix9 = Eigen::Matrix<double, 9, 9>;

struct Joint {
  std::array<int, 3> v;  ///< x0, x1 (the shared vertex), x2
  double phi0;           ///< rest turning angle
  double weight;         ///< k/ℓ̄
};

/// The turning angle φ ∈ [0, π] of e1 = x1 − x0, e2 = x2 − x1.
inline double turning_angle(const Eigen::Vector3d& e1, const Eigen::Vector3d& e2) {
  return std::atan2(e1.cross(e2).norm(), e1.dot(e2));
}

/// One joint: returns E = w (φ − φ₀)², sets `g` = ∇E = 2w(φ − φ₀)∇φ (vertex order of
/// Joint::v) and `H` to the projected Hessian (file comment) when non-null. Sets `collapsed`
/// when a segment has zero length, where ∇φ does not exist: no force then (`g`, `H`
/// untouched).
PCE_ALWAYS_INLINE double joint_terms(const Joint& j, const Eigen::Matrix3Xd& x, Vector9* g, Matrix9* H,
                                     bool& collapsed) {
  constexpr double pi = 3.14159265358979323846;
  const Eigen::Vector3d e1 = x.col(j.v[1]) - x.col(j.v[0]), e2 = x.col(j.v[2]) - x.col(j.v[1]);
  const double l1 = e1.norm(), l2 = e2.norm();
  const double phi = turning_angle(e1, e2), d = phi - j.phi0;
  const double energy = j.weight * d * d;
  collapsed = !(l1 > 0 && l2 > 0);
  if (collapsed || (!g && !H)) return energy;
  const Eigen::Vector3d t1 = e1 / l1, t2 = e2 / l2;
  const Eigen::Vector3d b = t1.cross(t2);
  const double s = b.norm();
  const Eigen::Vector3d bh = s > 1e-10 ? Eigen::Vector3d(b / s) : pce::any_orthogonal<double>(t1);
  const Eigen::Vector3d d1 = -bh.cross(t1) / l1, d2 = bh.cross(t2) / l2;  // ∂φ/∂e1, ∂φ/∂e2
  Vector9 gphi;
  gphi << -d1, d1 - d2, d2;
  if (g) *g = (2 * j.weight * d) * gphi;
  if (H) {
    H->noalias() = gphi * gphi.transpose();
    // Out-of-plane curvature of φ, kept where (φ − φ₀) times its eigenvalue is > 0.
    const double c_minus = phi > 0 ? d / std::tan(0.5 * phi) : (j.phi0 == 0 ? 2.0 : 0.0);
    const double c_plus = d < 0 && phi < pi ? -d * std::tan(0.5 * phi) : 0.0;
    const double r1 = 1 / l1, r2 = 1 / l2;
    if (c_minus > 0) {
      Vector9 q;
      q << -r1 * bh, (r1 + r2) * bh, -r2 * bh;
      H->noalias() += (0.5 * c_minus) * q * q.transpose();
    }
    if (c_plus > 0) {
      Vector9 q;
      q << -r1 * bh, (r1 - r2) * bh, r2 * bh;
      H->noalias() += (0.5 * c_plus) * q * q.transpose();
    }
    *H *= 2 * j.weight;
  }
  return energy;
}

class StrandBending final : public Effect {
 public:
  StrandBending(int vertex_count, std::vector<Joint> joints) : Effect("strand_bending"), joints_(std::move(joints)) {
    incidence_.build(vertex_count, joints_.size(), [this](std::size_t e) { return joints_[e].v; });
  }
  void declare(Pattern& pattern) const override {
    for (const Joint& j : joints_) pattern.add(j.v);
  }
  /// E = Σ_joints k (φ − φ₀)²/ℓ̄, ∇E = 2k/ℓ̄ (φ − φ₀)∇φ, Hessian as in the file comment.
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    double energy = 0;
    degenerate_ = 0;
    Vector9 g;
    Matrix9 H;
    for (const Joint& j : joints_) {
      bool collapsed;
      energy += joint_terms(j, x, gradient ? &g : nullptr, hessian ? &H : nullptr, collapsed);
      if (collapsed) {  // a collapsed segment has no direction: no force, counted
        ++degenerate_;
        continue;
      }
      if (gradient)
        for (int a = 0; a < 3; ++a) gradient->col(j.v[a]) += g.segment<3>(3 * a);
      if (hessian) hessian->add<3>(j.v, H);
    }
    return energy;
  }
  /// Per listed vertex, the sum over its joints of the joint's gradient and Hessian block at
  /// it (joint_terms, as `evaluate`); a collapsed joint adds nothing. The statistics'
  /// degenerate joints are those of the last `evaluate`.
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    add_local_terms(incidence_, vertices, terms, [&](const Incident& u, Eigen::Vector3d& ga, Eigen::Matrix3d& B) {
      Vector9 g;
      Matrix9 H;
      bool collapsed;
      joint_terms(joints_[static_cast<std::size_t>(u.item)], x, &g, &H, collapsed);
      if (collapsed) return true;
      ga += g.segment<3>(3 * u.slot);
      B += H.block<3, 3>(3 * u.slot, 3 * u.slot);
      return true;
    });
  }
  void report(EffectCounters& counters) const override {
    counters[Counter::joints] = static_cast<double>(joints_.size());
    counters[Counter::degenerate_joints] = static_cast<double>(degenerate_);
  }

 private:
  std::vector<Joint> joints_;
  VertexIncidence incidence_;  ///< per vertex, its joints
  long degenerate_ = 0;
};

}  // namespace

std::unique_ptr<Effect> make_strand_bending(const Model& model, double stiffness) {
  const double k = args::stiffness("stiffness", stiffness);
  const Eigen::Matrix2Xi& S = model.segments;
  // A joint at every vertex shared by exactly two segments (strand ends and branch points
  // carry none).
  const int n = model.vertex_count();
  std::vector<int> degree(static_cast<std::size_t>(n), 0);
  std::vector<std::array<int, 2>> other(static_cast<std::size_t>(n), {-1, -1});  // the far ends
  for (Eigen::Index j = 0; j < S.cols(); ++j)
    for (int end = 0; end < 2; ++end) {
      const auto v = static_cast<std::size_t>(S(end, j));
      if (degree[v] < 2) other[v][static_cast<std::size_t>(degree[v])] = S(1 - end, j);
      ++degree[v];
    }
  std::vector<Joint> joints;
  for (int v = 0; v < n; ++v) {
    if (degree[static_cast<std::size_t>(v)] != 2) continue;
    Joint jt;
    jt.v = {other[static_cast<std::size_t>(v)][0], v, other[static_cast<std::size_t>(v)][1]};
    const Eigen::Vector3d e1 = model.rest.col(v) - model.rest.col(jt.v[0]);
    const Eigen::Vector3d e2 = model.rest.col(jt.v[2]) - model.rest.col(v);
    const double mean = 0.5 * (e1.norm() + e2.norm());
    if (!(e1.norm() > 0 && e2.norm() > 0))
      throw ArgumentError(
          "", "a segment at vertex " + std::to_string(v) + " has zero rest length (strand bending needs a rest shape)");
    jt.phi0 = turning_angle(e1, e2);
    jt.weight = k / mean;
    joints.push_back(jt);
  }
  return std::make_unique<StrandBending>(model.vertex_count(), std::move(joints));
}

}  // namespace pce::sim
