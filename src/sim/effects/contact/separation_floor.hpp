// SPDX-License-Identifier: MIT
/// @file
/// The minimum separation of a self-contact effect (internal; docs/simulation.md §4.6): what
/// happens to a pair the step bound held at its floor.
///
/// Each candidate has a floor, `min_separation` times d (times a fold pair's reach):
/// StepBound keeps every pair that starts a Newton step at or above its floor there, and
/// lists the pairs whose limit the floor set (`StepBound::held`). A penalty too soft for its
/// load would leave such a pair at the floor, and Newton, whose direction keeps pressing it
/// in, cutting every step short until its iteration cap. So after each Newton iteration, a
/// listed pair that the iteration pressed in (it ended within kHeldWithin floors, and near
/// the gap the step bound kept, or halfway there) is *held*: its penalty's stiffness is
/// multiplied by kFloorStiffening, 16 (so is its force at every distance, and its largest
/// force grows sixteenfold per hold until it carries the load). The factor stays while the pair is
/// active and is forgotten when a step starts with the pair beyond its reach, or the pair
/// leaves the candidate set; checkpoints keep it.
#pragma once

#include "activity.hpp"
#include "step_bound.hpp"

#include <vector>

namespace pce::sim::contact {

/// The minimum separation's stiffening of one self-contact effect (see the file comment).
template <bool VF> class SeparationFloor {
 public:
  /// The effect's candidates and classifier (whose stiffening factors this sets).
  SeparationFloor(const CandidateSet<VF>& candidates, Classifier<VF>& classifier)
      : candidates_(&candidates), classifier_(&classifier) {}

  /// Forgets the factors of pairs beyond their reach at the step's start `x`; zeroes the
  /// frame's hold count.
  void begin_step(const Eigen::Matrix3Xd& x);
  /// After a Newton iteration that left the state at `x`: stiffens each of `held` (the step
  /// bound's list) that x has closer than kHeldWithin floors and within a quarter floor of
  /// the gap the step bound kept, or at least halfway there from its start (pressed in, not
  /// merely limited); true when one was.
  bool stiffen(const Eigen::Matrix3Xd& x, const std::vector<FloorLimit>& held);
  /// After a query: the factors follow their pairs (`previous`: per new candidate its former
  /// index, or −1).
  void carry_over(const std::vector<long>& previous);

  /// Holds in the frame so far (a pair held at two iterations counts twice).
  long holds() const { return holds_; }
  /// Candidates whose factor is above 1.
  long stiffened() const;

 private:
  /// Candidate k's distance at x (closest features), or +∞ when it cannot be measured.
  double distance(const Eigen::Matrix3Xd& x, std::size_t k) const;

  const CandidateSet<VF>* candidates_;
  Classifier<VF>* classifier_;
  long holds_ = 0;
};

}  // namespace pce::sim::contact
