// SPDX-License-Identifier: MIT
/// @file
/// The step bound of a self-contact effect with a barrier or `ccd` (internal;
/// docs/simulation.md §4.6): the largest fraction of a Newton step along which no candidate
/// pair can cross and the candidate set stays valid, and, from the same pass, the list of
/// candidates that can be active anywhere on that segment (what a line-search trial then
/// visits alone).
///
/// Conservative advancement (additive CCD, Li et al. 2021): the distance is unchanged by a
/// common translation, so with p̄ the mean of the pair's four vertex displacements, along
/// x + t dx the distance between the primitives changes by at most t (max |dxᵢ − p̄| over
/// the first's vertices + max |dxⱼ − p̄| over the second's); each candidate keeps 10 % of
/// its current distance (closest features), so no candidate pair can cross during the step.
/// A pair whose one-shot bound would lower t is advanced further by measuring its distance
/// again (`advance`): one round cut a sliding or glancing pair's step to a few percent; on
/// the hammock's frames 21-40 that cost ~3 Newton iterations a frame. (Without p̄, strands
/// falling side by side limited each other's step to ~6 % for twenty iterations.) The step
/// also keeps the candidate set valid (`CandidateSet::step_limit`), so no other pair can come
/// within d either: bounding the candidates alone let a landing sheet cross faces that were
/// not candidates.
#pragma once

#include "activity.hpp"
#include "effects/floor.hpp"

#include <vector>

namespace pce::sim::contact {

/// The step bound of one self-contact effect (see the file comment).
template <bool VF> class StepBound {
 public:
  /// The effect's candidates and classifier.
  StepBound(CandidateSet<VF>& candidates, const Classifier<VF>& classifier)
      : candidates_(&candidates), classifier_(&classifier) {}

  /// The largest fraction t ∈ [0, 1] of the step dx from x that keeps every candidate at
  /// least 10 % of its distance apart and the candidate set valid; lists the candidates
  /// that can be active on x + s dx, s ∈ [0, t_valid] (`segment`).
  double max_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx);
  /// The candidates that can be active at x when x lies on the last max_step's segment
  /// (x = x₀ + s dx with s ∈ [0, t_valid], to within kSegmentTolerance · max(|x₀|, 1) per
  /// coordinate, what the solver's x₀ + α dx rounds to); null otherwise.
  const std::vector<std::size_t>* segment_at(const Eigen::Matrix3Xd& x) const;
  /// Forgets the last segment (the candidates changed, or a new step begins).
  void invalidate() {
    segment_valid_ = false;
    held_.clear();
  }
  /// The candidates whose limit in the last max_step was set by their floor (or that started
  /// it below their floor) and was below its chunk's running minimum: those the step may have brought
  /// to their floor (ascending).
  const std::vector<FloorLimit>& held() const { return held_; }

 private:
  /// Candidate k's part of max_step: whether it can be active on the segment (appended to
  /// `segment`), and the limit it puts on t (lowering `t`, the running minimum).
  /// A pair whose limit its floor set is appended to `held`.
  void bound_pair(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, std::size_t k, double t_valid, double& t,
                  std::vector<std::size_t>& segment, std::vector<FloorLimit>& held) const;
  /// Additive CCD, iterated (see the file comment): the largest t found for which the pair
  /// at xp + s dxp, s ∈ [0, t], stays at least g = 0.1 d₀ apart (d₀ its distance at s = 0,
  /// `lp` = ma + mb the bound on how fast the distance changes along the step). From a
  /// distance dᵢ at tᵢ the distance stays ≥ g up to tᵢ + (dᵢ − g)/lp; each round advances
  /// 0.9 of that and measures again, until t reaches `cap` (then the pair cannot lower the
  /// minimum), the advance stalls below 1e-3 t, or 32 rounds. The first round is the
  /// one-shot bound 0.9 d₀/lp.
  static double advance(const Vec12<double>& xp, const Vec12<double>& dxp, double d0, double lp, double cap);
  /// The pair's separation along m, the unit vector between its closest points at xp (from
  /// the second primitive's to the first's): S = min over the first's vertices of m·x less
  /// the max over the second's, and r = the largest m·dx of the second's vertices less the
  /// smallest of the first's. Both primitives are convex hulls of their vertices, so at
  /// xp + s dxp their distance is at least their separation along m, hence at least S − s r
  /// for every s ≥ 0 (S is the distance at s = 0 up to rounding). False when the pair is
  /// degenerate or touching.
  static bool separation(const Vec12<double>& xp, const Vec12<double>& dxp, double& S, double& r);
  /// The floor's bound (docs/simulation.md §4.6, `advance_to_gap`): the pair at
  /// xp + s dxp keeps at least g − `slack`, measured by its separation along the unit vector
  /// between its closest points.
  static double directional_advance(const Vec12<double>& xp, const Vec12<double>& dxp, double g, double slack,
                                    double cap);

  /// segment_at's tolerance per coordinate, relative to max(|x₀|, 1): far above the rounding
  /// of x₀ + α dx (a few ε), far below any distance that matters.
  static constexpr double kSegmentTolerance = 1e-12;

  CandidateSet<VF>* candidates_;
  const Classifier<VF>* classifier_;
  /// The candidates that can be active on the segment of the last max_step (ascending), per
  /// chunk while it is built, and that segment: x₀ + s dx, s ∈ [0, segment_t_].
  std::vector<std::size_t> segment_;
  std::vector<std::vector<std::size_t>> segments_;
  Eigen::Matrix3Xd segment_x_, segment_dx_;
  double segment_t_ = 0;
  double segment_slack_ = 0;      ///< the list's allowance for a state up to segment_at's tolerance off the segment
  double floor_slack_ = 0;        ///< the floor's rounding allowance at the last max_step's x
  std::vector<FloorLimit> held_;  ///< see held()
  std::vector<std::vector<FloorLimit>> held_chunks_;
  bool segment_valid_ = false;  ///< segment_ belongs to the current candidates
};

}  // namespace pce::sim::contact
