// SPDX-License-Identifier: MIT
/// @file
/// The pair potential of self contact (internal; docs/simulation.md §4.3): pce's energy,
/// gradient and projected Hessian of one candidate at one state, when the classifier finds
/// it active. Plane mode evaluates the penalty of L = σ l on the frame the classifier built
/// (pce::pair_energy's result, without a second frame); closest-feature mode and fold pairs
/// evaluate pce::closest_feature_energy. The Hessian is the effect's projection
/// (`hessian`). A barrier at L ≤ 0 is infinite energy, which the line search rejects.
#pragma once

#include "activity.hpp"
#include "ordered_chunks.hpp"

#include <pce/energy/closest_feature.hpp>
#include <pce/energy/pair_energy.hpp>
#include <pce/energy/projection.hpp>

#include <limits>
#include <vector>

namespace pce::sim::contact {

/// What one evaluation says about one candidate: its term when active, and what the
/// sparsity pattern would declare for it.
struct PairOutcome {
  bool active = false;
  /// is_active would say yes: active, or a degenerate closest-feature configuration.
  bool declare = false;
  bool unsure = false;  ///< declare is unknown (a status of the effect's penalty other than ok)
  PairTerm<4> term;     ///< when active
};

/// The pair potential of one self-contact effect (see the file comment).
template <bool VF> class PairPotential {
  using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;

 public:
  /// The effect's settings, candidates and classifier.
  PairPotential(const ContactSettings& settings, const CandidateSet<VF>& candidates, const Classifier<VF>& classifier)
      : settings_(&settings), candidates_(&candidates), classifier_(&classifier) {}

  /// Candidate k at x with the effect's `penalty`: its term in `o` when active, its
  /// projected Hessian appended to `blocks` when that is non-null. `local`: a pass of block
  /// descent's local terms, on several threads that may share k: without the candidate
  /// set's filter (the last measure_drift was at another state) and without tightening its
  /// bound (no write).
  template <class Penalty> void evaluate(const Eigen::Matrix3Xd& x, long k, const Penalty& penalty,
                                         std::vector<PairBlock<4>>* blocks, PairOutcome& o, bool local = false) const {
    o.active = false;
    const auto uk = static_cast<std::size_t>(k);
    std::array<int, 4> v;
    Vec12<double> xp;
    Activity a;
    if (!classifier_->active_candidate(x, uk, v, xp, a, !local)) return;
    o.declare = a.mode == Activity::Mode::plane;  // is_active: plane mode is active
    o.term.k = k;
    o.term.vertices = v;
    const Penalty pk = classifier_->weighted(penalty, uk);
    if (a.mode == Activity::Mode::closest)
      return a.fold ? closest(xp, k, Classifier<VF>::with_reach(pk, a.limit), a.limit, blocks, o, local)
                    : closest(xp, k, pk, a.limit, blocks, o, local);
    // pair_energy's result from the frame already built (signed with the side σ, or the
    // unsigned length, whose σ = sgn l is the same number): no second frame.
    PairEnergy<double> e;
    e.frame = a.frame;
    e.sigma = a.sigma;
    e.length = a.sigma * a.frame.l;
    const Status s = evaluate_penalty(pk, e.length, e.psi);
    if (s == Status::out_of_domain) return infinite(o);
    if (s != Status::ok) return;
    o.active = true;
    o.term.length = e.length;
    o.term.energy = e.psi.value;
    o.term.gradient = energy_gradient(e);
    if (blocks) blocks->push_back({v, projected_hessian(e, settings_->hessian)});
  }

 private:
  /// Closest-feature evaluation of candidate k: active when the distance is below `limit`.
  template <class Penalty> void closest(const Vec12<double>& xp, long k, const Penalty& penalty, double limit,
                                        std::vector<PairBlock<4>>* blocks, PairOutcome& o, bool local) const {
    ClosestFeatureEnergy<double> ce;
    const Status s = closest_feature_energy<Kind>(xp, UnsignedLength{}, penalty, ce);
    // What is_active (which measures with a probe penalty) says: degenerate, or a distance
    // below the limit (a barrier's out_of_domain is a distance of 0). Another status of the
    // effect's penalty (overflow) leaves it unknown.
    o.declare = s == Status::degenerate || s == Status::out_of_domain || (s == Status::ok && ce.length < limit);
    o.unsure = !(s == Status::ok || s == Status::degenerate || s == Status::out_of_domain);
    // A barrier at distance 0 (out of its domain, or a point kind's `degenerate`, which
    // is reported only at distance exactly 0) is infinite energy.
    if (s == Status::out_of_domain || (s == Status::degenerate && settings_->penalty.barrier())) return infinite(o);
    if (s == Status::ok && !local) candidates_->tighten(static_cast<std::size_t>(k), o.term.vertices, ce.length);
    if (s != Status::ok || !(ce.length < limit)) return;
    o.active = true;
    o.term.length = ce.length;
    o.term.energy = ce.psi.value;
    o.term.gradient = energy_gradient(ce);
    if (blocks) blocks->push_back({o.term.vertices, projected_hessian(ce, settings_->hessian)});
  }

  /// A barrier evaluated at L ≤ 0: infinite energy, which the line search rejects.
  static void infinite(PairOutcome& o) {
    o.active = true;
    o.term.energy = std::numeric_limits<double>::infinity();
    o.term.length = 0;
    o.term.gradient.setZero();
  }

  const ContactSettings* settings_;
  const CandidateSet<VF>* candidates_;
  const Classifier<VF>* classifier_;
};

}  // namespace pce::sim::contact
