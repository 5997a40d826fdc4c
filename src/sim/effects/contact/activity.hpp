// SPDX-License-Identifier: MIT
/// @file
/// Which candidates of a self-contact effect are active, and how (internal;
/// docs/simulation.md §4.3): the one activity test behind the sparsity pattern, the
/// evaluation, the friction freezing and the step bound, so what is declared is what is
/// assembled.
///
/// A fold pair (one mesh, closer than 2d at rest, `CandidateSet::fold_pair`) is tested by
/// closest features against its reach min(d, D₀/2); every other candidate by the effect's
/// mode against the activation distance d:
///  * plane mode (the paper's): the frame of the pair; active when the closest points of the
///    plane (line) distance lie inside the triangle (both segments) and L < d, with L = |l|
///    (unsigned) or L = σ l (signed: the side σ is settled the first time a step starts with
///    the vertex over the face, `settle_sides`, and kept while the pair stays a candidate);
///  * closest-feature mode: the distance between the primitives (measured by the caller).
/// With `area_weighted`, a pair's penalty is the effect's with stiffness w k, w its rest
/// area (vertex-face: the face's area plus the vertex's lumped area; edge-edge: the two
/// edges' lumped areas); a pair held at its minimum separation has it multiplied by its
/// stiffening factor (separation_floor.hpp).
#pragma once

#include "effects/contact_penalty.hpp"
#include "candidate_set.hpp"
#include "pair_geometry.hpp"

#include <pce/energy/closest_feature.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/sim/effects.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pce::sim::contact {

/// The distance between a pair's primitives (positions `xp`) by closest features; false
/// when pce reports a status other than ok (a degenerate primitive).
template <bool VF> bool closest_distance(const Vec12<double>& xp, double& distance) {
  using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;
  ClosestFeatureEnergy<double> ce;
  if (closest_feature_energy<Kind>(xp, UnsignedLength{}, QuadraticPenalty{1.0, 0.0}, ce) != Status::ok) return false;
  distance = ce.length;
  return true;
}

/// What `Classifier::classify` decides for one candidate at one state.
struct Activity {
  /// none: inactive; plane: active in plane mode (its frame and σ below); closest: to be
  /// measured by closest features (active when its distance is below `limit`, or in a
  /// degenerate configuration).
  enum class Mode { none, plane, closest } mode = Mode::none;
  double limit = 0;  ///< the activation distance it was tested against (a fold pair's reach, else d)
  bool fold = false;
  Frame<double> frame;  ///< plane: the pair's frame
  double sigma = 1;     ///< plane: the sign of L = σ l
};

/// The activity test of one self-contact effect, and the settled sides it reads (see the
/// file comment).
template <bool VF> class Classifier {
  using Geometry = PairGeometry<VF>;
  using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;

 public:
  /// The effect's settings and candidate set; `areas` its rest areas (area_weighted, else empty).
  Classifier(const ContactSettings& settings, const CandidateSet<VF>& candidates, const RestAreas& areas)
      : settings_(&settings), candidates_(&candidates), areas_(&areas) {}

  /// Whether candidate k (positions `xp`) is active, and how. The cheap rejections come
  /// first: the pair's own box gap or distance bound, then, in plane mode, plane_active.
  /// A closest-feature candidate that passes them is returned as closest with its limit.
  /// (Callers first ask filtered_out, the candidate set's filter.)
  Activity classify(const Vec12<double>& xp, std::size_t k) const {
    Activity a;
    a.fold = candidates_->fold_pair(k);
    if (a.fold) {
      a.limit = candidates_->fold_reach(k);
      if (!(a.limit > 0) || Geometry::distance_lower_bound(xp) >= a.limit) return a;
      a.mode = Activity::Mode::closest;
      return a;
    }
    a.limit = settings_->penalty.distance;
    if (Geometry::box_gap(xp) > inactive_beyond()) return a;
    if (settings_->closest_features) {
      a.mode = Activity::Mode::closest;
      return a;
    }
    if (plane_active(xp, k, a.limit, a.frame, a.sigma)) a.mode = Activity::Mode::plane;
    return a;
  }

  /// Candidate k at x, read only as far as needed: false when the filter drops it or
  /// classify finds it inactive; otherwise true with its vertices `v`, positions `xp` and
  /// activity `a`.
  /// `filter` false: without the candidate set's filter (a pass whose state the last
  /// measure_drift does not describe: block descent's local terms).
  bool active_candidate(const Eigen::Matrix3Xd& x, std::size_t k, std::array<int, 4>& v, Vec12<double>& xp, Activity& a,
                        bool filter = true) const {
    if (filter && filtered_out(k)) return false;
    v = candidates_->vertices(k);
    xp = Geometry::gather(x, v);
    a = classify(xp, k);
    return a.mode != Activity::Mode::none;
  }

  /// Pairs farther apart than this are inactive in every mode: the activation distance d,
  /// or 2d for signed plane mode (a pair counts down to L = −2d).
  double inactive_beyond() const {
    return (settings_->signed_length && !settings_->closest_features ? 2.0 : 1.0) * settings_->penalty.distance;
  }

  /// Candidate k is inactive while its distance is above this: its fold reach (a fold
  /// pair) or inactive_beyond().
  double reach_of(std::size_t k) const {
    return candidates_->fold_pair(k) ? candidates_->fold_reach(k) : inactive_beyond();
  }

  /// The candidate set's filter, before any vertex position is read: candidate k is
  /// provably farther apart than its reach at the last measured state.
  bool filtered_out(std::size_t k) const { return candidates_->beyond(k, reach_of(k)); }

  /// Whether candidate k is active at x (length below its limit, or a degenerate closest-
  /// feature configuration): what the sparsity pattern declares.
  bool is_active(const Eigen::Matrix3Xd& x, std::size_t k) const {
    if (filtered_out(k)) return false;
    const Vec12<double> xp = Geometry::gather(x, candidates_->vertices(k));
    const Activity a = classify(xp, k);
    if (a.mode != Activity::Mode::closest) return a.mode == Activity::Mode::plane;
    ClosestFeatureEnergy<double> ce;
    const QuadraticPenalty probe{1.0, 0.0};
    const Status s = closest_feature_energy<Kind>(xp, UnsignedLength{}, probe, ce);
    if (s == Status::ok) candidates_->tighten(k, candidates_->vertices(k), ce.length);
    return s == Status::degenerate || (s == Status::ok && ce.length < a.limit);
  }

  /// The penalty of candidate k: the effect's, with its stiffness times the pair's rest
  /// area when area weighted and times its stiffening (`stiffening`; ψ is linear in both).
  template <class Penalty> Penalty weighted(const Penalty& penalty, std::size_t k) const {
    const double m = stiffening_.empty() ? 1.0 : stiffening_[k];
    if (!settings_->area_weighted) return m == 1.0 ? penalty : scaled(penalty, m);
    const auto& c = candidates_->pairs()[k];
    const RestAreas& w = *areas_;
    return scaled(penalty, (VF ? w.vertex[c[0]] + w.triangle[c[1]] : w.edge[c[0]] + w.edge[c[1]]) * m);
  }

  /// Candidate k's minimum separation (docs/simulation.md §4.6): `min_separation` times d,
  /// or times its reach for a fold pair (0: no floor).
  double floor_of(std::size_t k) const {
    const double f = settings_->min_separation;
    if (!(f > 0)) return 0;
    return f * (candidates_->fold_pair(k) ? candidates_->fold_reach(k) : settings_->penalty.distance);
  }
  /// The largest floor of any candidate: min_separation times d.
  double largest_floor() const { return settings_->min_separation * settings_->penalty.distance; }

  /// Per candidate: the factor on its penalty's stiffness (≥ 1; `SeparationFloor` raises it
  /// for a pair held at its floor), or empty when every factor is 1.
  std::vector<double>& stiffening() { return stiffening_; }
  /// Per candidate: the factor on its penalty's stiffness, or empty when every factor is 1.
  const std::vector<double>& stiffening() const { return stiffening_; }

  /// The penalty with its activation distance replaced by `reach` (fold pairs).
  static QuadraticPenalty with_reach(QuadraticPenalty p, double reach) {
    p.eps = reach;
    return p;
  }
  /// The penalty with its activation distance replaced by `reach` (fold pairs).
  static CubicPenalty with_reach(CubicPenalty p, double reach) {
    p.eps = reach;
    return p;
  }
  /// The penalty with its activation distance replaced by `reach` (fold pairs).
  static LogBarrierPenalty with_reach(LogBarrierPenalty p, double reach) {
    p.dhat = reach;
    return p;
  }

  /// Per candidate: its settled side (signed length), or 0 while unknown.
  std::vector<signed char>& sides() { return sides_; }
  /// Per candidate: its settled side (signed length), or 0 while unknown.
  const std::vector<signed char>& sides() const { return sides_; }

  /// Signed length: a pair's side is fixed the first time the start of a step (a state the
  /// solver accepted) has the vertex over the face (the edges' closest points inside both)
  /// at a distance above rounding; until then it is unknown (0) and the pair is evaluated
  /// unsigned. Recording the side when the pair merely enters the candidate set would take
  /// it from the sign of l beside the face, where it means nothing (a sheet's own coplanar
  /// neighbours would get random sides and "penetrate" when the sheet folds).
  void settle_sides(const Eigen::Matrix3Xd& x) {
    const long n = static_cast<long>(candidates_->size());
#pragma omp parallel for schedule(dynamic, 256) if (n > 256)
    for (long k = 0; k < n; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      signed char& side = sides_[uk];
      if (side != 0 || candidates_->fold_pair(uk)) continue;
      const Vec12<double> xp = Geometry::gather(x, candidates_->vertices(uk));
      // (vertex-face: the foot of the vertex outside the triangle by more than the test's
      // slack rules out `inside` before a frame is built; most candidates are a sheet's own
      // neighbours, beside each other)
      if constexpr (VF)
        if (!Geometry::may_be_plane_active(xp, kAnyDistance)) continue;
      Frame<double> f;
      if (Kind::frame(xp, f) != Status::ok || !Geometry::inside(f) || !foot_consistent<Kind>(xp, f)) continue;
      if (std::abs(f.l) > 1e-3 * settings_->penalty.distance) side = f.l < 0 ? -1 : 1;
    }
  }

 private:
  /// Plane mode: the frame exists and is well conditioned (edges at least ~3° from
  /// parallel, PairGeometry::well_conditioned), the closest points of the plane (line)
  /// distance lie inside the primitives, and L = σ l is below `limit` and (signed) not
  /// deeper than 2d.
  bool plane_active(const Vec12<double>& xp, std::size_t k, double limit, Frame<double>& f, double& sigma) const {
    const double d = settings_->penalty.distance;
    if (!Geometry::may_be_plane_active(xp, std::max(limit, 2 * d))) return false;
    if (Kind::frame(xp, f) != Status::ok || !Geometry::inside(f) || !foot_consistent<Kind>(xp, f)) return false;
    if (!Geometry::well_conditioned(xp)) return false;
    const signed char side = settings_->signed_length ? sides_[k] : 0;
    sigma = side != 0 ? static_cast<double>(side) : (f.l < 0 ? -1.0 : 1.0);
    const double L = sigma * f.l;
    return L < limit && L >= -2 * d;
  }

  /// A reach that PairGeometry::may_be_plane_active's distance test never rejects (its
  /// square times a triangle's |n|² stays finite): what settle_sides passes to use the foot
  /// test alone.
  static constexpr double kAnyDistance = 1e150;

  const ContactSettings* settings_;
  const CandidateSet<VF>* candidates_;
  const RestAreas* areas_;
  std::vector<signed char> sides_;
  std::vector<double> stiffening_;
};

}  // namespace pce::sim::contact
