// SPDX-License-Identifier: MIT
/// @file
/// The friction of an obstacle-contact effect (internal; docs/simulation.md §4.7): at the
/// step's start every active (vertex, obstacle) pair is frozen with λ = −ψ′(d) (weighted),
/// the tangent basis of its normal, and the displacement over the step of the obstacle's
/// surface point nearest the vertex (its rigid motion from the step's start pose to its end
/// pose): the vertex's slip is its displacement less that one (effects/friction.hpp,
/// pce/friction/lagged_friction.hpp). With `lagged_iterations` n > 1, after each of the
/// first n − 1 solves the pairs are frozen again at the solve's result with the end poses.
#pragma once

#include "effects/friction.hpp"
#include "effects/vertex_incidence.hpp"
#include "obstacle_penalties.hpp"

#include <pce/sim/newton_hooks.hpp>

#include <vector>

namespace pce::sim::obstacle {

/// The frozen friction of one obstacle-contact effect (see the file comment).
class ObstacleFriction {
 public:
  ObstacleFriction(const FrictionSettings& settings, const ObstacleSet& set, const ObstaclePenalties& penalties)
      : settings_(settings), set_(&set), penalties_(&penalties) {}

  /// At the step's start: freezes the pairs active at xⁿ with the start poses.
  void begin_step(const StepContext& ctx);
  /// A solve ended at x: freezes again with the end poses while lagged iterations remain;
  /// true when it did (the step is solved again).
  bool end_solve(const Eigen::Matrix3Xd& x);
  /// The friction potential at x, adding its gradient and Hessian where given.
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian);
  /// Vertex i's frozen contacts at x: adds their gradient and majorizer blocks (block descent).
  void add_local(const Eigen::Matrix3Xd& x, int i, Eigen::Vector3d& g, Eigen::Matrix3d& H) const;
  /// The frozen contacts with μλ > 0 (Newton's stopping rule).
  const std::vector<FrozenFriction>& published() const { return published_; }
  /// Its counters.
  void report(EffectCounters& counters) const;

 private:
  /// Freezes the friction of every pair active at `x`, with the obstacles at their start
  /// poses (`at_start`) or their end poses.
  void freeze(const Eigen::Matrix3Xd& x, bool at_start);

  FrictionSettings settings_;
  const ObstacleSet* set_;
  const ObstaclePenalties* penalties_;
  std::vector<FrictionContact<1>> frozen_;              ///< the step's frozen friction pairs
  VertexIncidence incidence_;                           ///< per vertex, its entries of frozen_
  std::vector<std::vector<FrictionContact<1>>> parts_;  ///< per chunk while freezing
  std::vector<FrozenFriction> published_;               ///< frozen_ with μλ > 0, padded
  const Eigen::Matrix3Xd* x_start_ = nullptr;
  double slip_ = 0;  ///< ε_v h, the slip below which a contact sticks
  int rounds_ = 0;   ///< solves of this step with friction frozen so far
  FrictionStats stats_;
};

}  // namespace pce::sim::obstacle
