// SPDX-License-Identifier: MIT
// Cloth bending on the interior edges (hinges), discrete shells (Grinspun, Hirani, Desbrun &
// Schröder 2003, "Discrete shells", eq. 1 with the 3|ē|²/(Ā₁+Ā₂) weight):
//   E = k (θ − θ₀)² · 3|ē|²/(Ā₁ + Ā₂),
// θ the signed dihedral angle of the hinge (x0, x1) with wings x2 (triangle A) and x3
// (triangle B), θ₀ its rest value, ē, Ā rest quantities. With e = x1 − x0,
// n_A = e × (x2 − x0), n_B = (x3 − x0) × e (equal directions when flat, whatever the
// triangles' winding) and θ = atan2((n_A × n_B)·ê, n_A·n_B):
//   ∂θ/∂x2 = −|e| n_A/|n_A|²,  ∂θ/∂x3 = −|e| n_B/|n_B|²        (a wing turns about the edge
//   ∂θ/∂x0 = −(1 − s_A) ∂θ/∂x2 − (1 − s_B) ∂θ/∂x3               by its displacement over its
//   ∂θ/∂x1 = −s_A ∂θ/∂x2 − s_B ∂θ/∂x3                            height; the edge vertices
// with s_{A,B} = (x_{2,3} − x0)·e/|e|² (the wings' feet on the edge); the edge vertices'
// terms follow from invariance under translations and rotations (the same form as Bridson,
// Marino & Fedkiw 2003, "Simulation of clothing with folds and wrinkles", §4).
// Hessian: the Gauss–Newton part 2 k w ∇θ ∇θᵀ, PSD by construction; it drops
// 2 k w (θ − θ₀) ∇²θ, which vanishes at the rest angle.
#include <pce/sim/instrumentation.hpp>
#include "arguments.hpp"
#include "local_terms.hpp"

#include <pce/sim/effects.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

using Vector12 = Eigen::Matrix<double, 12, 1>;
using Matrix12 = Eigen::Matrix<double, 12, 12>;

struct Hinge {
  std::array<int, 4> v;  ///< edge x0 → x1 (triangle A's winding), wing of A, wing of B
  double theta0;         ///< rest dihedral angle
  double weight;         ///< k · 3|ē|²/(Ā_A + Ā_B)
};

/// What θ and every slot's ∇θ share: the edge e = x1 − x0, the normals, their squares.
struct HingeShape {
  Eigen::Vector3d e, nA, nB;
  double l2, l, nA2, nB2;
};

/// θ at the hinge and its shape; returns false when a current triangle of the hinge has
/// (near) zero area, where θ's gradient does not exist (`theta` is then 0 or the atan2 of
/// what is left).
inline bool hinge_shape(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Eigen::Vector3d& x2,
                        const Eigen::Vector3d& x3, double& theta, HingeShape& h) {
  h.e = x1 - x0;
  h.nA = h.e.cross(x2 - x0);
  h.nB = (x3 - x0).cross(h.e);
  h.l2 = h.e.squaredNorm();
  h.l = std::sqrt(h.l2);
  h.nA2 = h.nA.squaredNorm();
  h.nB2 = h.nB.squaredNorm();
  theta = std::atan2(h.l > 0 ? h.nA.cross(h.nB).dot(h.e) / h.l : 0.0, h.nA.dot(h.nB));
  // A wing's height must not vanish against the edge: h = |n|/|e| > 1e-12 |e|.
  return h.l2 > 0 && h.nA2 > 1e-24 * h.l2 * h.l2 && h.nB2 > 1e-24 * h.l2 * h.l2;
}

/// ∂θ/∂x_slot at a hinge of shape h (file comment): a wing's −|e| n/|n|², an edge vertex's
/// combination of both wings' by their feet s_{A,B} on the edge.
inline Eigen::Vector3d hinge_gradient(const HingeShape& h, const Eigen::Vector3d& x0, const Eigen::Vector3d& x2,
                                      const Eigen::Vector3d& x3, int slot) {
  if (slot == 2) return (-h.l / h.nA2) * h.nA;
  if (slot == 3) return (-h.l / h.nB2) * h.nB;
  const Eigen::Vector3d gA = (-h.l / h.nA2) * h.nA, gB = (-h.l / h.nB2) * h.nB;
  const double sA = (x2 - x0).dot(h.e) / h.l2, sB = (x3 - x0).dot(h.e) / h.l2;
  if (slot == 0) return -(1 - sA) * gA - (1 - sB) * gB;
  return -sA * gA - sB * gB;
}

/// θ and ∇θ (12-vector, vertex order of Hinge::v); returns false when a current triangle of
/// the hinge has (near) zero area (`hinge_shape`; `g` untouched then).
inline bool dihedral_angle(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Eigen::Vector3d& x2,
                           const Eigen::Vector3d& x3, double& theta, Vector12* g) {
  HingeShape h;
  if (!hinge_shape(x0, x1, x2, x3, theta, h)) return false;
  if (g) {  // hinge_gradient's four slots, the wings' terms computed once
    const Eigen::Vector3d gA = (-h.l / h.nA2) * h.nA, gB = (-h.l / h.nB2) * h.nB;
    const double sA = (x2 - x0).dot(h.e) / h.l2, sB = (x3 - x0).dot(h.e) / h.l2;
    g->segment<3>(0) = -(1 - sA) * gA - (1 - sB) * gB;
    g->segment<3>(3) = -sA * gA - sB * gB;
    g->segment<3>(6) = gA;
    g->segment<3>(9) = gB;
  }
  return true;
}

/// θ − θ₀ wrapped into (−π, π].
inline double angle_difference(double theta, double theta0) {
  constexpr double pi = 3.14159265358979323846;
  double d = theta - theta0;
  if (d > pi)
    d -= 2 * pi;
  else if (d <= -pi)
    d += 2 * pi;
  return d;
}

class Bending final : public Effect {
 public:
  Bending(int vertex_count, std::vector<Hinge> hinges) : Effect("bending"), hinges_(std::move(hinges)) {
    incidence_.build(vertex_count, hinges_.size(), [this](std::size_t e) { return hinges_[e].v; });
  }
  void declare(Pattern& pattern) const override {
    for (const Hinge& h : hinges_) pattern.add(h.v);
  }
  /// E = Σ_hinges w (θ − θ₀)², ∇E = 2w(θ − θ₀)∇θ, H ≈ 2w ∇θ∇θᵀ (Gauss–Newton).
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    double energy = 0;
    degenerate_ = 0;
    Vector12 g;
    for (const Hinge& h : hinges_) {
      double theta;
      const bool ok = dihedral_angle(x.col(h.v[0]), x.col(h.v[1]), x.col(h.v[2]), x.col(h.v[3]), theta, &g);
      const double d = angle_difference(theta, h.theta0);
      energy += h.weight * d * d;
      if (!ok) {  // no direction to push along: no force, counted in the statistics
        ++degenerate_;
        continue;
      }
      if (gradient)
        for (int a = 0; a < 4; ++a) gradient->col(h.v[a]) += (2 * h.weight * d) * g.segment<3>(3 * a);
      if (hessian) hessian->add<4>(h.v, ((2 * h.weight) * g * g.transpose()).eval());
    }
    return energy;
  }
  /// Per listed vertex, the sum over its hinges of 2w(θ − θ₀)∇ₐθ and 2w ∇ₐθ∇ₐθᵀ (a its slot
  /// in the hinge); a degenerate hinge adds nothing, as in `evaluate`. The statistics'
  /// degenerate hinges are those of the last `evaluate`.
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    add_local_terms(incidence_, vertices, terms, [&](const Incident& u, Eigen::Vector3d& ga, Eigen::Matrix3d& B) {
      const Hinge& h = hinges_[static_cast<std::size_t>(u.item)];
      double theta;
      HingeShape shape;
      const Eigen::Vector3d x0 = x.col(h.v[0]), x2 = x.col(h.v[2]), x3 = x.col(h.v[3]);
      if (!hinge_shape(x0, x.col(h.v[1]), x2, x3, theta, shape)) return true;
      const double d = angle_difference(theta, h.theta0);
      const Eigen::Vector3d gs = hinge_gradient(shape, x0, x2, x3, u.slot);
      ga += (2 * h.weight * d) * gs;
      B.noalias() += (2 * h.weight) * gs * gs.transpose();
      return true;
    });
  }
  void report(EffectCounters& counters) const override {
    counters[Counter::hinges] = static_cast<double>(hinges_.size());
    counters[Counter::degenerate_hinges] = static_cast<double>(degenerate_);
  }

 private:
  std::vector<Hinge> hinges_;
  VertexIncidence incidence_;  ///< per vertex, its hinges
  long degenerate_ = 0;
};

}  // namespace

std::unique_ptr<Effect> make_bending(const Model& model, double stiffness) {
  const double k = args::stiffness("stiffness", stiffness);
  const Eigen::Matrix3Xi& T = model.triangles;
  // Every triangle edge as (min, max, triangle, corner): corner c's edge is (c, c+1) in
  // winding order, its wing the vertex c+2. Sorting groups the triangles of an edge.
  struct EdgeUse {
    int lo, hi, triangle, corner;
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * static_cast<std::size_t>(T.cols()));
  for (int t = 0; t < static_cast<int>(T.cols()); ++t)
    for (int c = 0; c < 3 && !model.is_boundary_triangle(t); ++c) {
      const int a = T(c, t), b = T((c + 1) % 3, t);
      uses.push_back({std::min(a, b), std::max(a, b), t, c});
    }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& p, const EdgeUse& q) {
    return p.lo != q.lo ? p.lo < q.lo : p.hi != q.hi ? p.hi < q.hi : p.triangle < q.triangle;
  });
  std::vector<Hinge> hinges;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    if (j - i == 2) {  // manifold interior edge; boundary and non-manifold edges carry no hinge
      const EdgeUse& A = uses[i];
      const EdgeUse& B = uses[i + 1];
      Hinge h;
      h.v = {T(A.corner, A.triangle), T((A.corner + 1) % 3, A.triangle), T((A.corner + 2) % 3, A.triangle),
             T((B.corner + 2) % 3, B.triangle)};
      const auto X = [&](int a) { return model.rest.col(h.v[static_cast<std::size_t>(a)]); };
      const Eigen::Vector3d x0 = X(0), x1 = X(1), x2 = X(2), x3 = X(3);
      const Eigen::Vector3d e = x1 - x0;
      const double area = 0.5 * (e.cross(x2 - x0).norm() + (x3 - x0).cross(e).norm());
      if (!dihedral_angle(x0, x1, x2, x3, h.theta0, nullptr) || !(area > 0))
        throw ArgumentError("", "the hinge of triangles " + std::to_string(A.triangle) + " and " +
                                    std::to_string(B.triangle) +
                                    " has a zero-area rest triangle (bending needs a rest shape)");
      h.weight = k * 3 * e.squaredNorm() / area;
      hinges.push_back(h);
    }
    i = j;
  }
  instrumentation().bending_hinges_allocated += static_cast<long>(hinges.size());
  return std::make_unique<Bending>(model.vertex_count(), std::move(hinges));
}

}  // namespace pce::sim
