// SPDX-License-Identifier: MIT
/// @file
/// The candidate set of one self-contact effect (internal; docs/simulation.md §4.2): the
/// broad-phase query over a sweep, the fold pairs, the validity of the set and its
/// re-queries, and the per-pass filter that drops candidates which provably cannot be
/// active. It knows nothing of energies: the effect classifies and evaluates the pairs
/// (`activity.hpp`, `pair_potential.hpp`).
///
/// Validity: every pair that is not a candidate stays more than d apart while either of two
/// conditions holds.
///  (A) Sweep: the query grew each primitive's box over the sweep x0 → x1 by r = d + m, so a
///      non-candidate pair is more than r apart along some axis there; while every vertex
///      stays within m/2 of its own swept box on every axis (sweep_use ≤ 1), each
///      primitive's box grows by at most m/2, and the pair stays more than d apart.
///  (B) Relative drift: at x0 a non-candidate pair was more than r apart and at least the
///      gap G_AB between its two meshes' boxes; it stays more than d apart while its
///      relative drift is below the budget max(m, G_AB − d) (m within one mesh). With D the
///      drift from x0, c_A a mesh's mean drift and s_A = max_{i∈A}|Dᵢ − c_A|, a pair of
///      meshes A, B drifts relatively by at most
///          rel_AB(D) = s_A + s_B + |c_A − c_B|   (2 s_A within one mesh),
///      which ignores common translations (a sheet falling alone keeps its set).
/// With a step bound (a barrier or `ccd`), `step_limit` never lets both conditions fail:
/// before a Newton step that would leave the set, `cover` queries again over that step (so
/// the step is not cut short for the set's sake), and a set still valid at the start of the
/// next time step is kept (`begin_step`); the set is also queried again after a step that
/// the validity limit cut short (a step longer than `cover` sweeps), sweeping from there to
/// that step's Newton target. Without a step bound, every time step queries and a query
/// follows once both conditions have used half their budget.
#pragma once

#include "pair_geometry.hpp"
#include "util/stopwatch.hpp"

#include <pce/energy/closest_feature.hpp>
#include <pce/penalties/quadratic.hpp>
#include <pce/sim/broad_phase.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <type_traits>
#include <vector>

namespace pce::sim::contact {

template <bool VF> class CandidateSet {
  using Geometry = PairGeometry<VF>;

 public:
  using Pair = std::array<int, 2>;

  /// What the queries of one time step cost.
  struct QueryStats {
    double broad_phase_ms = 0, tree_ms = 0;
    int queries = 0;
  };

  /// `distance` d, the activation distance; `bounded`: the effect bounds its steps
  /// (validity is then kept by step_limit, and re-queries wait until the limit binds);
  /// `allowed`: M×M (M the model's meshes, symmetric), whether primitives of meshes a and b
  /// may be a candidate pair, or empty for every pair.
  CandidateSet(const Model& model, BroadPhaseKind kind, double distance, bool bounded, std::vector<char> allowed = {});

  /// Fold pairs are active below this fraction of their rest distance (and below d).
  static constexpr double kFoldReach = 0.5;

  std::size_t size() const { return pairs_.size(); }
  const std::vector<Pair>& pairs() const { return pairs_; }
  std::array<int, 4> vertices(std::size_t k) const { return Geometry::vertices(*model_, pairs_[k]); }
  /// Candidate k is a fold pair (one mesh, closer than 2d at rest); its activation distance.
  bool fold_pair(std::size_t k) const { return fold_pair_[k] != 0; }
  double fold_reach(std::size_t k) const { return fold_reach_[k]; }
  /// Fold pairs among the candidates.
  long fold_pairs() const { return static_cast<long>(std::count(fold_pair_.begin(), fold_pair_.end(), char(1))); }
  const QueryStats& stats() const { return stats_; }

  /// Starts a time step. With a step bound, a set that is still valid at x0 is kept (the
  /// step's cover queries again once a Newton step would leave it); otherwise one query over
  /// the sweep x0 → x1 (the effect sweeps from xⁿ to the inertial prediction), after which
  /// `previous[k]` is the index the new candidate k had before, or −1. Returns true when it
  /// queried.
  bool begin_step(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, std::vector<long>& previous);

  /// A query for this many vertices has been made (or restored), with its bounds.
  bool has_query(const Eigen::Matrix3Xd& x) const {
    return query_at_.cols() == x.cols() && query_lb_.size() == pairs_.size();
  }

  /// Whether the set still covers every pair within d at x (see the file comment).
  bool still_valid(const Eigen::Matrix3Xd& x) const;

  /// Queries again at x, over the sweep to the last step's Newton target.
  void refresh(const Eigen::Matrix3Xd& x, std::vector<long>& previous);

  /// Queries again at x alone (no sweep): afterwards every pair that is not a candidate is
  /// more than the query radius r = d + m apart at x (block descent's bounds).
  void query_at(const Eigen::Matrix3Xd& x, std::vector<long>& previous) {
    validity_bound_ = false;
    query(x, x, previous);
  }
  /// The query radius r = d + m: at the query's state, a pair that is not a candidate is
  /// farther apart.
  double query_radius() const { return distance_ + margin_; }

  /// Before a step: when the set does not stay valid along the whole step x → x + dx (a
  /// step_limit below 1), queries again over the sweep x → x + c dx, c = min(1, `reach` /
  /// max|dxᵢ|) (a step that moves a vertex by more than `reach` is covered only that far), so
  /// the step is not cut short for the set's sake. Returns true when it queried (then
  /// `previous` maps the new candidates to the former ones). Only with a step bound, or
  /// `always`.
  /// `always`: also without a step bound (block descent's first move).
  bool cover(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, double reach, std::vector<long>& previous,
             bool always = false);

  /// The largest t ∈ [0, 1] for which x + t dx keeps the set valid (the larger of the two
  /// conditions' limits, each where it holds at x); measures the drift (as measure_drift)
  /// and the step's reach (step_reach) for the step filter, and keeps x + dx as the target of
  /// a re-query.
  double step_limit(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx);

  /// Records the step limit's outcome: `t_valid` from step_limit, `t` the limit the effect
  /// returned; when the validity limit was the one that bound, the next still_valid says no.
  void record_step(double t_valid, double t) { validity_bound_ = t_valid < 1 && t >= t_valid; }

  /// drift_rel_[a·M + b] = rel_AB(x − query point) (validity_use's measure) and drift_ =
  /// x − query point: no pair of meshes A, B has moved relatively by more since the query,
  /// so a candidate's distance at x is at least its bound at the query minus this. Called
  /// once per pass, before the pair loop.
  void measure_drift(const Eigen::Matrix3Xd& x);

  /// The largest drift of the pair's vertices relative to each other since the query: max
  /// over i of the first primitive and j of the second of |Dᵢ − Dⱼ| (D = x − query point of
  /// the last measure_drift). The distance between the primitives has changed by at most
  /// this since the query.
  double pair_drift(const std::array<int, 4>& v) const { return relative_motion(drift_, v); }

  /// True when candidate k provably is farther than `limit` apart at the x of the last
  /// measure_drift: its lower bound at the query point, less how far its primitives can have
  /// closed in since (first the relative drift of its two meshes, one comparison; then the
  /// pair's own, pair_drift), is at least `limit`, each with a relative slack of 1e-9, far
  /// beyond rounding. A few flops instead of a frame or a distance, for every candidate that
  /// has not closed in (on the hammock, nearly all of them, fold pairs included).
  bool beyond(std::size_t k, double limit) const {
    if (query_lb_.size() != pairs_.size()) return false;
    const double room = query_lb_[k] - limit * (1 + 1e-9);
    if (room >= drift_rel_[static_cast<std::size_t>(mesh_pair_[k])] * (1 + 1e-9)) return true;
    if (!(room > 0)) return false;
    if (room >= drift_bound(k) * (1 + 1e-9)) return true;
    return room >= pair_drift(vertices(k)) * (1 + 1e-9);
  }

  /// An upper bound on pair_drift of candidate k from its primitives' spreads (no vertex
  /// read): with mᵢ the mean of a primitive's drifts and ρᵢ the largest distance of one of
  /// them from it, no vertex of the first moves relative to one of the second by more than
  /// ρ_a + ρ_b + |m_a − m_b|.
  double drift_bound(std::size_t k) const { return spread_bound(drift_first_, drift_second_, k); }

  /// An upper bound on the step's ma + mb for candidate k (max_step: the most its two
  /// primitives move relative to the mean p̄ of its four vertex displacements) from the
  /// primitives' spreads of the last step_limit's dx: with p̄ = (n_a m_a + n_b m_b)/4, a
  /// vertex of the first moves relative to p̄ by at most ρ_a + (n_b/4)|m_a − m_b|, one of the
  /// second by at most ρ_b + (n_a/4)|m_a − m_b|, and n_a + n_b = 4.
  double step_bound(std::size_t k) const { return spread_bound(step_first_, step_second_, k); }

  /// Tightens candidate k's bound at the query with a distance measured at the x of the last
  /// measure_drift: the distance at the query is at least `distance` less the pair's drift
  /// since (pair_drift) and less a rounding allowance of 64 ε max|x|, far beyond the error
  /// of a closest-feature distance. The passes call it where they measure a distance anyway,
  /// so a pair whose box-or-sphere bound is 0 (a sheet's close neighbours: their boxes
  /// overlap) costs one distance, not one per pass. Each pass writes only its own k.
  void tighten(std::size_t k, const std::array<int, 4>& v, double distance) const {
    if (query_lb_.size() != pairs_.size() || !std::isfinite(distance)) return;
    query_lb_[k] = std::max(query_lb_[k], distance - rounding_ - pair_drift(v));
  }

  /// The step bound's floor for these filters: the largest distance at which it stops a
  /// pressed pair (twice the largest minimum separation, with the rounding allowance; 0:
  /// none).
  void set_floor(double floor) { floor_ = floor; }
  /// How much closer a pair at a distance of at least `lb` may come in the first round of
  /// the step bound: 0.9 lb (it keeps a tenth), or, with a floor F (set_floor), 0.9 (lb − F)
  /// (the floor's own first round allows at least this for every distance ≥ lb).
  double clearance(double lb) const { return floor_ > 0 ? 0.9 * (lb - floor_) : 0.9 * lb; }

  /// Step filter, meshes only: candidate k cannot limit a step below `t_valid` (from the
  /// last step_limit): with lb its bound at the query, its distance at x is at least
  /// lb − rel_AB, and the step moves its primitives relative to their mean p̄ by at most
  /// ma + mb ≤ 2 W_AB (step_reach), so its own limit clearance(distance)/(ma + mb) ≥ t_valid.
  bool cannot_limit(std::size_t k, double t_valid) const {
    if (query_lb_.size() != pairs_.size()) return false;
    const auto mp = static_cast<std::size_t>(mesh_pair_[k]);
    return clearance(query_lb_[k] - drift_rel_[mp]) >= t_valid * 2 * step_reach_[mp] * (1 + 1e-9);
  }

  /// Segment filter, meshes only: candidate k stays farther apart than `limit` on the whole
  /// segment x + s dx, s ∈ [0, t] (x of the last measure_drift, dx of the last step_limit):
  /// its bound at the query, less the relative drift of its meshes since and the most the
  /// step moves its primitives relative to their mean (2 W_AB t), is at least `limit`, less
  /// an absolute `slack` and with relative slacks of 1e-9.
  bool stays_beyond(std::size_t k, double limit, double t, double slack) const {
    if (query_lb_.size() != pairs_.size()) return false;
    const auto mp = static_cast<std::size_t>(mesh_pair_[k]);
    return query_lb_[k] - limit * (1 + 1e-9) >= (drift_rel_[mp] + 2 * t * step_reach_[mp]) * (1 + 1e-9) + slack;
  }

  /// The bound beyond() starts from for candidate k with vertices v: its bound at the query
  /// less the pair's drift since (a lower bound on its distance at the x of the last
  /// measure_drift; −∞ before the query's bounds exist).
  double lower_bound(std::size_t k, const std::array<int, 4>& v) const {
    if (query_lb_.size() != pairs_.size()) return -std::numeric_limits<double>::infinity();
    return query_lb_[k] - pair_drift(v);
  }

  /// lower_bound without reading a vertex: the bound at the query less drift_bound.
  double primitive_lower_bound(std::size_t k) const {
    if (query_lb_.size() != pairs_.size()) return -std::numeric_limits<double>::infinity();
    return query_lb_[k] - drift_bound(k);
  }

  /// Step filter, the pair's own drift: candidate k with vertices v, whose primitives the
  /// step moves by ma + mb relative to their mean, cannot lower `t` (no vertex position read).
  bool cannot_lower(std::size_t k, const std::array<int, 4>& v, double motion, double t) const {
    return query_lb_.size() == pairs_.size() && clearance(query_lb_[k] - pair_drift(v)) >= t * motion * (1 + 1e-9);
  }

  /// Replaces the candidates with `pairs` (sorted; a checkpoint's), the fold pairs marked;
  /// the filter waits for the next query's bounds.
  void restore(std::vector<Pair> pairs);

  /// restore, and the query these pairs came from (a checkpoint's: its sweep `at` → `to` and
  /// whether the last step's validity limit bound), so the next begin_step decides as it
  /// would have in the uninterrupted run; the bounds are those of a fresh query at `at`.
  void restore(std::vector<Pair> pairs, const Eigen::Matrix3Xd& at, const Eigen::Matrix3Xd& to, bool validity_bound);

  /// The last query's sweep (x0 → x1; no columns before the first query) and whether the
  /// last step's validity limit bound: what a checkpoint keeps (restore).
  const Eigen::Matrix3Xd& query_to() const { return query_to_; }
  bool validity_bound() const { return validity_bound_; }

  /// The query's start state (the effect settles signed sides there).
  const Eigen::Matrix3Xd& query_point() const { return query_at_; }

 private:
  /// max over i of the first primitive and j of the second of |Dᵢ − Dⱼ|, D a displacement
  /// per vertex: how far the pair's primitives can have closed in under D.
  static double relative_motion(const Eigen::Matrix3Xd& D, const std::array<int, 4>& v) {
    constexpr int na = Geometry::first_side_count();
    double worst = 0;
    for (int i = 0; i < na; ++i)
      for (int j = na; j < 4; ++j)
        worst = std::max(worst,
                         (D.col(v[static_cast<std::size_t>(i)]) - D.col(v[static_cast<std::size_t>(j)])).squaredNorm());
    return std::sqrt(worst);
  }

  /// A primitive's displacements (3 × vertex count columns of some D): their mean and the
  /// largest distance of one of them from it.
  struct Spread {
    Eigen::Vector3d mean;
    double radius;
  };
  /// Per primitive of either side (vertices or edges, triangles or edges): its Spread under D.
  void spreads(const Eigen::Matrix3Xd& D, std::vector<Spread>& first, std::vector<Spread>& second) const;
  double spread_bound(const std::vector<Spread>& first, const std::vector<Spread>& second, std::size_t k) const {
    if (first.empty()) return std::numeric_limits<double>::infinity();
    const Spread& a = first[static_cast<std::size_t>(pairs_[k][0])];
    const Spread& b = (VF ? second : first)[static_cast<std::size_t>(pairs_[k][1])];
    return a.radius + b.radius + (a.mean - b.mean).norm();
  }

  /// Per mesh: the mean c_A of D's columns and s_A = max_{i∈A} |Dᵢ − c_A|.
  struct MeshDrift {
    std::vector<Eigen::Vector3d> c;
    std::vector<double> s;
  };
  MeshDrift mesh_drift(const Eigen::Matrix3Xd& D) const;
  static double relative(const MeshDrift& m, std::size_t a, std::size_t b) {
    return a == b ? 2 * m.s[a] : m.s[a] + m.s[b] + (m.c[a] - m.c[b]).norm();
  }
  /// Per pair of meshes, W_AB = max(2 s_A, 2 s_B, rel_AB(step)): no two vertices of a pair of
  /// primitives in A and B move by more than W_AB relative to each other, so neither moves
  /// by more than W_AB relative to their mean p̄ (the step bound's ma, mb).
  static std::vector<double> step_reach(const MeshDrift& step);
  /// max over mesh pairs of rel_AB(D)/budget_AB (≤ 1: condition B holds). With `step`, also
  /// lowers *t to the largest fraction of `step` that keeps every rel within its budget.
  double validity_use(const MeshDrift& now, const MeshDrift* step, double* t = nullptr) const;

  /// The largest t ∈ [0, 1] for which x + t dx keeps the set valid: the larger of the two
  /// conditions' limits, each where it holds at x (`step` = mesh_drift(dx)).
  double valid_fraction(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx, const MeshDrift& step) const;

  /// Half the margin, the room each vertex has beyond its swept box (condition A), less a
  /// relative 1e-6 for the rounding of positions and steps.
  double sweep_room() const { return 0.5 * margin_ * (1 - 1e-6); }

  /// max over vertices and axes of (how far xᵢ lies outside its swept box) / sweep_room():
  /// condition A holds while this is ≤ 1.
  double sweep_use(const Eigen::Matrix3Xd& x) const;

  /// The largest t ∈ [0, 1] for which x + t dx keeps every vertex within sweep_room() of its
  /// swept box on every axis (condition A along the step); 0 when x itself does not.
  double sweep_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) const;

  /// The query over the sweep x0 → x1 (x0 = x1: at one state): the candidates, each vertex's
  /// swept box (condition A), the gaps between the meshes' boxes at x0 (condition B), and
  /// every candidate's distance bound at x0 (the filter).
  void query(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, std::vector<long>& previous);

  /// Removes the (vertex, triangle) pairs whose vertex lies inside a volume
  /// (`Model::surface_vertex`: only a volume's surface takes part in contact) and the pairs
  /// of two meshes `allowed_` leaves out. Keeps the order (the broad phase's lists are sorted).
  void drop_excluded(std::vector<Pair>& pairs) const;

  /// The sweep of a query: its ends, each vertex's box over it (condition A) and the gaps
  /// between the meshes' boxes at x0 (condition B).
  void set_sweep(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1);

  /// Per candidate, at the query point: the distance lower bound (box or spheres; for a pair
  /// that was a candidate before, at least its former bound less how far its vertices moved
  /// relative to each other since the former query and the rounding allowance) and the
  /// index a·M + b (a ≤ b) of its two primitives' meshes; what beyond and the step filter
  /// read.
  void bound_at_query(const std::vector<long>& previous);

  /// The same-mesh pairs whose primitives are closer than 2d in the rest shape (a sheet's
  /// neighbours one or two rings apart), sorted, with their reach min(d, kFoldReach · D₀):
  /// once per effect, by a rest-shape query of radius 2d filtered by the exact distance D₀.
  void find_fold_pairs();

  /// fold_pair_[k]: candidate k is a fold pair, with its reach (one merge pass of two sorted lists).
  void mark_fold_pairs();

  const Model* model_;
  std::unique_ptr<BroadPhase> broad_phase_;
  double distance_;                       ///< d
  const double margin_;                   ///< the margin m = d/2 of the query radius r = d + m
  bool bounded_;                          ///< the effect bounds its steps (validity kept by step_limit)
  std::vector<int> mesh_of_;              ///< per vertex: its mesh
  std::vector<char> allowed_;             ///< M×M: meshes whose primitives may pair; empty: all
  std::vector<Pair> pairs_;               ///< the candidates, sorted
  std::vector<Pair> folds_;               ///< same-mesh pairs closer than 2d at rest, sorted
  std::vector<double> fold_reaches_;      ///< per entry of folds_: min(d, kFoldReach · rest distance)
  std::vector<char> fold_pair_;           ///< per candidate: it is a fold pair
  std::vector<double> fold_reach_;        ///< per candidate: its fold reach, else 0
  Eigen::Matrix3Xd query_at_, query_to_;  ///< the last query's sweep x0 → x1
  Eigen::Matrix3Xd sweep_lo_, sweep_hi_;  ///< per vertex: its box over the sweep (condition A)
  std::vector<double> gaps_;              ///< M×M (upper part): gap between meshes' boxes at x0
  Eigen::Matrix3Xd target_;               ///< x + dx of the last step_limit: where a re-query sweeps to
  bool validity_bound_ = false;           ///< the last step's limit was the validity limit
  /// Per candidate: distance lower bound at x0 (box or spheres at the query, tightened by
  /// distances the passes measure: a cache of a bound, hence mutable).
  mutable std::vector<double> query_lb_;
  double rounding_ = 0;                             ///< 64 ε max|x| of the last measure_drift (or query)
  double floor_ = 0;                                ///< the step bound's largest floor with its allowance (set_floor)
  std::vector<double> former_lb_;                   ///< during a query: the former candidates' bounds
  Eigen::Matrix3Xd moved_;                          ///< during a query: new query point − former query point
  std::vector<int> mesh_pair_;                      ///< per candidate: a·M + b of its meshes (a ≤ b)
  Eigen::Matrix3Xd drift_;                          ///< x − x0 of the last measure_drift
  std::vector<double> drift_rel_;                   ///< rel_AB(drift_), indexed a·M + b
  std::vector<double> step_reach_;                  ///< W_AB of the last step_limit, indexed a·M + b
  std::vector<Spread> drift_first_, drift_second_;  ///< per primitive: Spread of drift_ (second empty for edges)
  std::vector<Spread> step_first_, step_second_;    ///< per primitive: Spread of the last step_limit's dx
  QueryStats stats_;
};

}  // namespace pce::sim::contact
