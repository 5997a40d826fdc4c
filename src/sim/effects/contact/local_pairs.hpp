// SPDX-License-Identifier: MIT
/// @file
/// Block descent's view of one self-contact effect (internal; docs/simulation.md §5.5):
/// every vertex's conservative bound at a query, the candidates one sweep's local passes
/// can find active, and their per-vertex terms.
///
/// Bounds (after Chen et al. 2025, "Offset geometric contact", per-vertex displacement
/// bounds): at the query's state x₀ candidate k is D apart, its floor F (minimum
/// separation). Each of its vertices may move kShare (D − F) from x₀, or kShare D/10 when
/// D ≤ F: however all of them move within their bounds, its primitives close in by at most
/// 2 kShare (D − F) < D − F, so it keeps its floor (or nine tenths of its distance). A pair
/// that is not a candidate is more than r = d + m apart at a query's state x₀ (more than d
/// where the set is still valid), so a bound of at most kShare (r − F) (kShare (d − F))
/// keeps it apart too.
#pragma once

#include "activity.hpp"
#include "pair_potential.hpp"

#include "effects/vertex_incidence.hpp"

#include <pce/sim/block_hessian.hpp>
#include <pce/sim/effect.hpp>

#include <vector>

namespace pce::sim::contact {

/// Block descent's bounds and local terms of one self-contact effect (see the file comment).
template <bool VF> class LocalPairs {
 public:
  /// The share of a pair's room each of its vertices may use (below one half).
  static constexpr double kShare = 0.45;

  /// The effect's settings, candidates, classifier and pair potential.
  LocalPairs(const ContactSettings& settings, CandidateSet<VF>& candidates, const Classifier<VF>& classifier,
             const PairPotential<VF>& potential)
      : settings_(&settings), candidates_(&candidates), classifier_(&classifier), potential_(&potential) {}

  /// Lowers bound[i] for every vertex of the model's surface (see the file comment); at x
  /// every pair that is not a candidate is more than `apart` apart (the query radius at the
  /// query's state, d where the set is still valid).
  void bounds(const Model& model, const Eigen::Matrix3Xd& x, double apart, Eigen::VectorXd& bound) const;
  /// Before a sweep from x in which vertex i moves at most reach[i]: lists the candidates
  /// that can be active somewhere in the sweep (their distance at x, less the most their
  /// vertices can close in, below their reach), per vertex, and declares their vertices in
  /// `couplings`.
  void begin_sweep(const Eigen::Matrix3Xd& x, const Eigen::VectorXd& reach, Pattern& couplings);
  /// Forgets the sweep's list (the candidates changed, or a step begins).
  void forget() { ready_ = false; }
  /// Whether a sweep's list is there.
  bool ready() const { return ready_; }
  /// Adds, for each vertex of `vertices`, the gradient and the vertex's diagonal block of
  /// the projected Hessian of every listed candidate it is a corner of that is active at x.
  void evaluate(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) const;

 private:
  const ContactSettings* settings_;
  CandidateSet<VF>* candidates_;
  const Classifier<VF>* classifier_;
  const PairPotential<VF>* potential_;
  std::vector<long> listed_;                ///< the sweep's candidates, ascending
  std::vector<std::vector<long>> parts_;    ///< per chunk while listing
  mutable std::vector<double> pair_bound_;  ///< per candidate, while bounding
  VertexIncidence incidence_;               ///< per vertex, its entries of listed_
  bool ready_ = false;
};

}  // namespace pce::sim::contact
