// SPDX-License-Identifier: MIT
/// @file
/// The step bounds of an obstacle-contact effect (internal; docs/simulation.md §4.6, §5.5):
/// how far the vertices may move before a pair leaves the penalty's domain or passes its
/// floor. The obstacles keep their end poses throughout a step's solve.
///
/// Newton's line search (`line_search_bound`). Without a minimum separation, a log barrier's
/// pairs: the distance d is 1-Lipschitz in the vertex position, so t ≤ 0.9 d₀/|Δxᵢ| keeps
/// d ≥ 0.1 d₀ > 0 along the step (a pair with d₀ > |Δxᵢ| is not bounded). With a minimum
/// separation F (effects/floor.hpp), for every penalty: a pair whose tenth is below twice its
/// floor keeps `floor_gap`, any other pair that could come within 2F + 2δ a tenth of d₀,
/// each bounded by `advance_to_gap` along its separating direction: for a convex obstacle the
/// supporting plane at the closest surface point, which the shape lies behind, so the
/// distance from xᵢ + s Δxᵢ is at least S − s r with S the distance at xᵢ and r = −n·Δxᵢ (a
/// vertex sliding along its floor or leaving does not limit the step); for a mesh obstacle
/// the Lipschitz bound, r = |Δxᵢ|. The pairs whose limit their floor gap set are listed
/// (`held`).
///
/// Block descent (`room`, `move_limit`, `vertex_bounds`): a vertex at distance d may move
/// 0.9 (d − F) towards a surface (0.09 d when d ≤ F; inside, d ≤ 0, no limit: the penalty
/// pushes it out).
#pragma once

#include "effects/floor.hpp"
#include "obstacle_set.hpp"

#include <vector>

namespace pce::sim::obstacle {

/// The step bounds of one obstacle-contact effect (see the file comment).
class ObstacleBounds {
 public:
  /// `floor`: f·d (0: none); `barrier`: the penalty is a log barrier.
  ObstacleBounds(const ObstacleSet& set, double floor, bool barrier) : set_(&set), floor_(floor), barrier_(barrier) {}

  /// Newton: the largest fraction t ∈ [0, 1] of the step dx from x that keeps every pair in
  /// the barrier's domain and at its floor (see the file comment); lists the pairs the floor
  /// limited (`held`).
  double line_search_bound(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx);
  /// The pairs whose limit in the last line_search_bound their floor set, in pair order.
  const std::vector<FloorLimit>& held() const { return held_; }

  /// Block descent: how far a vertex at distance d > 0 from a surface may move towards it.
  double room(double d) const { return 0.9 * (d > floor_ ? d - floor_ : 0.1 * d); }
  /// Block descent: the largest fraction (≤ 1) of vertex i's move dxᵢ from x that keeps its
  /// room(d) to every obstacle (1 inside a volume, or inside an obstacle).
  double move_limit(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, Eigen::Index i) const;
  /// Block descent's first move: the largest fraction of dx every vertex's move_limit allows.
  double safe_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) const;
  /// Block descent's first move: lowers limit[i] to vertex i's move_limit.
  void limit_moves(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, Eigen::VectorXd& limit) const;
  /// Block descent: lowers bound[i] to vertex i's room at x to every obstacle.
  void vertex_bounds(const Eigen::Matrix3Xd& x, Eigen::VectorXd& bound) const;

 private:
  /// Pair (i, k)'s part of line_search_bound at distance d0 (a pair its lower bound did not
  /// rule out), lowering the running minimum `t`.
  void bound_pair(const Eigen::Vector3d& p, const Eigen::Vector3d& dxi, Eigen::Index i, std::size_t k, double d0,
                  double& t, std::vector<FloorLimit>& held) const;

  const ObstacleSet* set_;
  double floor_;
  bool barrier_;
  double slack_ = 0;  ///< the floor's rounding allowance at the last line_search_bound's x
  std::vector<FloorLimit> held_;
  std::vector<std::vector<FloorLimit>> held_chunks_;
};

}  // namespace pce::sim::obstacle
