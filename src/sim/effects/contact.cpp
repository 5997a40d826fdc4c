// SPDX-License-Identifier: MIT
// Self contact through pce's pair energies: the effects `self_vertex_face` and
// `self_edge_edge` (docs/simulation.md, "From candidates to energies").
//
// Per time step: the broad phase finds the candidate pairs within the query radius
// r = d + m (activation distance d, margin m = d) around the inertial prediction
// x̃ = xⁿ + h vⁿ; the candidate set then stays fixed while every vertex stays within m/2 of
// where it was queried (checked after each Newton update, re-queried otherwise), so any pair
// that comes within d of contact is in the set. Only pairs that share a vertex are never
// candidates. Fold pairs, of one mesh and closer than 2d at rest (distance D₀: a sheet's
// neighbours one or two rings apart), are evaluated by closest features with the activation
// distance min(d, D₀/2): no force at rest or in a smooth bend, a continuous repulsion in a
// tight fold; with every other candidate they are in the step bound, so no pair that does
// not share a vertex can cross during a step. Per Newton iteration every other candidate is
// evaluated by pce:
//  * plane mode (the paper's): the frame of the pair; the pair is active when the closest
//    points of the plane (line) distance lie inside the triangle (both segments) and
//    L < d, with L = |l| (unsigned) or L = side·l (signed: the side is settled from the
//    first step start with the vertex over the face, and kept while the pair stays a
//    candidate);
//  * closest-feature mode: pce::closest_feature_energy, the distance between the primitives.
// The Hessian is pce's projection chosen per effect (`hessian`). Pairs are evaluated in
// parallel (OpenMP) into per-pair buffers and scattered serially into the block Hessian.
#include "penalty_spec.hpp"

#include <pce/energy/closest_feature.hpp>
#include <pce/energy/pair_energy.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/sim/instrumentation.hpp>

#include <Eigen/Geometry>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>

namespace pce::sim {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

/// An active pair's result of one evaluation (k its candidate index). Kept per thread, for
/// active pairs only, so the serial pass that sums and scatters touches those alone (a
/// record per candidate made it sweep ~100 MB per evaluation on the hammock).
struct PairOut {
  long k = 0;
  double energy = 0;
  double length = std::numeric_limits<double>::infinity();
  bool active = false;
  Vec12<double> g;
};

/// The Hessian of an active pair (k its candidate index). Kept per thread, for active pairs
/// only: a 12×12 block per candidate would cost ~1 KiB each (0.7 GB for the hammock's
/// candidates).
struct PairHessian {
  long k;
  Mat12<double> H;
};

template <bool VF> class SelfContact final : public Effect {
 public:
  SelfContact(const ContactSettings& spec, const Model& model)
      : spec_(spec), model_(&model), broad_phase_(make_broad_phase(spec.broad_phase)) {
    mesh_of_.resize(static_cast<std::size_t>(model_->vertex_count()));
    for (std::size_t m = 0; m < model_->meshes.size(); ++m)
      for (int i = 0; i < model_->meshes[m].vertex_count; ++i)
        mesh_of_[static_cast<std::size_t>(model_->meshes[m].first_vertex + i)] = static_cast<int>(m);
    find_rest_neighbours();
  }

  const char* name() const override { return VF ? "self_vertex_face" : "self_edge_edge"; }

  void begin_step(const StepContext& ctx) override {
    x_start_ = ctx.x_start;
    // One query over the sweep from xⁿ to the inertial prediction x̃ = xⁿ + h vⁿ: the
    // iterates of most steps stay within (or within m/2 of) the boxes that sweep spans, so
    // the set serves the whole step. Margin m = d.
    margin_ = spec_.penalty.distance;
    set_query_point(*ctx.x_start, *ctx.x_start + ctx.dt * *ctx.v_start);
    target_.resize(3, 0);
    validity_bound_ = false;
    stats_ = {};
    query();
  }

  /// Validity of the candidate set (docs/simulation.md §4.2): every pair that is not a
  /// candidate stays more than d apart while either of two conditions holds.
  ///  (A) Sweep: the query grew each primitive's box over the sweep x0 → x1 by r = d + m,
  ///      so a non-candidate pair is more than r apart along some axis there; while every
  ///      vertex stays within m/2 of its own swept box on every axis (sweep_use ≤ 1), each
  ///      primitive's box grows by at most m/2, and the pair stays more than d apart.
  ///  (B) Relative drift: at x0 a non-candidate pair was more than r apart and at least the
  ///      gap G_AB between its two meshes' boxes; it stays more than d apart while its
  ///      relative drift is below the budget max(m, G_AB − d) (m within one mesh). With D
  ///      the drift from x0, c_A a mesh's mean drift and s_A = max_{i∈A}|Dᵢ − c_A|, a pair
  ///      of meshes A, B drifts relatively by at most
  ///          rel_AB(D) = s_A + s_B + |c_A − c_B|   (2 s_A within one mesh),
  ///      which ignores common translations (a sheet falling alone keeps its set).
  /// With a step bound (barrier or `ccd`), max_step never lets both conditions fail, and the
  /// set is queried again only after a step that the validity limit cut short (the bound
  /// bound), sweeping from there to that step's Newton target. Without one, a query follows
  /// once both conditions have used half their budget.
  bool still_valid(const Eigen::Matrix3Xd& x) override {
    if (validity_bound_) return false;
    const double limit = spec_.penalty.barrier() || spec_.ccd ? 1.0 : 0.5;
    return sweep_use(x) <= limit || validity_use(mesh_drift(x - query_at_), nullptr) <= limit;
  }

  void refresh(const Eigen::Matrix3Xd& x) override {
    set_query_point(x, target_.cols() == x.cols() ? target_ : x);
    validity_bound_ = false;
    query();
  }

  void declare(Pattern& pattern) const override {
    for (std::size_t k = 0; k < pairs_.size(); ++k)
      if (declared_[k]) pattern.add(vertices(pairs_[k]));
  }

  bool update_pattern(const Eigen::Matrix3Xd& x) override {
    // Exactly the pairs active at x (those whose Hessian evaluate() adds) couple their
    // vertices. Declaring more (pairs that were near activation at some earlier iterate)
    // multiplies the factorisation's fill-in: on the hammock, 65 k declared pairs for 3 k
    // active ones made L 4.9 M non-zeros and each factorisation 0.5 s.
    const long n = static_cast<long>(pairs_.size());
    if (near_.size() < pairs_.size()) near_.resize(pairs_.size());
    measure_drift(x);
#pragma omp parallel for schedule(static)
    for (long k = 0; k < n; ++k) near_[static_cast<std::size_t>(k)] = is_active(x, k);
    bool changed = false;
    for (std::size_t k = 0; k < pairs_.size(); ++k)
      if (near_[k] != declared_[k]) declared_[k] = near_[k], changed = true;
    return changed;
  }

  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    const auto t0 = Clock::now();
    const bool want_h = hessian != nullptr;
    const long n = static_cast<long>(pairs_.size());
    const auto threads = static_cast<std::size_t>(omp_get_max_threads());
    hessians_.resize(threads);
    actives_.resize(threads);
    measure_drift(x);
    visit_penalty(spec_.penalty, [&](const auto& penalty) {
#pragma omp parallel
      {
        const auto me = static_cast<std::size_t>(omp_get_thread_num());
        std::vector<PairHessian>& my_hessians = hessians_[me];
        std::vector<PairOut>& my_actives = actives_[me];
        my_hessians.clear();
        my_actives.clear();
        // static schedule: thread t owns one contiguous range of k, so reading the threads'
        // lists in thread order visits the active pairs in k order (sums and scatter are
        // the same, bit for bit, whatever the thread count)
#pragma omp for schedule(static)
        for (long k = 0; k < n; ++k) {
          PairOut o;
          evaluate_pair(x, k, penalty, want_h ? &my_hessians : nullptr, o);
          if (o.active) {
            o.k = k;
            my_actives.push_back(o);
          }
        }
      }
    });
    (VF ? instrumentation().vertex_face_pairs_evaluated : instrumentation().edge_edge_pairs_evaluated) += n;
    stats_.pair_ms += ms_since(t0);
    const auto t1 = Clock::now();
    double energy = 0;
    long active = 0, fold_active = 0;
    double min_length = std::numeric_limits<double>::infinity();
    for (const auto& list : actives_)
      for (const PairOut& o : list) {
        ++active;
        fold_active += fold_pair_[static_cast<std::size_t>(o.k)];
        energy += o.energy;
        min_length = std::min(min_length, o.length);
        if (!std::isfinite(o.energy)) continue;  // a barrier at distance 0: E = ∞, nothing to add
        const auto v = vertices(pairs_[static_cast<std::size_t>(o.k)]);
        if (gradient)
          for (int j = 0; j < 4; ++j) gradient->col(v[static_cast<std::size_t>(j)]) += o.g.segment<3>(3 * j);
      }
    if (hessian)
      for (const auto& list : hessians_)
        for (const PairHessian& ph : list) hessian->add<4>(vertices(pairs_[static_cast<std::size_t>(ph.k)]), ph.H);
    stats_.scatter_ms += ms_since(t1);
    stats_.active = active;
    stats_.fold_active = fold_active;
    stats_.min_length = min_length;
    if (!std::isfinite(energy)) return std::numeric_limits<double>::infinity();
    return energy;
  }

  double max_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override {
    if (!spec_.penalty.barrier() && !spec_.ccd) return 1.0;
    // Conservative advancement (the additive-CCD bound, Li et al. 2021): the distance is
    // unchanged by a common translation, so with p̄ the mean of the pair's four vertex
    // displacements, along x + t dx the distance between the primitives changes by at most
    // t (max |dxᵢ − p̄| over the first's vertices + max |dxⱼ − p̄| over the second's); keep
    // 10 % of every candidate's current distance (closest features), so no candidate pair
    // can cross during the step. (Without p̄, strands falling side by side limited each
    // other's step to ~6 % for twenty iterations.)
    // The step also keeps the candidate set valid (still_valid), so no other pair can come
    // within d either: rel_AB(D + t dx) ≤ rel_AB(D) + t rel_AB(dx) for every pair of
    // meshes. (Bounding the candidates alone let a landing sheet cross faces that were not
    // candidates.)
    const MeshDrift step = mesh_drift(dx);
    double t_drift = 1.0;
    const bool drift_valid = validity_use(mesh_drift(x - query_at_), &step, &t_drift) <= 1;
    const double t_valid = std::max(drift_valid ? t_drift : 0.0, sweep_step(x, dx));
    target_ = x + dx;
    double t = t_valid;  // (inside the loop, t is a thread's own minimum, which starts at +∞)
    // Pairs whose distance provably stays above what t_valid allows are skipped before
    // their vertices are read: with lb the lower bound at the query point, the distance at
    // x is at least lb − rel_AB(x − query point), and a step moves the pair's two
    // primitives relative to p̄ by at most ma + mb ≤ 2 W_AB (step_reach), so its own limit
    // 0.9 · distance/(ma + mb) is at least t_valid (1e-9: beyond rounding).
    measure_drift(x);
    const std::vector<double> reach = step_reach(step);
    const bool filter = query_lb_.size() == pairs_.size();
    const long n = static_cast<long>(pairs_.size());
#pragma omp parallel for schedule(static) reduction(min : t)
    for (long k = 0; k < n; ++k) {
      if (filter) {
        const auto uk = static_cast<std::size_t>(k);
        const int mp = mesh_pair_[uk];
        if (0.9 * (query_lb_[uk] - drift_rel_[static_cast<std::size_t>(mp)]) >=
            t_valid * 2 * reach[static_cast<std::size_t>(mp)] * (1 + 1e-9))
          continue;
      }
      const auto v = vertices(pairs_[static_cast<std::size_t>(k)]);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int j = 0; j < 4; ++j) mean += dx.col(v[static_cast<std::size_t>(j)]);
      mean *= 0.25;
      double ma = 0, mb = 0;  // largest motion on each primitive relative to p̄
      for (int j = 0; j < 4; ++j) {
        const double d = (dx.col(v[static_cast<std::size_t>(j)]) - mean).norm();
        double& m = j < first_side_count() ? ma : mb;
        m = std::max(m, d);
      }
      if (!(ma + mb > 0)) continue;
      // The same test with the query's bound less the pair's drift since (no vertex read).
      if (filter && 0.9 * (query_lb_[static_cast<std::size_t>(k)] - pair_drift(v)) >=
                        std::min(t, t_valid) * (ma + mb) * (1 + 1e-9))
        continue;
      const Vec12<double> xp = gather(x, v);
      // The distance is at least distance_lower_bound, so a pair whose bound already allows the
      // smaller of this thread's minimum and the validity bound cannot lower the result:
      // it is the same without the pair's distance.
      if (0.9 * distance_lower_bound(xp) >= std::min(t, t_valid) * (ma + mb)) continue;
      ClosestFeatureEnergy<double> ce;
      const QuadraticPenalty probe{1.0, 0.0};
      if (closest_feature_energy<Kind>(xp, UnsignedLength{}, probe, ce) != Status::ok) continue;
      t = std::min(t, 0.9 * ce.length / (ma + mb));
    }
    validity_bound_ = t_valid < 1 && t >= t_valid;
    return std::max(t, 0.0);
  }

  void report(EffectCounters& c) const override {
    const std::string kind = VF ? "vertex_face" : "edge_edge";
    c[kind + "_candidates"] = static_cast<double>(pairs_.size());
    c[kind + "_declared"] = static_cast<double>(std::count(declared_.begin(), declared_.end(), char(1)));
    c[kind + "_rest_neighbours"] = static_cast<double>(std::count(fold_pair_.begin(), fold_pair_.end(), char(1)));
    c[kind + "_fold_contacts"] = static_cast<double>(stats_.fold_active);
    c[kind + "_contacts"] = static_cast<double>(stats_.active);
    c[kind + "_min_distance"] = stats_.min_length;
    c["broad_phase_ms"] = stats_.broad_phase_ms;
    c["broad_phase_tree_ms"] = stats_.tree_ms;
    c["broad_phase_queries"] = stats_.queries;
    c["pair_ms"] = stats_.pair_ms;
    c["scatter_ms"] = stats_.scatter_ms;
  }

  /// The tracked pairs with their sides and declarations: what the next begin_step keeps
  /// (query() merges the fresh candidates with them). Per pair: two int32 indices, the side
  /// and the declaration as int8; native byte order.
  std::string save_state() const override {
    std::string out;
    const std::uint64_t count = pairs_.size();
    out.append(reinterpret_cast<const char*>(&count), sizeof count);
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      const std::int32_t ab[2] = {pairs_[k][0], pairs_[k][1]};
      const signed char flags[2] = {sides_[k], static_cast<signed char>(declared_[k])};
      out.append(reinterpret_cast<const char*>(ab), sizeof ab);
      out.append(reinterpret_cast<const char*>(flags), sizeof flags);
    }
    return out;
  }

  void load_state(const std::string& state) override {
    constexpr std::size_t record = 2 * sizeof(std::int32_t) + 2;
    std::uint64_t count = 0;
    if (state.size() < sizeof count) throw std::invalid_argument(std::string(name()) + ": truncated state");
    std::memcpy(&count, state.data(), sizeof count);
    if (count > (state.size() - sizeof count) / record || state.size() != sizeof count + count * record)
      throw std::invalid_argument(std::string(name()) + ": the state's size does not match its pair count");
    const long first_max = VF ? model_->vertex_count() : model_->edges.cols();
    const long second_max = VF ? model_->triangles.cols() : model_->edges.cols();
    std::vector<std::array<int, 2>> pairs(count);
    std::vector<signed char> sides(count);
    std::vector<char> declared(count);
    const char* p = state.data() + sizeof count;
    for (std::size_t k = 0; k < count; ++k, p += record) {
      std::int32_t ab[2];
      signed char flags[2];
      std::memcpy(ab, p, sizeof ab);
      std::memcpy(flags, p + sizeof ab, sizeof flags);
      if (ab[0] < 0 || ab[0] >= first_max || ab[1] < 0 || ab[1] >= second_max || flags[0] < -1 || flags[0] > 1 ||
          flags[1] < 0 || flags[1] > 1 || (k > 0 && !(pairs[k - 1] < std::array<int, 2>{ab[0], ab[1]})))
        throw std::invalid_argument(std::string(name()) + ": pair " + std::to_string(k) +
                                    " of the saved state does not fit this model");
      pairs[k] = {ab[0], ab[1]};
      sides[k] = flags[0];
      declared[k] = flags[1];
    }
    pairs_ = std::move(pairs);
    sides_ = std::move(sides);
    declared_ = std::move(declared);
    mark_rest_neighbours();
    query_lb_.clear();  // no filter until the next query measures the bounds
  }

 private:
  using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;
  static constexpr int first_side_count() { return VF ? 1 : 2; }

  double margin() const { return margin_; }

  std::array<int, 4> vertices(const std::array<int, 2>& c) const {
    if constexpr (VF) {
      const auto t = model_->triangles.col(c[1]);
      return {c[0], t[0], t[1], t[2]};
    } else {
      const auto a = model_->edges.col(c[0]), b = model_->edges.col(c[1]);
      return {a[0], a[1], b[0], b[1]};
    }
  }

  static Vec12<double> gather(const Eigen::Matrix3Xd& x, const std::array<int, 4>& v) {
    Vec12<double> xp;
    for (int j = 0; j < 4; ++j) xp.segment<3>(3 * j) = x.col(v[static_cast<std::size_t>(j)]);
    return xp;
  }

  /// A lower bound on the distance between the pair's two primitives: the distance between
  /// their axis-aligned boxes (each primitive lies in its box). A few comparisons, against
  /// a frame or a closest-feature evaluation; it lets every pass skip the candidates that
  /// provably cannot be active or limit a step.
  static double box_gap(const Vec12<double>& xp) {
    constexpr int na = first_side_count();
    Eigen::Vector3d alo = xp.segment<3>(0), ahi = alo, blo = xp.segment<3>(3 * na), bhi = blo;
    for (int j = 1; j < na; ++j) {
      alo = alo.cwiseMin(xp.segment<3>(3 * j));
      ahi = ahi.cwiseMax(xp.segment<3>(3 * j));
    }
    for (int j = na + 1; j < 4; ++j) {
      blo = blo.cwiseMin(xp.segment<3>(3 * j));
      bhi = bhi.cwiseMax(xp.segment<3>(3 * j));
    }
    return (blo - ahi).cwiseMax(alo - bhi).cwiseMax(0.0).norm();
  }

  /// Pairs whose primitives are farther apart than this are inactive in every mode: the
  /// activation distance d, or 2d for signed plane mode (a pair counts down to L = −2d).
  double inactive_beyond() const {
    return (spec_.signed_length && !spec_.closest_features ? 2.0 : 1.0) * spec_.penalty.distance;
  }

  /// Per mesh: the mean c_A of D's columns and s_A = max_{i∈A} |Dᵢ − c_A|.
  struct MeshDrift {
    std::vector<Eigen::Vector3d> c;
    std::vector<double> s;
  };
  MeshDrift mesh_drift(const Eigen::Matrix3Xd& D) const {
    MeshDrift m;
    for (const MeshRange& r : model_->meshes) {
      const auto block = D.middleCols(r.first_vertex, r.vertex_count);
      const Eigen::Vector3d c = block.rowwise().mean();
      m.c.push_back(c);
      m.s.push_back((block.colwise() - c).colwise().norm().maxCoeff());
    }
    return m;
  }
  static double relative(const MeshDrift& m, std::size_t a, std::size_t b) {
    return a == b ? 2 * m.s[a] : m.s[a] + m.s[b] + (m.c[a] - m.c[b]).norm();
  }
  /// max over mesh pairs of rel_AB(D)/budget_AB (≤ 1: valid). With `step`, also lowers *t
  /// to the largest fraction of `step` that keeps every rel within its budget.
  double validity_use(const MeshDrift& now, const MeshDrift* step, double* t = nullptr) const {
    double use = 0;
    const std::size_t M = now.s.size();
    for (std::size_t a = 0; a < M; ++a)
      for (std::size_t b = a; b < M; ++b) {
        const double budget = std::max(margin(), gaps_[a * M + b] - spec_.penalty.distance);
        const double rel = relative(now, a, b);
        use = std::max(use, rel / budget);
        if (step && t) {
          const double moving = relative(*step, a, b);
          if (moving > 0) *t = std::min(*t, std::max(0.0, budget - rel) / moving);
        }
      }
    return use;
  }
  /// Half the margin, the room each vertex has beyond its swept box (condition A), less a
  /// relative 1e-6 for the rounding of positions and steps.
  double sweep_room() const { return 0.5 * margin() * (1 - 1e-6); }

  /// max over vertices and axes of (how far xᵢ lies outside its swept box) / sweep_room():
  /// condition A holds while this is ≤ 1.
  double sweep_use(const Eigen::Matrix3Xd& x) const {
    const double outside = (sweep_lo_ - x).cwiseMax(x - sweep_hi_).maxCoeff();
    return std::max(outside, 0.0) / sweep_room();
  }

  /// The largest t ∈ [0, 1] for which x + t dx keeps every vertex within sweep_room() of its
  /// swept box on every axis (condition A along the step); 0 when x itself does not.
  double sweep_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) const {
    if (sweep_use(x) > 1) return 0.0;
    const double room = sweep_room();
    double t = 1.0;
    for (Eigen::Index i = 0; i < x.cols(); ++i)
      for (int c = 0; c < 3; ++c) {
        const double d = dx(c, i);
        if (d > 0)
          t = std::min(t, (sweep_hi_(c, i) + room - x(c, i)) / d);
        else if (d < 0)
          t = std::min(t, (sweep_lo_(c, i) - room - x(c, i)) / d);
      }
    return std::max(t, 0.0);
  }

  /// Makes the sweep x0 → x1 the next query's (x0 = x1: a query at one state), keeps each
  /// vertex's swept box (condition A) and measures the gaps between the meshes' boxes at x0
  /// (condition B).
  void set_query_point(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& x1) {
    query_at_ = x;
    query_to_ = x1;
    sweep_lo_ = x.cwiseMin(x1);
    sweep_hi_ = x.cwiseMax(x1);
    const std::size_t M = model_->meshes.size();
    std::vector<Eigen::AlignedBox3d> boxes(M);
    for (std::size_t a = 0; a < M; ++a) {
      const MeshRange& r = model_->meshes[a];
      const auto block = x.middleCols(r.first_vertex, r.vertex_count);
      boxes[a] = Eigen::AlignedBox3d(block.rowwise().minCoeff(), block.rowwise().maxCoeff());
    }
    gaps_.assign(M * M, 0.0);
    for (std::size_t a = 0; a < M; ++a)
      for (std::size_t b = a + 1; b < M; ++b) gaps_[a * M + b] = std::sqrt(boxes[a].squaredExteriorDistance(boxes[b]));
  }

  static bool inside(const Frame<double>& f) {
    if constexpr (VF)
      return f.beta >= 0 && f.gamma >= 0 && f.beta + f.gamma <= 1;
    else
      return f.beta >= 0 && f.beta <= 1 && f.gamma <= 0 && f.gamma >= -1;
  }

  void query_pairs(const Eigen::Matrix3Xd& x, std::vector<std::array<int, 2>>& out) {
    const double r = spec_.penalty.distance + margin();
    if constexpr (VF)
      broad_phase_->vertex_face(x, query_to_, model_->triangles, r, out);
    else
      broad_phase_->edge_edge(x, query_to_, model_->edges, r, out);
  }

  void query() {
    const auto t0 = Clock::now();
    std::vector<std::array<int, 2>> fresh;
    const auto t_tree = Clock::now();
    query_pairs(query_at_, fresh);
    stats_.tree_ms += ms_since(t_tree);
    // Pairs already tracked keep their side and their declaration (until the next
    // update_pattern); new pairs get their side from xⁿ. Both lists are sorted: one merge
    // pass.
    std::vector<signed char> sides(fresh.size(), 0);
    std::vector<char> declared(fresh.size(), 0);
    std::size_t old = 0;
    for (std::size_t k = 0; k < fresh.size(); ++k) {
      while (old < pairs_.size() && pairs_[old] < fresh[k]) ++old;
      if (old < pairs_.size() && pairs_[old] == fresh[k]) {
        sides[k] = sides_[old];
        declared[k] = declared_[old];
      }
    }
    pairs_ = std::move(fresh);
    sides_ = std::move(sides);
    declared_ = std::move(declared);
    mark_rest_neighbours();
    bound_at_query();
    if (spec_.signed_length) settle_sides(*x_start_);
    stats_.queries += 1;
    ++instrumentation().broad_phase_queries;
    stats_.broad_phase_ms += ms_since(t0);
  }

  /// The same-mesh pairs whose primitives are closer than the query radius r = 2d in the
  /// rest shape (a sheet's neighbours one or two rings apart), sorted: once per effect, by a
  /// rest-shape query of radius r filtered by the exact distance.
  void find_rest_neighbours() {
    std::vector<int> mesh_of(static_cast<std::size_t>(model_->vertex_count()));
    for (std::size_t m = 0; m < model_->meshes.size(); ++m)
      for (int i = 0; i < model_->meshes[m].vertex_count; ++i)
        mesh_of[static_cast<std::size_t>(model_->meshes[m].first_vertex + i)] = static_cast<int>(m);
    const double r = 2 * spec_.penalty.distance;
    std::vector<std::array<int, 2>> rest_pairs;
    if constexpr (VF)
      broad_phase_->vertex_face(model_->rest, model_->triangles, r, rest_pairs);
    else
      broad_phase_->edge_edge(model_->rest, model_->edges, r, rest_pairs);
    const long n = static_cast<long>(rest_pairs.size());
    std::vector<char> near(rest_pairs.size(), 0);
    std::vector<double> rest_distance(rest_pairs.size(), 0.0);
#pragma omp parallel for schedule(static)
    for (long k = 0; k < n; ++k) {
      const auto v = vertices(rest_pairs[static_cast<std::size_t>(k)]);
      if (mesh_of[static_cast<std::size_t>(v[0])] != mesh_of[static_cast<std::size_t>(v[3])]) continue;
      const Vec12<double> rest = gather(model_->rest, v);
      if (distance_lower_bound(rest) >= r) continue;
      ClosestFeatureEnergy<double> ce;
      const Status st = closest_feature_energy<Kind>(rest, UnsignedLength{}, QuadraticPenalty{1.0, 0.0}, ce);
      near[static_cast<std::size_t>(k)] = st != Status::ok || ce.length < r;
      rest_distance[static_cast<std::size_t>(k)] = st == Status::ok ? ce.length : 0.0;
    }
    rest_neighbours_.clear();
    rest_reach_.clear();
    for (std::size_t k = 0; k < rest_pairs.size(); ++k)
      if (near[k]) {
        rest_neighbours_.push_back(rest_pairs[k]);
        rest_reach_.push_back(std::min(spec_.penalty.distance, kFoldReach * rest_distance[k]));
      }
  }

  /// fold_pair_[k]: candidate k is a fold pair, with its reach (one merge pass of two sorted lists).
  void mark_rest_neighbours() {
    fold_pair_.assign(pairs_.size(), 0);
    fold_reach_.assign(pairs_.size(), 0.0);
    std::size_t j = 0;
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      while (j < rest_neighbours_.size() && rest_neighbours_[j] < pairs_[k]) ++j;
      fold_pair_[k] = j < rest_neighbours_.size() && rest_neighbours_[j] == pairs_[k];
      if (fold_pair_[k]) fold_reach_[k] = rest_reach_[j];
    }
  }

  template <class Penalty> void evaluate_pair(const Eigen::Matrix3Xd& x, long k, const Penalty& penalty,
                                              std::vector<PairHessian>* hessians, PairOut& o) const {
    o.active = false;
    if (cannot_be_active(k)) return;
    const auto v = vertices(pairs_[static_cast<std::size_t>(k)]);
    const Vec12<double> xp = gather(x, v);
    const double d = spec_.penalty.distance;
    if (fold_pair_[static_cast<std::size_t>(k)]) {
      // A fold pair: the closest-feature distance against its own reach.
      const double reach = fold_reach_[static_cast<std::size_t>(k)];
      if (!(reach > 0) || distance_lower_bound(xp) >= reach) return;
      return closest_pair(xp, k, with_reach(penalty, reach), reach, hessians, o);
    }
    if (box_gap(xp) > inactive_beyond()) return;
    if (spec_.closest_features) return closest_pair(xp, k, penalty, d, hessians, o);
    Frame<double> f;
    double sigma = 1;
    if (!plane_active(xp, k, d, f, sigma)) return;
    // pair_energy's result from the frame already built (signed with the side σ, or the
    // unsigned length, whose σ = sgn l is the same number): no second frame.
    PairEnergy<double> e;
    e.frame = f;
    e.sigma = sigma;
    e.length = sigma * f.l;
    const Status s = detail::evaluate_penalty(penalty, e.length, e.psi);
    if (s == Status::out_of_domain) return fail_infinite(o);
    if (s != Status::ok) return;
    o.active = true;
    o.length = e.length;
    o.energy = e.psi.value;
    o.g = energy_gradient(e);
    if (hessians) hessians->push_back({k, projected_hessian(e, spec_.hessian)});
  }

  /// Closest-feature evaluation of candidate k: active when the distance is below `limit`.
  template <class Penalty> void closest_pair(const Vec12<double>& xp, long k, const Penalty& penalty, double limit,
                                             std::vector<PairHessian>* hessians, PairOut& o) const {
    ClosestFeatureEnergy<double> ce;
    const Status s = closest_feature_energy<Kind>(xp, UnsignedLength{}, penalty, ce);
    // A barrier at distance 0 (out of its domain, or a point kind's `degenerate`, which
    // is reported only at distance exactly 0) is infinite energy.
    if (s == Status::out_of_domain || (s == Status::degenerate && spec_.penalty.barrier())) return fail_infinite(o);
    if (s != Status::ok || !(ce.length < limit)) return;
    o.active = true;
    o.length = ce.length;
    o.energy = ce.psi.value;
    o.g = energy_gradient(ce);
    if (hessians) hessians->push_back({k, projected_hessian(ce, spec_.hessian)});
  }

  /// The effect's penalty with its activation distance replaced by `reach` (fold pairs).
  static QuadraticPenalty with_reach(QuadraticPenalty p, double reach) {
    p.eps = reach;
    return p;
  }
  static CubicPenalty with_reach(CubicPenalty p, double reach) {
    p.eps = reach;
    return p;
  }
  static LogBarrierPenalty with_reach(LogBarrierPenalty p, double reach) {
    p.dhat = reach;
    return p;
  }

  /// Signed length: a pair's side is fixed the first time the start of a step (a state the
  /// solver accepted) has the vertex over the face (the edges' closest points inside both)
  /// at a distance above rounding; until then it is unknown (0) and the pair is evaluated
  /// unsigned. Recording the side when the pair merely enters the candidate set would
  /// take it from the sign of l beside the face, where it means nothing (a sheet's own
  /// coplanar neighbours would get random sides and "penetrate" when the sheet folds).
  void settle_sides(const Eigen::Matrix3Xd& x) {
    const long n = static_cast<long>(pairs_.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (long k = 0; k < n; ++k) {
      signed char& side = sides_[static_cast<std::size_t>(k)];
      if (side != 0 || fold_pair_[static_cast<std::size_t>(k)]) continue;
      const Vec12<double> xp = gather(x, vertices(pairs_[static_cast<std::size_t>(k)]));
      Frame<double> f;
      if (Kind::frame(xp, f) != Status::ok || !inside(f) || !detail::foot_consistent<Kind>(xp, f)) continue;
      if (std::abs(f.l) > 1e-3 * spec_.penalty.distance) side = f.l < 0 ? -1 : 1;
    }
  }

  /// Plane mode: the frame exists and is well conditioned (edges at least ~3° from
  /// parallel: nearer, the line distance and its closest points are ill-conditioned and the
  /// frame's normal flips without any crossing), the closest points of the plane (line)
  /// distance lie inside the primitives, and L = σ l is below `limit` and (signed) not
  /// deeper than the query radius.
  bool plane_active(const Vec12<double>& xp, long k, double limit, Frame<double>& f, double& sigma) const {
    if (!may_be_plane_active(xp, std::max(limit, 2 * spec_.penalty.distance))) return false;
    if (Kind::frame(xp, f) != Status::ok || !inside(f) || !detail::foot_consistent<Kind>(xp, f)) return false;
    if constexpr (!VF) {
      const Eigen::Vector3d e0 = xp.segment<3>(3) - xp.segment<3>(0), e1 = xp.segment<3>(9) - xp.segment<3>(6);
      if (e0.cross(e1).squaredNorm() < kParallelSin2 * e0.squaredNorm() * e1.squaredNorm()) return false;
    }
    const signed char side = spec_.signed_length ? sides_[static_cast<std::size_t>(k)] : 0;
    sigma = side != 0 ? static_cast<double>(side) : (f.l < 0 ? -1.0 : 1.0);
    const double L = sigma * f.l;
    return L < limit && L >= -2 * spec_.penalty.distance;
  }

  /// A necessary condition for plane_active, in a few dozen flops instead of a frame: the
  /// plane (line) distance |l| is at most `reach`, the foot of the vertex lies in the
  /// triangle (the closest points of the lines in both segments) and, for edges, they are
  /// not nearer parallel than plane_active allows — each with a relative slack of 1e-6
  /// (parameters) or 1 % (the parallel test), far beyond the rounding of either
  /// computation, so it never rejects a pair the frame would accept.
  static bool may_be_plane_active(const Vec12<double>& xp, double reach) {
    constexpr double slack = 1e-6;
    if constexpr (VF) {
      const Eigen::Vector3d p = xp.segment<3>(0), a = xp.segment<3>(3), b = xp.segment<3>(6), c = xp.segment<3>(9);
      const Eigen::Vector3d n = (b - a).cross(c - a);
      const double nn = n.squaredNorm(), s = (p - a).dot(n);
      if (!(s * s <= reach * reach * nn * (1 + slack))) return false;
      // Unnormalised barycentric coordinates of the foot of p (each nn at its own corner).
      const double tol = -slack * nn;
      return (c - b).cross(p - b).dot(n) >= tol && (a - c).cross(p - c).dot(n) >= tol &&
             (b - a).cross(p - a).dot(n) >= tol;
    } else {
      const Eigen::Vector3d a0 = xp.segment<3>(0), e0 = xp.segment<3>(3) - a0, b0 = xp.segment<3>(6),
                            e1 = xp.segment<3>(9) - b0, w = b0 - a0;
      const Eigen::Vector3d m = e0.cross(e1);
      const double mm = m.squaredNorm();
      if (!(mm >= 0.99 * kParallelSin2 * e0.squaredNorm() * e1.squaredNorm()) || !(mm > 0)) return false;
      const double s = w.dot(m);
      if (!(s * s <= reach * reach * mm * (1 + slack))) return false;
      // Closest points of the lines: a0 + u e0 and b0 + v e1, u = ((w × e1)·m)/|m|²,
      // v = ((w × e0)·m)/|m|².
      const double u = w.cross(e1).dot(m), v = w.cross(e0).dot(m), tol = slack * mm;
      return u >= -tol && u <= mm + tol && v >= -tol && v <= mm + tol;
    }
  }

  /// A lower bound on the distance between the pair's primitives: the larger of the box gap
  /// and the gap between their bounding spheres (centred at the mean of the primitive's
  /// vertices, radius the farthest of them). The spheres are the sharper bound for
  /// neighbours of one sheet, whose boxes overlap.
  static double distance_lower_bound(const Vec12<double>& xp) {
    constexpr int na = first_side_count();
    Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) (j < na ? ca : cb) += xp.segment<3>(3 * j);
    ca /= na;
    cb /= 4 - na;
    double ra = 0, rb = 0;
    for (int j = 0; j < 4; ++j) {
      double& r = j < na ? ra : rb;
      r = std::max(r, (xp.segment<3>(3 * j) - (j < na ? ca : cb)).norm());
    }
    // (1 − 1e-12): the rounding of the norms must not lift the bound above the distance.
    return std::max(box_gap(xp), ((ca - cb).norm() - ra - rb) * (1 - 1e-12));
  }

  /// Per candidate, at the query point: the distance lower bound and the index a·M + b
  /// (a ≤ b) of its two primitives' meshes; what cannot_be_active and max_step's filter read.
  void bound_at_query() {
    const long n = static_cast<long>(pairs_.size());
    const int M = static_cast<int>(model_->meshes.size());
    query_lb_.resize(pairs_.size());
    mesh_pair_.resize(pairs_.size());
#pragma omp parallel for schedule(static)
    for (long k = 0; k < n; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      const auto v = vertices(pairs_[uk]);
      query_lb_[uk] = distance_lower_bound(gather(query_at_, v));
      const int a = mesh_of_[static_cast<std::size_t>(v[0])], b = mesh_of_[static_cast<std::size_t>(v[3])];
      mesh_pair_[uk] = std::min(a, b) * M + std::max(a, b);
    }
  }

  /// drift_rel_[a·M + b] = rel_AB(x − query point) (validity_use's measure): no pair of
  /// meshes A, B has moved relatively by more since the query, so a candidate's distance at
  /// x is at least its query_lb_ minus this. Called once per pass, before the pair loop.
  void measure_drift(const Eigen::Matrix3Xd& x) {
    drift_ = x - query_at_;
    const MeshDrift m = mesh_drift(drift_);
    const std::size_t M = m.s.size();
    drift_rel_.assign(M * M, 0.0);
    for (std::size_t a = 0; a < M; ++a)
      for (std::size_t b = a; b < M; ++b) drift_rel_[a * M + b] = relative(m, a, b);
  }

  /// Per pair of meshes, W_AB = max(2 s_A, 2 s_B, rel_AB(step)): no two vertices of a pair of
  /// primitives in A and B move by more than W_AB relative to each other, so neither moves
  /// by more than W_AB relative to their mean p̄ (max_step's ma, mb).
  std::vector<double> step_reach(const MeshDrift& step) const {
    const std::size_t M = step.s.size();
    std::vector<double> w(M * M, 0.0);
    for (std::size_t a = 0; a < M; ++a)
      for (std::size_t b = a; b < M; ++b) w[a * M + b] = std::max({2 * step.s[a], 2 * step.s[b], relative(step, a, b)});
    return w;
  }

  /// The largest drift of the pair's vertices relative to each other since the query:
  /// max over i of the first primitive and j of the second of |Dᵢ − Dⱼ| (D = drift_). The
  /// distance between the primitives has changed by at most this since the query.
  double pair_drift(const std::array<int, 4>& v) const {
    constexpr int na = first_side_count();
    double worst = 0;
    for (int i = 0; i < na; ++i)
      for (int j = na; j < 4; ++j)
        worst = std::max(
            worst,
            (drift_.col(v[static_cast<std::size_t>(i)]) - drift_.col(v[static_cast<std::size_t>(j)])).squaredNorm());
    return std::sqrt(worst);
  }

  /// True when candidate k provably is inactive at the x of the last measure_drift: its
  /// lower bound at the query point, less how far its primitives can have closed in since
  /// (first the relative drift of its two meshes, one comparison; then the pair's own,
  /// pair_drift), is at least its activation limit (fold reach, else inactive_beyond), each
  /// with a relative slack of 1e-9, far beyond rounding. Every pass tests this first: a
  /// few flops instead of a frame or a distance, for every candidate that has not closed in
  /// (on the hammock, nearly all of them, fold pairs included).
  bool cannot_be_active(long k) const {
    const auto uk = static_cast<std::size_t>(k);
    if (query_lb_.size() != pairs_.size()) return false;
    const double room = query_lb_[uk] - (fold_pair_[uk] ? fold_reach_[uk] : inactive_beyond()) * (1 + 1e-9);
    if (room >= drift_rel_[static_cast<std::size_t>(mesh_pair_[uk])] * (1 + 1e-9)) return true;
    return room > 0 && room >= pair_drift(vertices(pairs_[uk])) * (1 + 1e-9);
  }

  /// Whether candidate k is active at x (length below d): the test evaluate() applies.
  bool is_active(const Eigen::Matrix3Xd& x, long k) const {
    if (cannot_be_active(k)) return false;
    const Vec12<double> xp = gather(x, vertices(pairs_[static_cast<std::size_t>(k)]));
    const bool fold = fold_pair_[static_cast<std::size_t>(k)];
    const double limit = fold ? fold_reach_[static_cast<std::size_t>(k)] : spec_.penalty.distance;
    if (fold && (!(limit > 0) || distance_lower_bound(xp) >= limit)) return false;
    if (!fold && box_gap(xp) > inactive_beyond()) return false;
    if (fold || spec_.closest_features) {
      ClosestFeatureEnergy<double> ce;
      const QuadraticPenalty probe{1.0, 0.0};
      const Status s = closest_feature_energy<Kind>(xp, UnsignedLength{}, probe, ce);
      return s == Status::degenerate || (s == Status::ok && ce.length < limit);
    }
    Frame<double> f;
    double sigma = 1;
    return plane_active(xp, k, limit, f, sigma);
  }

  static constexpr double kParallelSin2 = 0.05 * 0.05;
  /// A fold pair is active below this fraction of its rest distance (and below d).
  static constexpr double kFoldReach = 0.5;

  static void fail_infinite(PairOut& o) {
    // A barrier evaluated at L ≤ 0: infinite energy, which the line search rejects.
    o.active = true;
    o.energy = std::numeric_limits<double>::infinity();
    o.length = 0;
    o.g.setZero();
  }

  struct Stats {
    double broad_phase_ms = 0, tree_ms = 0, pair_ms = 0, scatter_ms = 0, queries = 0;
    long active = 0, fold_active = 0;
    double min_length = std::numeric_limits<double>::infinity();
  };

  ContactSettings spec_;
  const Model* model_;
  std::unique_ptr<BroadPhase> broad_phase_;
  const Eigen::Matrix3Xd* x_start_ = nullptr;
  Eigen::Matrix3Xd query_at_, query_to_;  ///< the last query's sweep x0 → x1
  Eigen::Matrix3Xd sweep_lo_, sweep_hi_;  ///< per vertex: its box over the sweep (condition A)
  Eigen::Matrix3Xd target_;               ///< x + dx of the last max_step: where a re-query sweeps to
  bool validity_bound_ = false;           ///< the last max_step's result was the validity limit
  std::vector<double> gaps_;              ///< M×M (upper part): gap between meshes' boxes at query_at_
  std::vector<std::array<int, 2>> pairs_;
  double margin_ = 0;  ///< this step's candidate margin m
  std::vector<signed char> sides_;
  /// Same-mesh pairs closer than 2d at rest, sorted; per candidate, whether it is one.
  std::vector<std::array<int, 2>> rest_neighbours_;
  std::vector<double> rest_reach_;  ///< per rest neighbour: min(d, kFoldReach · rest distance)
  std::vector<char> fold_pair_;
  std::vector<double> fold_reach_;             ///< per candidate: its rest_reach_ (fold pairs), else 0
  std::vector<char> declared_, near_;          ///< per candidate: in the pattern; active at the last update_pattern
  std::vector<int> mesh_of_;                   ///< per vertex: its mesh
  std::vector<double> query_lb_;               ///< per candidate: distance lower bound at query_at_
  std::vector<int> mesh_pair_;                 ///< per candidate: a·M + b of its meshes (a ≤ b)
  Eigen::Matrix3Xd drift_;                     ///< x − query_at_ of the last measure_drift
  std::vector<double> drift_rel_;              ///< rel_AB(drift_), indexed a·M + b
  std::vector<std::vector<PairOut>> actives_;  ///< per thread, active pairs only
  std::vector<std::vector<PairHessian>> hessians_;  ///< per thread, active pairs only
  Stats stats_;
};

/// Throws ArgumentError unless the settings are consistent (fields named as the scene's keys).
void check_contact(const ContactSettings& s) {
  check_penalty(s.penalty, "penalty.");
  if (s.hessian == Projection::none)
    throw ArgumentError("hessian",
                        "expected a PSD strategy (analytic, exact, numerical, gauss_newton or abs), got none");
  if (s.closest_features && s.signed_length)
    throw ArgumentError("length",
                        "closest-feature evaluation measures the distance between the primitives, which is unsigned: "
                        "use \"unsigned\" or \"closest_features\": false");
  if (s.penalty.barrier() && !s.closest_features)
    throw ArgumentError("closest_features",
                        "the log barrier needs the distance between the primitives: set \"closest_features\": true");
}

}  // namespace

std::unique_ptr<Effect> make_self_vertex_face(const Model& model, const ContactSettings& settings) {
  check_contact(settings);
  check_penalty_for_model(settings.penalty, model, "penalty.");
  if (model.triangles.cols() == 0) throw ArgumentError("", "self_vertex_face needs a mesh with triangles");
  return std::make_unique<SelfContact<true>>(settings, model);
}

std::unique_ptr<Effect> make_self_edge_edge(const Model& model, const ContactSettings& settings) {
  check_contact(settings);
  check_penalty_for_model(settings.penalty, model, "penalty.");
  if (model.edges.cols() < 2) throw ArgumentError("", "self_edge_edge needs at least two edges");
  return std::make_unique<SelfContact<false>>(settings, model);
}

}  // namespace pce::sim
