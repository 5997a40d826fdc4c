// SPDX-License-Identifier: MIT
/// @file
/// The penalties of an obstacle-contact effect (internal; docs/simulation.md §3):
/// E(x) = Σᵢ Σₖ wᵢₖ ψ(dₖ(xᵢ)) over the pairs with dₖ below the activation distance, dₖ the
/// signed distance to obstacle k's surface at its end pose (`surface_distance`), wᵢₖ the
/// vertex's lumped rest area when area weighted times the pair's stiffening factor
/// (obstacle_floor.hpp); the penalty is evaluated with stiffness wᵢₖ k, which ψ is linear in.
/// Gradient ψ′(d) n (∇d = n, the outward unit normal at the closest surface point).
/// Hessian ∇²E = ψ″ n nᵀ + ψ′ ∇n. For a convex shape (sphere, box, capsule) ∇n is positive
/// semidefinite with n in its null space (for a sphere ∇n = (I − n nᵀ)/|x − c|), and ψ′ ≤ 0
/// where ψ is active, so ψ′ ∇n is negative semidefinite and shares the eigenvector n: the
/// exact PSD projection of ∇²E is max(ψ″, 0) n nᵀ, which is what is assembled. For a mesh
/// obstacle (unsigned distance to a non-convex surface) the same matrix is the Gauss-Newton
/// approximation, not the exact projection. A log barrier's energy is +∞ (returned, not
/// thrown) when a vertex sits at d ≤ 0.
#pragma once

#include "effects/contact/ordered_chunks.hpp"
#include "effects/contact_penalty.hpp"
#include "obstacle_floor.hpp"
#include "obstacle_set.hpp"

#include <limits>
#include <vector>

namespace pce::sim::obstacle {

/// The penalties of one obstacle-contact effect (see the file comment).
class ObstaclePenalties {
 public:
  /// `areas`: per vertex its lumped rest area (area weighting), else empty.
  ObstaclePenalties(const ContactPenalty& penalty, const ObstacleSet& set, const ObstacleFloor& floor,
                    Eigen::VectorXd areas)
      : penalty_(penalty), set_(&set), floor_(&floor), areas_(std::move(areas)) {}

  /// The penalty settings.
  const ContactPenalty& penalty() const { return penalty_; }
  /// The penalty of pair (i, k): `penalty` with its stiffness times wᵢₖ.
  template <class Penalty> Penalty weighted(const Penalty& penalty, Eigen::Index i, std::size_t k) const {
    const double m = floor_->factor(i, k);
    if (!areas_.size()) return m == 1.0 ? penalty : scaled(penalty, m);
    return scaled(penalty, areas_[i] * m);
  }
  /// The energy at x, adding its gradient and PSD Hessian where given; +∞ when a barrier's
  /// domain is left (a vertex at d ≤ 0). Keeps the active pairs for `report`.
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian);
  /// Vertex i at p: adds its pairs' gradient and Hessian block to g and H (block descent).
  template <class Penalty> void add_local(const Penalty& penalty, const Eigen::Vector3d& p, Eigen::Index i,
                                          Eigen::Vector3d& g, Eigen::Matrix3d& H) const;

  /// Whether the last evaluation left a barrier's domain (its energy +∞).
  bool left_domain() const { return left_domain_; }
  /// Active pairs at the last evaluation.
  long contacts() const;
  /// The smallest distance (or lower bound of it) at the last evaluation.
  double min_distance() const { return min_distance_; }

 private:
  /// The active pairs at x with their terms (terms_, in vertex then obstacle order) and the
  /// minimum distance; true when a barrier's domain is left.
  template <class Penalty> bool gather(const Eigen::Matrix3Xd& x, const Penalty& penalty);

  ContactPenalty penalty_;
  const ObstacleSet* set_;
  const ObstacleFloor* floor_;
  Eigen::VectorXd areas_;
  contact::PairTerms<1> terms_;      ///< per chunk: the active pairs of the last evaluation
  std::vector<double> chunk_min_;    ///< per chunk: its smallest distance (bound) of the last evaluation
  std::vector<char> chunk_blocked_;  ///< per chunk: a barrier's domain was left
  double min_distance_ = std::numeric_limits<double>::max();
  bool left_domain_ = false;
};

template <class Penalty> void ObstaclePenalties::add_local(const Penalty& penalty, const Eigen::Vector3d& p,
                                                           Eigen::Index i, Eigen::Vector3d& g,
                                                           Eigen::Matrix3d& H) const {
  const double reach = penalty_.distance;
  set_->near(
      p, [&](double lower) { return lower >= reach; },
      [&](std::size_t k, const SurfaceDistance& s) {
        if (!(s.distance < reach) || (penalty_.barrier() && !(s.distance > 0))) return;
        const PenaltyDerivatives<double> psi = weighted(penalty, i, k).evaluate(s.distance);
        g += psi.first * s.normal;
        if (psi.second > 0) H += psi.second * (s.normal * s.normal.transpose());
      });
}

}  // namespace pce::sim::obstacle
