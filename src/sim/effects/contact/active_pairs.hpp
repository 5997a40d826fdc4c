// SPDX-License-Identifier: MIT
/// @file
/// The active pairs of a self-contact effect (internal; docs/simulation.md §4.3): what the
/// sparsity pattern declares (`update_pattern`) and the evaluation pass that sums the
/// active pairs' energies, gradients and Hessians (`evaluate`), both from the classifier's
/// one test, so what is declared is what is assembled. Passes that can reuse an earlier one
/// visit its list instead of every candidate: at the pattern's state, the pairs active
/// there; on a line-search trial, those the step bound found possibly active along the step.
#pragma once

#include "activity.hpp"
#include "ordered_chunks.hpp"
#include "pair_potential.hpp"

#include <pce/sim/block_hessian.hpp>

#include <limits>
#include <vector>

namespace pce::sim::contact {

/// The per-frame counters of one self-contact effect's evaluations.
struct ContactStats {
  double pair_ms = 0, scatter_ms = 0, settle_ms = 0;
  long active = 0, fold_active = 0;
  double min_length = std::numeric_limits<double>::infinity();
};

/// The declared and active pairs of one self-contact effect (see the file comment).
template <bool VF> class ActivePairs {
 public:
  /// The effect's settings, candidates, classifier and pair potential.
  ActivePairs(const ContactSettings& settings, CandidateSet<VF>& candidates, const Classifier<VF>& classifier,
              const PairPotential<VF>& potential)
      : settings_(&settings), candidates_(&candidates), classifier_(&classifier), potential_(&potential) {}

  /// Declares the vertices of every declared candidate.
  void declare(Pattern& pattern) const;
  /// Declares exactly the candidates active at x (those whose Hessian evaluate adds);
  /// returns true when that changed the declaration. Declaring more (pairs that were near
  /// activation at some earlier iterate) multiplies the factorisation's fill-in: on the
  /// hammock, 65 k declared pairs for 3 k active ones made L 4.9 M non-zeros and each
  /// factorisation 0.5 s.
  bool update_pattern(const Eigen::Matrix3Xd& x);
  /// The contact energy at x; adds its gradient and projected Hessian where non-null.
  /// `segment`: the candidates that can be active at x when x lies on the last step bound's
  /// segment (a line-search trial), else null. Writes the counters of `stats`.
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian,
                  const std::vector<std::size_t>* segment, ContactStats& stats);
  /// After a query: per new candidate k, `previous[k]` its former index or −1; a tracked
  /// pair keeps its declaration (until the next update_pattern), a new one starts
  /// undeclared. Forgets the lists of earlier passes.
  void carry_over(const std::vector<long>& previous);
  /// Forgets the lists of earlier passes (the candidates changed).
  void invalidate() { pattern_x_valid_ = evaluated_x_valid_ = false; }
  /// Per candidate: 1 when it is in the pattern.
  const std::vector<char>& declared() const { return declared_; }
  /// Replaces the declarations (a checkpoint's, one per candidate).
  void restore(std::vector<char> declared) {
    declared_ = std::move(declared);
    invalidate();
  }

 private:
  const ContactSettings* settings_;
  CandidateSet<VF>* candidates_;
  const Classifier<VF>* classifier_;
  const PairPotential<VF>* potential_;
  std::vector<char> declared_, near_;           ///< per candidate: in the pattern; active at the last update_pattern
  std::vector<std::size_t> active_at_pattern_;  ///< the candidates active at the last update_pattern, ascending
  Eigen::Matrix3Xd pattern_x_;                  ///< the state of the last update_pattern
  bool pattern_x_valid_ = false;                ///< active_at_pattern_ belongs to the current candidates
  std::vector<std::size_t> declared_at_evaluation_;  ///< is_active at the last full evaluation, ascending
  Eigen::Matrix3Xd evaluated_x_;                     ///< the state of that evaluation
  bool evaluated_x_valid_ = false;                   ///< declared_at_evaluation_ is usable
  std::vector<std::vector<std::size_t>> declares_;   ///< per chunk: its pairs is_active would declare
  std::vector<char> unsure_;                         ///< per chunk: some declaration unknown
  PairTerms<4> terms_;                               ///< per chunk, active pairs only
};

}  // namespace pce::sim::contact
