// SPDX-License-Identifier: MIT
/// @file
/// The minimum separation of an obstacle-contact effect (internal; effects/floor.hpp,
/// docs/simulation.md §4.6): the stiffening factors of its (vertex, obstacle) pairs, which
/// grow when a line search pressed a pair its step bound held at its floor
/// (obstacle_bounds.hpp lists them), are forgotten when a step starts with the pair beyond
/// the penalty's reach, and are what a checkpoint keeps.
#pragma once

#include "effects/floor.hpp"
#include "obstacle_set.hpp"

#include <string>
#include <vector>

namespace pce::sim::obstacle {

/// The stiffening of one obstacle-contact effect (see the file comment).
class ObstacleFloor {
 public:
  /// `floor`: the minimum separation f·d (0: none); `vertices`: the model's vertex count.
  ObstacleFloor(const ObstacleSet& set, double floor, long vertices) : set_(&set), floor_(floor), vertices_(vertices) {}

  /// The floor f·d.
  double floor() const { return floor_; }
  /// The factor of pair (i, k): 1 unless the pair was held.
  double factor(Eigen::Index i, std::size_t k) const { return factors_.empty() ? 1.0 : factors_[set_->pair(i, k)]; }
  /// At the step's start `x` (the obstacles at their end poses): forgets the factors of pairs
  /// beyond `reach` (the penalty's activation distance); zeroes the frame's hold count.
  void begin_step(const Eigen::Matrix3Xd& x, double reach);
  /// After a line search that ended at x: stiffens each of `held` (the step bound's list)
  /// the search pressed in (`pressed_in`); true when one was.
  bool stiffen(const Eigen::Matrix3Xd& x, const std::vector<FloorLimit>& held);

  /// Holds in the frame so far.
  long holds() const { return holds_; }
  /// Pairs whose factor is above 1.
  long stiffened() const;
  /// The factors above 1 as (pair index, factor) records.
  std::string save() const;
  /// Restores what `save` wrote; std::invalid_argument (naming `effect`) when it does not fit.
  void load(const std::string& state, const std::string& effect);

 private:
  const ObstacleSet* set_;
  double floor_;
  long vertices_;                ///< the model's vertex count (0 without a model: no factor loads)
  std::vector<double> factors_;  ///< per pair i·K + k; empty when all are 1
  long holds_ = 0;               ///< holds in the frame so far
};

}  // namespace pce::sim::obstacle
