// SPDX-License-Identifier: MIT
/// @file
/// Friction of a self-contact effect (internal; docs/simulation.md §4.7): at the step's
/// start every candidate active there is frozen (`freeze`): λ = −ψ′(L) of its (weighted)
/// penalty, its closest points' weights (the frame's for the plane kinds, the closest
/// feature's otherwise) and a tangent basis of its normal (pce::friction_geometry), μλ and
/// ε = ε_v h. The potential of the closest points' relative slip over the step is summed
/// with the contact energy, on its own list: a frozen pair stays one for the step whether
/// or not it is still active or a candidate. With `lagged_iterations` n > 1, the pairs are
/// frozen again after each of the first n − 1 solves of the step.
#pragma once

#include "effects/vertex_incidence.hpp"

#include "effects/friction.hpp"
#include "activity.hpp"

#include <pce/sim/counters.hpp>

#include <vector>

namespace pce::sim::contact {

/// The frozen friction contacts of one self-contact effect (see the file comment).
template <bool VF> class FrictionFreezing {
 public:
  /// The effect's settings (with friction), candidates and classifier.
  FrictionFreezing(const ContactSettings& settings, CandidateSet<VF>& candidates, const Classifier<VF>& classifier)
      : settings_(&settings), candidates_(&candidates), classifier_(&classifier) {}

  /// Starts a time step: freezes the pairs active at xⁿ = ctx.x_start.
  void begin_step(const StepContext& ctx);
  /// After a solve that ended at x: freezes again at x and returns true, unless the step
  /// has had its `lagged_iterations` solves.
  bool update_lagged(const Eigen::Matrix3Xd& x);
  /// The friction potential at x; adds its gradient and Hessian where non-null.
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian);
  /// Adds, for each vertex of `vertices`, its gradient and diagonal Hessian block of the
  /// friction potential at x to `terms` (block descent; the frozen pairs it is a corner of,
  /// in order).
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) const;
  /// Declares the frozen pairs' vertices.
  void declare(Pattern& pattern) const {
    for (const FrictionContact<4>& c : frozen_) pattern.add(c.v);
  }
  /// Writes the friction counters of this kind of pair.
  void report(Counters& counters) const;
  /// The frozen contacts with μλ > 0, as Newton's stopping rule reads them.
  const std::vector<FrozenFriction>& published() const { return published_; }

 private:
  /// Freezes the friction of every candidate active at x (chunks of consecutive candidates
  /// on the threads, joined in candidate order).
  void freeze(const Eigen::Matrix3Xd& x);

  const ContactSettings* settings_;
  CandidateSet<VF>* candidates_;
  const Classifier<VF>* classifier_;
  const Eigen::Matrix3Xd* x_start_ = nullptr;
  std::vector<FrictionContact<4>> frozen_;              ///< the step's frozen pairs
  VertexIncidence incidence_;                           ///< per vertex, the frozen pairs it is a corner of
  std::vector<std::vector<FrictionContact<4>>> parts_;  ///< per chunk while freezing
  std::vector<FrozenFriction> published_;               ///< frozen_ with μλ > 0, padded
  double slip_ = 0;                                     ///< ε_v h, the slip below which a contact sticks
  int rounds_ = 0;                                      ///< solves of this step with friction frozen so far
  FrictionStats stats_;
};

}  // namespace pce::sim::contact
