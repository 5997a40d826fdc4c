// SPDX-License-Identifier: MIT
// Strand stretching, a spring per segment: E = ½ k (|e| − L)²/L (e = x1 − x0, L the rest
// length, k in newtons: the force is k times the strain). With n = e/|e|:
//   ∇_{x1}E = k (|e| − L)/L · n = −∇_{x0}E,
//   ∇²_{x1x1}E = (k/L) [n nᵀ + (1 − L/|e|)(I − n nᵀ)],
// whose eigenvalues are k/L (along n) and (k/L)(1 − L/|e|) twice; the projection clamps the
// latter at 0 (exact PSD projection of the 6×6 [[H, −H], [−H, H]]).
#include "arguments.hpp"
#include "local_terms.hpp"

#include <pce/sim/effects.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

struct Spring {
  std::array<int, 2> v;
  double length;                   ///< rest length L
  Eigen::Vector3d rest_direction;  ///< n at rest, the fallback when |e| = 0
};

/// One spring: returns ½ k (|e| − L)²/L, sets `f` = ∇_{x1}E = −∇_{x0}E and `B` = ∇²_{x1x1}E
/// projected (the 6×6 Hessian is [[B, −B], [−B, B]]) when non-null.
inline double spring_terms(const Spring& s, const Eigen::Matrix3Xd& x, double k, Eigen::Vector3d* f,
                           Eigen::Matrix3d* B) {
  const Eigen::Vector3d e = x.col(s.v[1]) - x.col(s.v[0]);
  const double l = e.norm(), L = s.length, kl = k / L;
  const Eigen::Vector3d n = l > 1e-12 * L ? Eigen::Vector3d(e / l) : s.rest_direction;
  if (f) *f = kl * (l - L) * n;
  if (B) {
    const double transverse = l > L ? 1 - L / l : 0.0;
    const Eigen::Matrix3d nn = n * n.transpose();
    *B = kl * (nn + transverse * (Eigen::Matrix3d::Identity() - nn));
  }
  return 0.5 * kl * (l - L) * (l - L);
}

class StrandStretching final : public Effect {
 public:
  StrandStretching(int vertex_count, std::vector<Spring> springs, double k)
      : Effect("strand_stretching"), springs_(std::move(springs)), k_(k) {
    incidence_.build(vertex_count, springs_.size(), [this](std::size_t e) { return springs_[e].v; });
  }
  void declare(Pattern& pattern) const override {
    for (const Spring& s : springs_) pattern.add(s.v);
  }
  /// E = Σ ½ k (|e| − L)²/L with the exactly projected Hessian (file comment).
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    double energy = 0;
    Eigen::Vector3d f;
    Eigen::Matrix3d B;
    for (const Spring& s : springs_) {
      energy += spring_terms(s, x, k_, gradient ? &f : nullptr, hessian ? &B : nullptr);
      if (gradient) {
        gradient->col(s.v[1]) += f;
        gradient->col(s.v[0]) -= f;
      }
      if (hessian) {
        Eigen::Matrix<double, 6, 6> H;
        H << B, -B, -B, B;
        hessian->add<2>(s.v, H);
      }
    }
    return energy;
  }
  /// Per listed vertex, the sum over its springs of ∓f (x0: −f, x1: +f) and B.
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    add_local_terms(incidence_, vertices, terms, [&](const Incident& u, Eigen::Vector3d& g, Eigen::Matrix3d& B) {
      Eigen::Vector3d f;
      Eigen::Matrix3d Bs;
      spring_terms(springs_[static_cast<std::size_t>(u.item)], x, k_, &f, &Bs);
      if (u.slot == 1)
        g += f;
      else
        g -= f;
      B += Bs;
      return true;
    });
  }

 private:
  std::vector<Spring> springs_;
  double k_;
  VertexIncidence incidence_;  ///< per vertex, its springs
};

}  // namespace

std::unique_ptr<Effect> make_strand_stretching(const Model& model, double stiffness) {
  const double k = args::stiffness("stiffness", stiffness);
  std::vector<Spring> springs;
  springs.reserve(static_cast<std::size_t>(model.segments.cols()));
  for (Eigen::Index j = 0; j < model.segments.cols(); ++j) {
    Spring s;
    s.v = {model.segments(0, j), model.segments(1, j)};
    const Eigen::Vector3d e = model.rest.col(s.v[1]) - model.rest.col(s.v[0]);
    s.length = e.norm();
    if (!(s.length > 0))
      throw ArgumentError(
          "", "segment " + std::to_string(j) + " has zero rest length (strand stretching needs a rest shape)");
    s.rest_direction = e / s.length;
    springs.push_back(s);
  }
  return std::make_unique<StrandStretching>(model.vertex_count(), std::move(springs), k);
}

}  // namespace pce::sim
