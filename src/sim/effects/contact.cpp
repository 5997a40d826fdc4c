// SPDX-License-Identifier: MIT
// Self contact through pce's pair energies: the effects `self_vertex_face` and
// `self_edge_edge` (docs/simulation.md, "From candidates to energies"), in three steps:
//  * candidates (`contact/candidate_set.hpp`): broad-phase queries with radius r = d + m
//    (activation distance d, margin m = d/2) over a sweep: from xⁿ to the inertial prediction
//    x̃ = xⁿ + h vⁿ at a step's start, and, with a step bound, over a Newton step that would
//    leave the set (cover_step); a set is kept while it provably covers every pair within d
//    (with a step bound, from one time step to the next); fold pairs (one mesh, closer than
//    2d at rest); a per-pass filter that drops candidates which cannot have closed in;
//  * active pairs (`classify` below): the one test that the sparsity pattern
//    (update_pattern) and the evaluation call, so what is declared is what is assembled;
//    passes that can reuse an earlier one visit its list instead of every candidate (the
//    pairs active at the pattern's state; on a line-search trial, those max_step found
//    possibly active along the step);
//  * the pair potential (`evaluate_pair`): pce's energy, gradient and projected Hessian of
//    an active pair, scattered by candidate index.
// Only pairs that share a vertex are never candidates. Fold pairs, of one mesh and closer
// than 2d at rest (distance D₀: a sheet's neighbours one or two rings apart), are evaluated
// by closest features with the activation distance min(d, D₀/2): no force at rest or in a
// smooth bend, a continuous repulsion in a tight fold; with every other candidate they are
// in the step bound, so no pair that does not share a vertex can cross during a step. Every
// other candidate is evaluated by pce:
//  * plane mode (the paper's): the frame of the pair; the pair is active when the closest
//    points of the plane (line) distance lie inside the triangle (both segments) and
//    L < d, with L = |l| (unsigned) or L = side·l (signed: the side is settled from the
//    first step start with the vertex over the face, and kept while the pair stays a
//    candidate);
//  * closest-feature mode: pce::closest_feature_energy, the distance between the primitives.
// With `area_weighted`, a pair's energy is w ψ(L), w its rest area (vertex-face: the face's
// area plus the vertex's lumped area; edge-edge: the two edges' lumped areas), evaluated as
// ψ with stiffness w k. With `friction`, every pair active at the step's start is frozen
// there (friction.hpp): λ = −ψ′(L), the closest points' weights (the frame's for the plane
// kinds, the closest feature's otherwise) and a tangent basis of the pair's normal; the
// potential of the closest points' relative slip over the step is summed with the contact
// energy, on its own list (a frozen pair stays one for the step whether or not it is still
// active or a candidate).
// The Hessian is pce's projection chosen per effect (`hessian`). Pairs are evaluated in
// parallel (OpenMP, chunks of consecutive candidates on a dynamic schedule) into per-chunk
// buffers, which are summed and scattered serially, in chunk order, into the block Hessian.
#include "contact/candidate_set.hpp"
#include "contact/pair_geometry.hpp"
#include "friction.hpp"
#include "penalty_spec.hpp"
#include "util/stopwatch.hpp"

#include <pce/energy/closest_feature.hpp>
#include <pce/energy/pair_energy.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/sim/instrumentation.hpp>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace pce::sim {

namespace {

/// An active pair's result of one evaluation (k its candidate index). Kept per chunk, for
/// active pairs only, so the serial pass that sums and scatters touches those alone (a
/// record per candidate made it sweep ~100 MB per evaluation on the hammock).
struct PairOut {
  long k = 0;
  double energy = 0;
  double length = std::numeric_limits<double>::infinity();
  bool active = false;
  /// is_active would say yes: active, or a degenerate closest-feature configuration.
  bool declare = false;
  bool unsure = false;  ///< declare is unknown (see closest_pair)
  Vec12<double> g;
};

/// The Hessian of an active pair (k its candidate index). Kept per chunk, for active pairs
/// only: a 12×12 block per candidate would cost ~1 KiB each (0.7 GB for the hammock's
/// candidates).
struct PairHessian {
  long k;
  Mat12<double> H;
};

/// What `classify` decides for one candidate at one state.
struct Activity {
  /// none: inactive; plane: active in plane mode (its frame and σ below); closest: active by
  /// closest features (its distance below `limit`, or a degenerate configuration).
  enum class Mode { none, plane, closest } mode = Mode::none;
  double limit = 0;  ///< the activation distance it was tested against (a fold pair's reach, else d)
  bool fold = false;
  Frame<double> frame;  ///< plane: the pair's frame
  double sigma = 1;     ///< plane: the sign of L = σ l
};

/// The per-frame counters of one self-contact effect (`report` writes them under the
/// documented `stats.json` keys).
struct ContactStats {
  double pair_ms = 0, scatter_ms = 0, settle_ms = 0;
  long active = 0, fold_active = 0;
  double min_length = std::numeric_limits<double>::infinity();
};

template <bool VF> class SelfContact final : public Effect {
  using Geometry = contact::PairGeometry<VF>;
  using Kind = std::conditional_t<VF, VertexFace, EdgeEdge>;

 public:
  SelfContact(const ContactSettings& spec, const Model& model)
      : spec_(spec),
        model_(&model),
        candidates_(model, spec.broad_phase, spec.penalty.distance, spec.penalty.barrier() || spec.ccd) {
    if (spec.area_weighted) areas_ = rest_areas(model);
  }

  const char* name() const override { return VF ? "self_vertex_face" : "self_edge_edge"; }

  void begin_step(const StepContext& ctx) override {
    x_start_ = ctx.x_start;
    inertial_motion_ = ctx.dt * ctx.v_start->colwise().norm().maxCoeff();
    stats_ = {};
    // (a kept set keeps what its passes recorded: each record names the state it was made at)
    if (candidates_.begin_step(*ctx.x_start, *ctx.x_start + ctx.dt * *ctx.v_start, previous_)) carry_over();
    if (spec_.friction) {
      friction_stats_ = {};
      eps_ = spec_.friction->slip_velocity * ctx.dt;
      rounds_ = 1;
      freeze(*ctx.x_start);
    }
  }

  bool update_lagged(const Eigen::Matrix3Xd& x) override {
    if (!spec_.friction || rounds_ >= spec_.friction->lagged_iterations) return false;
    ++rounds_;
    freeze(x);
    return true;
  }

  bool still_valid(const Eigen::Matrix3Xd& x) override { return candidates_.still_valid(x); }

  bool cover_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override {
    if (!spec_.penalty.barrier() && !spec_.ccd) return false;
    if (!candidates_.cover(x, dx, cover_reach(), previous_)) return false;
    carry_over();
    return true;
  }

  void refresh(const Eigen::Matrix3Xd& x) override {
    candidates_.refresh(x, previous_);
    carry_over();
  }

  void declare(Pattern& pattern) const override {
    for (std::size_t k = 0; k < candidates_.size(); ++k)
      if (declared_[k]) pattern.add(candidates_.vertices(k));
    for (const FrictionContact<4>& c : frozen_) pattern.add(c.v);
  }

  bool update_pattern(const Eigen::Matrix3Xd& x) override {
    // Exactly the pairs active at x (those whose Hessian evaluate() adds) couple their
    // vertices. Declaring more (pairs that were near activation at some earlier iterate)
    // multiplies the factorisation's fill-in: on the hammock, 65 k declared pairs for 3 k
    // active ones made L 4.9 M non-zeros and each factorisation 0.5 s.
    // At the state of the last full evaluation (the line search's accepted trial), that pass
    // recorded is_active for every candidate; otherwise one pass asks it.
    if (evaluated_x_valid_ && evaluated_x_.cols() == x.cols() && evaluated_x_ == x) {
      near_.assign(candidates_.size(), 0);
      for (const std::size_t k : declared_at_evaluation_) near_[k] = 1;
    } else {
      const long n = static_cast<long>(candidates_.size());
      if (near_.size() < candidates_.size()) near_.resize(candidates_.size());
      candidates_.measure_drift(x);
#pragma omp parallel for schedule(dynamic, 2048)
      for (long k = 0; k < n; ++k) near_[static_cast<std::size_t>(k)] = is_active(x, k);
    }
    bool changed = false;
    active_at_pattern_.clear();
    for (std::size_t k = 0; k < candidates_.size(); ++k) {
      if (near_[k] != declared_[k]) declared_[k] = near_[k], changed = true;
      if (near_[k]) active_at_pattern_.push_back(k);
    }
    pattern_x_ = x;
    pattern_x_valid_ = true;
    return changed;
  }

  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    const auto t0 = Clock::now();
    const bool want_h = hessian != nullptr;
    candidates_.measure_drift(x);
    // At the state of the last update_pattern (the solver's Newton evaluation follows it), the
    // pairs active there are the only ones that can be: is_active is true for every pair
    // evaluate_pair finds active (and for degenerate closest-feature pairs, which it skips),
    // so the pass visits those alone, in the same ascending order, with the same result.
    const bool at_pattern = pattern_x_valid_ && pattern_x_.cols() == x.cols() && pattern_x_ == x;
    // On the last max_step's segment (a line-search trial), the pairs max_step listed as
    // possibly active there are the only ones that can be (is_active included), so the pass
    // visits those alone, again in ascending order with the same result.
    const bool on_list = !at_pattern && on_segment(x);
    const std::vector<std::size_t>* list = at_pattern ? &active_at_pattern_ : on_list ? &segment_ : nullptr;
    const long n = list ? static_cast<long>(list->size()) : static_cast<long>(candidates_.size());
    // Chunks of consecutive pairs, each with its own output lists, handed to the threads as
    // they come free (dynamic schedule: the cost per candidate varies by orders of
    // magnitude, and a static split left one of two threads idle most of a pass); reading
    // the chunks' lists in chunk order visits the active pairs in k order, so sums and
    // scatter are the same, bit for bit, whatever the thread count. Active pairs (each with
    // a Hessian) come in smaller chunks.
    const long chunk = at_pattern ? 32 : on_list ? 256 : 2048;
    const auto chunks = static_cast<std::size_t>((n + chunk - 1) / chunk);
    if (actives_.size() < chunks) {
      actives_.resize(chunks);
      hessians_.resize(chunks);
      declares_.resize(chunks);
    }
    unsure_.assign(chunks, 0);
    chunks_ = chunks;
    visit_penalty(spec_.penalty, [&](const auto& penalty) {
#pragma omp parallel for schedule(dynamic, 1)
      for (long c = 0; c < static_cast<long>(chunks); ++c) {
        const auto uc = static_cast<std::size_t>(c);
        std::vector<PairHessian>& my_hessians = hessians_[uc];
        std::vector<PairOut>& my_actives = actives_[uc];
        std::vector<std::size_t>& my_declares = declares_[uc];
        my_hessians.clear();
        my_actives.clear();
        my_declares.clear();
        const long end = std::min(n, (c + 1) * chunk);
        for (long i = c * chunk; i < end; ++i) {
          const long k = list ? static_cast<long>((*list)[static_cast<std::size_t>(i)]) : i;
          PairOut o;
          evaluate_pair(x, k, penalty, want_h ? &my_hessians : nullptr, o);
          if (o.declare) my_declares.push_back(static_cast<std::size_t>(k));
          if (o.unsure) unsure_[uc] = 1;
          if (o.active) {
            o.k = k;
            my_actives.push_back(o);
          }
        }
      }
    });
    (VF ? instrumentation().vertex_face_pairs_evaluated : instrumentation().edge_edge_pairs_evaluated) += n;
    // A pass over every candidate recorded is_active for each: update_pattern at this x
    // reads it instead of asking again.
    evaluated_x_valid_ = !at_pattern && std::count(unsure_.begin(), unsure_.end(), char(1)) == 0;
    if (evaluated_x_valid_) {
      evaluated_x_ = x;
      declared_at_evaluation_.clear();
      for (std::size_t c = 0; c < chunks_; ++c)
        declared_at_evaluation_.insert(declared_at_evaluation_.end(), declares_[c].begin(), declares_[c].end());
    }
    stats_.pair_ms += ms_since(t0);
    const auto t1 = Clock::now();
    double energy = 0;
    long active = 0, fold_active = 0;
    double min_length = std::numeric_limits<double>::infinity();
    for (std::size_t c = 0; c < chunks_; ++c)
      for (const PairOut& o : actives_[c]) {
        ++active;
        fold_active += candidates_.fold_pair(static_cast<std::size_t>(o.k));
        energy += o.energy;
        min_length = std::min(min_length, o.length);
        if (!std::isfinite(o.energy)) continue;  // a barrier at distance 0: E = ∞, nothing to add
        const auto v = candidates_.vertices(static_cast<std::size_t>(o.k));
        if (gradient)
          for (int j = 0; j < 4; ++j) gradient->col(v[static_cast<std::size_t>(j)]) += o.g.segment<3>(3 * j);
      }
    if (hessian)
      for (std::size_t c = 0; c < chunks_; ++c)
        for (const PairHessian& ph : hessians_[c])
          hessian->add<4>(candidates_.vertices(static_cast<std::size_t>(ph.k)), ph.H);
    stats_.scatter_ms += ms_since(t1);
    stats_.active = active;
    stats_.fold_active = fold_active;
    stats_.min_length = min_length;
    if (spec_.friction) {
      const auto t2 = Clock::now();
      energy += add_friction(frozen_, x, *x_start_, gradient, hessian, friction_stats_.sticking);
      friction_stats_.ms += ms_since(t2);
    }
    if (!std::isfinite(energy)) return std::numeric_limits<double>::infinity();
    return energy;
  }

  double max_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override {
    segment_valid_ = false;
    if (!spec_.penalty.barrier() && !spec_.ccd) return 1.0;
    // Conservative advancement (additive CCD, Li et al. 2021): the distance is unchanged by
    // a common translation, so with p̄ the mean of the pair's four vertex displacements,
    // along x + t dx the distance between the primitives changes by at most t (max |dxᵢ − p̄|
    // over the first's vertices + max |dxⱼ − p̄| over the second's); keep 10 % of every
    // candidate's current distance (closest features), so no candidate pair can cross
    // during the step. A pair whose one-shot bound would lower t is advanced further by
    // measuring its distance again (`advance`): one round cut a sliding or glancing pair's
    // step to a few percent; on the hammock's frames 21-40 that cost ~3 Newton iterations a
    // frame.
    // (Without p̄, strands falling side by side limited each other's step to ~6 % for twenty
    // iterations.)
    // The step also keeps the candidate set valid (step_limit), so no other pair can come
    // within d either. (Bounding the candidates alone let a landing sheet cross faces that
    // were not candidates.) cover_step, called before, has queried again where the whole
    // step would have left the set.
    const double t_valid = candidates_.step_limit(x, dx);
    // The same pass lists the candidates that can be active anywhere on x + s dx, s ∈ [0,
    // t_valid] (t_valid bounds what this returns, hence every line-search trial): a pair
    // whose distance at x, less t_valid (ma + mb), is at least its reach is inactive on the
    // whole segment. The trials then visit the list alone (evaluate, on_segment).
    segment_slack_ = 8 * kSegmentTolerance * std::max(x.cwiseAbs().maxCoeff(), 1.0);
    double t = t_valid;  // (inside the loop, t is a chunk's own minimum, which starts at +∞)
    const long n = static_cast<long>(candidates_.size());
    constexpr long chunk = 2048;
    const auto chunks = static_cast<std::size_t>((n + chunk - 1) / chunk);
    if (segments_.size() < chunks) segments_.resize(chunks);
      // (dynamic schedule: the minimum is the same whatever the order, and the chunks' lists
      // are joined in chunk order; see evaluate)
#pragma omp parallel for schedule(dynamic, 1) reduction(min : t)
    for (long c = 0; c < static_cast<long>(chunks); ++c) {
      std::vector<std::size_t>& my_segment = segments_[static_cast<std::size_t>(c)];
      my_segment.clear();
      const long end = std::min(n, (c + 1) * chunk);
      for (long k = c * chunk; k < end; ++k) {
        const auto uk = static_cast<std::size_t>(k);
        const double reach = reach_of(uk);
        // Two questions, each asked at three levels of detail, reading more only while the
        // answer is open: is the pair inactive on the whole segment (`far`: a lower bound on
        // its distance at x, less t_valid times a bound on ma + mb, is at least its reach),
        // and can it not lower t (the same bounds against t)? First from its meshes' drift
        // and step reach (stays_beyond, cannot_limit), then from its primitives' spreads
        // (primitive_lower_bound, step_bound), then from its four vertices.
        bool far = candidates_.stays_beyond(uk, reach, t_valid, segment_slack_);
        const bool cannot_limit = candidates_.cannot_limit(uk, t_valid);
        if (far && cannot_limit) continue;
        {
          const double motion = candidates_.step_bound(uk), bound = candidates_.primitive_lower_bound(uk);
          const bool far_too = far || bound - reach * (1 + 1e-9) >= (t_valid * motion + segment_slack_) * (1 + 1e-9);
          const bool no_limit =
              cannot_limit || !(motion > 0) || 0.9 * bound >= std::min(t, t_valid) * motion * (1 + 1e-9);
          if (far_too && no_limit) continue;
        }
        const auto v = candidates_.vertices(uk);
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (int j = 0; j < 4; ++j) mean += dx.col(v[static_cast<std::size_t>(j)]);
        mean *= 0.25;
        double ma = 0, mb = 0;  // largest motion on each primitive relative to p̄
        for (int j = 0; j < 4; ++j) {
          const double d = (dx.col(v[static_cast<std::size_t>(j)]) - mean).norm();
          double& m = j < Geometry::first_side_count() ? ma : mb;
          m = std::max(m, d);
        }
        const double reach_along = (t_valid * (ma + mb) + segment_slack_) * (1 + 1e-9);
        const auto beyond_along = [&](double lower_bound) { return lower_bound - reach * (1 + 1e-9) >= reach_along; };
        far = far || beyond_along(candidates_.lower_bound(uk, v));
        const bool may_limit =
            !cannot_limit && ma + mb > 0 && !candidates_.cannot_lower(uk, v, ma + mb, std::min(t, t_valid));
        if (far && !may_limit) continue;
        const Vec12<double> xp = Geometry::gather(x, v);
        // The distance is at least distance_lower_bound, so a pair whose bound already allows the
        // smaller of this chunk's minimum and the validity bound cannot lower the result:
        // it is the same without the pair's distance.
        const double bound = Geometry::distance_lower_bound(xp);
        far = far || beyond_along(bound);
        if (!far) my_segment.push_back(uk);
        if (!may_limit || 0.9 * bound >= std::min(t, t_valid) * (ma + mb)) continue;
        ClosestFeatureEnergy<double> ce;
        const QuadraticPenalty probe{1.0, 0.0};
        if (closest_feature_energy<Kind>(xp, UnsignedLength{}, probe, ce) != Status::ok) continue;
        candidates_.tighten(uk, v, ce.length);
        t = std::min(t, advance(xp, Geometry::gather(dx, v), ce.length, ma + mb, std::min(t, t_valid)));
      }
    }
    segment_.clear();
    for (std::size_t c = 0; c < chunks; ++c) segment_.insert(segment_.end(), segments_[c].begin(), segments_[c].end());
    segment_x_ = x;
    segment_dx_ = dx;
    segment_t_ = t_valid;
    segment_valid_ = true;
    candidates_.record_step(t_valid, t);
    return std::max(t, 0.0);
  }

  void report(EffectCounters& c) const override {
    const auto& q = candidates_.stats();
    c[VF ? Counter::vertex_face_candidates : Counter::edge_edge_candidates] = static_cast<double>(candidates_.size());
    c[VF ? Counter::vertex_face_declared : Counter::edge_edge_declared] =
        static_cast<double>(std::count(declared_.begin(), declared_.end(), char(1)));
    c[VF ? Counter::vertex_face_rest_neighbours : Counter::edge_edge_rest_neighbours] =
        static_cast<double>(candidates_.fold_pairs());
    c[VF ? Counter::vertex_face_fold_contacts : Counter::edge_edge_fold_contacts] =
        static_cast<double>(stats_.fold_active);
    c[VF ? Counter::vertex_face_contacts : Counter::edge_edge_contacts] = static_cast<double>(stats_.active);
    c[VF ? Counter::vertex_face_min_distance : Counter::edge_edge_min_distance] = stats_.min_length;
    c[Counter::broad_phase_ms] = q.broad_phase_ms + stats_.settle_ms;
    c[Counter::broad_phase_tree_ms] = q.tree_ms;
    c[Counter::broad_phase_queries] = q.queries;
    c[Counter::pair_ms] = stats_.pair_ms;
    c[Counter::scatter_ms] = stats_.scatter_ms;
    if (spec_.friction) {
      c[VF ? Counter::vertex_face_friction_contacts : Counter::edge_edge_friction_contacts] =
          static_cast<double>(frozen_.size());
      c[VF ? Counter::vertex_face_friction_sticking : Counter::edge_edge_friction_sticking] =
          static_cast<double>(friction_stats_.sticking);
      c[VF ? Counter::vertex_face_friction_ms : Counter::edge_edge_friction_ms] = friction_stats_.ms;
    }
  }

  /// The tracked pairs with their sides and declarations, and the query they came from:
  /// what the next begin_step keeps (a query carries them over to the fresh candidates; a
  /// set still valid is kept whole). Per pair: two int32 indices, the side and the
  /// declaration as int8. Then, when a query was made: the byte 1, the byte of the last
  /// step's validity limit (0 or 1), and the query's sweep as 2 × 3n doubles (x0 then x1,
  /// column-major). Native byte order. A state without the query part (older checkpoints)
  /// loads too; the next step then queries.
  std::string save_state() const override {
    std::string out;
    const auto& pairs = candidates_.pairs();
    const std::uint64_t count = pairs.size();
    out.append(reinterpret_cast<const char*>(&count), sizeof count);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const std::int32_t ab[2] = {pairs[k][0], pairs[k][1]};
      const signed char flags[2] = {sides_[k], static_cast<signed char>(declared_[k])};
      out.append(reinterpret_cast<const char*>(ab), sizeof ab);
      out.append(reinterpret_cast<const char*>(flags), sizeof flags);
    }
    const Eigen::Matrix3Xd &at = candidates_.query_point(), &to = candidates_.query_to();
    if (at.cols() == model_->vertex_count() && to.cols() == at.cols() && at.cols() > 0) {
      const char head[2] = {1, static_cast<char>(candidates_.validity_bound() ? 1 : 0)};
      out.append(head, sizeof head);
      out.append(reinterpret_cast<const char*>(at.data()), sizeof(double) * static_cast<std::size_t>(at.size()));
      out.append(reinterpret_cast<const char*>(to.data()), sizeof(double) * static_cast<std::size_t>(to.size()));
    }
    return out;
  }

  void load_state(const std::string& state) override {
    constexpr std::size_t record = 2 * sizeof(std::int32_t) + 2;
    std::uint64_t count = 0;
    if (state.size() < sizeof count) throw std::invalid_argument(std::string(name()) + ": truncated state");
    std::memcpy(&count, state.data(), sizeof count);
    const std::size_t n = static_cast<std::size_t>(model_->vertex_count());
    const std::size_t query_part = 2 + 2 * 3 * n * sizeof(double);
    if (count > (state.size() - sizeof count) / record)
      throw std::invalid_argument(std::string(name()) + ": the state's size does not match its pair count");
    const std::size_t pairs_end = sizeof count + count * record;
    const bool with_query = n > 0 && state.size() == pairs_end + query_part;
    if (state.size() != pairs_end && !with_query)
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
    if (with_query) {
      const char* q = state.data() + pairs_end;
      if (q[0] != 1 || (q[1] != 0 && q[1] != 1))
        throw std::invalid_argument(std::string(name()) + ": the saved query's header is not 1 followed by 0 or 1");
      Eigen::Matrix3Xd at(3, static_cast<Eigen::Index>(n)), to(3, static_cast<Eigen::Index>(n));
      std::memcpy(at.data(), q + 2, sizeof(double) * 3 * n);
      std::memcpy(to.data(), q + 2 + sizeof(double) * 3 * n, sizeof(double) * 3 * n);
      if (!at.allFinite() || !to.allFinite())
        throw std::invalid_argument(std::string(name()) + ": the saved query's positions are not all finite");
      candidates_.restore(std::move(pairs), at, to, q[1] == 1);
    } else {
      candidates_.restore(std::move(pairs));
    }
    sides_ = std::move(sides);
    declared_ = std::move(declared);
    pattern_x_valid_ = evaluated_x_valid_ = segment_valid_ = false;
  }

 private:
  /// After a query: pairs already tracked keep their side and their declaration (until the
  /// next update_pattern); new pairs start undeclared, with their side settled at xⁿ.
  void carry_over() {
    const auto t0 = Clock::now();
    pattern_x_valid_ = evaluated_x_valid_ = segment_valid_ = false;
    std::vector<signed char> sides(previous_.size(), 0);
    std::vector<char> declared(previous_.size(), 0);
    for (std::size_t k = 0; k < previous_.size(); ++k)
      if (previous_[k] >= 0) {
        sides[k] = sides_[static_cast<std::size_t>(previous_[k])];
        declared[k] = declared_[static_cast<std::size_t>(previous_[k])];
      }
    sides_ = std::move(sides);
    declared_ = std::move(declared);
    if (spec_.signed_length) settle_sides(*x_start_);
    stats_.settle_ms += ms_since(t0);
  }

  /// Additive CCD (Li et al. 2021, iterated): the largest t found for which the pair at
  /// xp + s dxp, s ∈ [0, t], stays at least g = 0.1 d₀ apart (d₀ its distance at s = 0, `lp` =
  /// ma + mb the bound on how fast the distance changes along the step). From a distance
  /// dᵢ at tᵢ the distance stays ≥ g up to tᵢ + (dᵢ − g)/lp; each round advances 0.9 of
  /// that and measures again, until t reaches `cap` (then the pair cannot lower the
  /// minimum), the advance stalls below 1e-3 t, or 32 rounds. The first round is the
  /// one-shot bound 0.9 d₀/lp.
  static double advance(const Vec12<double>& xp, const Vec12<double>& dxp, double d0, double lp, double cap) {
    const double g = 0.1 * d0;
    double t = 0.9 * d0 / lp;
    const QuadraticPenalty probe{1.0, 0.0};
    for (int round = 0; round < 32 && t < cap; ++round) {
      ClosestFeatureEnergy<double> ce;
      if (closest_feature_energy<Kind>(Vec12<double>(xp + t * dxp), UnsignedLength{}, probe, ce) != Status::ok) break;
      const double step = 0.9 * (ce.length - g) / lp;
      if (!(step > 1e-3 * t)) break;
      t += step;
    }
    return t;
  }

  /// How far a step may move a vertex and still be covered by one query (cover_step): 16 d,
  /// or twice the farthest inertial motion of the step when that is larger.
  double cover_reach() const { return std::max(8 * 2 * spec_.penalty.distance, 2 * inertial_motion_); }

  /// Pairs farther apart than this are inactive in every mode: the activation distance d, or
  /// 2d for signed plane mode (a pair counts down to L = −2d).
  double inactive_beyond() const {
    return (spec_.signed_length && !spec_.closest_features ? 2.0 : 1.0) * spec_.penalty.distance;
  }

  /// Whether candidate k is active at x, and how: the one activity test behind both the
  /// sparsity pattern (is_active) and the evaluation (evaluate_pair). A fold pair is
  /// tested by closest features against its reach, every other candidate by the effect's
  /// mode against d. The cheap rejections come first: the candidate set's filter (its bound
  /// at the query less the drift since), then the pair's own box gap or distance bound,
  /// then, in plane mode, plane_active. A closest-feature candidate that passes them is
  /// returned as closest with its limit; the caller measures its distance.
  Activity classify(const Vec12<double>& xp, std::size_t k) const {
    Activity a;
    a.fold = candidates_.fold_pair(k);
    if (a.fold) {
      a.limit = candidates_.fold_reach(k);
      if (!(a.limit > 0) || Geometry::distance_lower_bound(xp) >= a.limit) return a;
      a.mode = Activity::Mode::closest;
      return a;
    }
    a.limit = spec_.penalty.distance;
    if (Geometry::box_gap(xp) > inactive_beyond()) return a;
    if (spec_.closest_features) {
      a.mode = Activity::Mode::closest;
      return a;
    }
    if (plane_active(xp, k, a.limit, a.frame, a.sigma)) a.mode = Activity::Mode::plane;
    return a;
  }

  /// Candidate k is inactive while its distance is above this: its fold reach (a fold
  /// pair) or inactive_beyond().
  double reach_of(std::size_t k) const {
    return candidates_.fold_pair(k) ? candidates_.fold_reach(k) : inactive_beyond();
  }

  /// The filter classify starts from, before any vertex position is read.
  bool filtered_out(std::size_t k) const { return candidates_.beyond(k, reach_of(k)); }

  /// Whether x lies on the segment of the last max_step: x = x₀ + s dx with s ∈ [0, t_valid]
  /// (relative 1e-12), to within kSegmentTolerance · max(|x₀|, 1) per coordinate (what the
  /// solver's x₀ + α dx rounds to), so that only the pairs of segment_ can be active there.
  bool on_segment(const Eigen::Matrix3Xd& x) const {
    if (!segment_valid_ || x.cols() != segment_x_.cols()) return false;
    Eigen::Index row = 0, col = 0;
    const double largest = segment_dx_.cwiseAbs().maxCoeff(&row, &col);
    const double s = largest > 0 ? (x(row, col) - segment_x_(row, col)) / segment_dx_(row, col) : 0.0;
    if (!(s >= 0 && s <= segment_t_ * (1 + 1e-12))) return false;
    const double tolerance = kSegmentTolerance * std::max(segment_x_.cwiseAbs().maxCoeff(), 1.0);
    return ((x - segment_x_) - s * segment_dx_).cwiseAbs().maxCoeff() <= tolerance;
  }

  /// Whether candidate k is active at x (length below its limit, or a degenerate closest-
  /// feature configuration): what update_pattern declares.
  bool is_active(const Eigen::Matrix3Xd& x, long k) const {
    const auto uk = static_cast<std::size_t>(k);
    if (filtered_out(uk)) return false;
    const Vec12<double> xp = Geometry::gather(x, candidates_.vertices(uk));
    const Activity a = classify(xp, uk);
    if (a.mode != Activity::Mode::closest) return a.mode == Activity::Mode::plane;
    ClosestFeatureEnergy<double> ce;
    const QuadraticPenalty probe{1.0, 0.0};
    const Status s = closest_feature_energy<Kind>(xp, UnsignedLength{}, probe, ce);
    if (s == Status::ok) candidates_.tighten(uk, candidates_.vertices(uk), ce.length);
    return s == Status::degenerate || (s == Status::ok && ce.length < a.limit);
  }

  /// The pair potential: energy, gradient and projected Hessian of candidate k at x when it
  /// is active (classify), into `o` and `hessians`.
  template <class Penalty> void evaluate_pair(const Eigen::Matrix3Xd& x, long k, const Penalty& penalty,
                                              std::vector<PairHessian>* hessians, PairOut& o) const {
    o.active = false;
    const auto uk = static_cast<std::size_t>(k);
    if (filtered_out(uk)) return;
    const Vec12<double> xp = Geometry::gather(x, candidates_.vertices(uk));
    const Activity a = classify(xp, uk);
    if (a.mode == Activity::Mode::none) return;
    o.declare = a.mode == Activity::Mode::plane;  // is_active: plane mode is active
    const Penalty pk = weighted(penalty, uk);
    if (a.mode == Activity::Mode::closest)
      return a.fold ? closest_pair(xp, k, with_reach(pk, a.limit), a.limit, hessians, o)
                    : closest_pair(xp, k, pk, a.limit, hessians, o);
    // pair_energy's result from the frame already built (signed with the side σ, or the
    // unsigned length, whose σ = sgn l is the same number): no second frame.
    PairEnergy<double> e;
    e.frame = a.frame;
    e.sigma = a.sigma;
    e.length = a.sigma * a.frame.l;
    const Status s = evaluate_penalty(pk, e.length, e.psi);
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
    // What is_active (which measures with a probe penalty) says: degenerate, or a distance
    // below the limit (a barrier's out_of_domain is a distance of 0). Another status of the
    // effect's penalty (overflow) leaves it unknown.
    o.declare = s == Status::degenerate || s == Status::out_of_domain || (s == Status::ok && ce.length < limit);
    o.unsure = !(s == Status::ok || s == Status::degenerate || s == Status::out_of_domain);
    // A barrier at distance 0 (out of its domain, or a point kind's `degenerate`, which
    // is reported only at distance exactly 0) is infinite energy.
    if (s == Status::out_of_domain || (s == Status::degenerate && spec_.penalty.barrier())) return fail_infinite(o);
    if (s == Status::ok)
      candidates_.tighten(static_cast<std::size_t>(k), candidates_.vertices(static_cast<std::size_t>(k)), ce.length);
    if (s != Status::ok || !(ce.length < limit)) return;
    o.active = true;
    o.length = ce.length;
    o.energy = ce.psi.value;
    o.g = energy_gradient(ce);
    if (hessians) hessians->push_back({k, projected_hessian(ce, spec_.hessian)});
  }

  /// The rest area candidate k's energy is weighed by (area_weighted): the vertex's lumped
  /// area plus the face's area, or the two edges' lumped areas.
  double weight(std::size_t k) const {
    const auto& c = candidates_.pairs()[k];
    return VF ? areas_.vertex[c[0]] + areas_.triangle[c[1]] : areas_.edge[c[0]] + areas_.edge[c[1]];
  }

  /// The penalty of candidate k: the effect's, with its stiffness times weight(k) when
  /// area weighted (ψ is linear in it).
  template <class Penalty> Penalty weighted(const Penalty& penalty, std::size_t k) const {
    return spec_.area_weighted ? scaled(penalty, weight(k)) : penalty;
  }

  /// Freezes the friction of every candidate active at `x` (classify, then the pair's
  /// penalty): λ = −ψ′(L) of its (weighted) penalty, its closest points' weights and the
  /// tangent basis of its normal (pce::friction_geometry), μλ and ε = ε_v h. In chunks of
  /// consecutive candidates on the threads, joined in candidate order.
  void freeze(const Eigen::Matrix3Xd& x) {
    const auto t0 = Clock::now();
    candidates_.measure_drift(x);
    const long n = static_cast<long>(candidates_.size());
    constexpr long chunk = 2048;
    const auto chunks = static_cast<std::size_t>((n + chunk - 1) / chunk);
    std::vector<std::vector<FrictionContact<4>>> parts(chunks);
    const double mu = spec_.friction->coefficient;
    visit_penalty(spec_.penalty, [&](const auto& penalty) {
#pragma omp parallel for schedule(dynamic, 1)
      for (long c = 0; c < static_cast<long>(chunks); ++c) {
        const long end = std::min(n, (c + 1) * chunk);
        for (long k = c * chunk; k < end; ++k) {
          const auto uk = static_cast<std::size_t>(k);
          if (filtered_out(uk)) continue;
          const auto v = candidates_.vertices(uk);
          const Vec12<double> xp = Geometry::gather(x, v);
          const Activity a = classify(xp, uk);
          if (a.mode == Activity::Mode::none) continue;
          const auto pk = weighted(penalty, uk);
          double lambda = 0;
          VecN<double, 4> w;
          Eigen::Vector3d normal;
          if (a.mode == Activity::Mode::plane) {
            PenaltyDerivatives<double> psi;
            if (evaluate_penalty(pk, a.sigma * a.frame.l, psi) != Status::ok) continue;
            lambda = -psi.first;
            friction_geometry(a.frame, w, normal);
          } else {
            ClosestFeatureEnergy<double> ce;
            const Status s = a.fold ? closest_feature_energy<Kind>(xp, UnsignedLength{}, with_reach(pk, a.limit), ce)
                                    : closest_feature_energy<Kind>(xp, UnsignedLength{}, pk, ce);
            if (s != Status::ok || !(ce.length < a.limit) || !friction_geometry(ce, xp, w, normal)) continue;
            lambda = -ce.psi.first;
          }
          if (!(lambda > 0) || !std::isfinite(lambda)) continue;
          FrictionContact<4> fc;
          fc.v = v;
          fc.f.weights = w;
          fc.f.basis = tangent_basis<double>(normal);
          fc.f.mu_lambda = mu * lambda;
          fc.f.eps = eps_;
          parts[static_cast<std::size_t>(c)].push_back(fc);
        }
      }
    });
    frozen_.clear();
    for (const auto& part : parts) frozen_.insert(frozen_.end(), part.begin(), part.end());
    publish_friction(frozen_, frozen_friction_);
    friction_stats_.ms += ms_since(t0);
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
    const long n = static_cast<long>(candidates_.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (long k = 0; k < n; ++k) {
      const auto uk = static_cast<std::size_t>(k);
      signed char& side = sides_[uk];
      if (side != 0 || candidates_.fold_pair(uk)) continue;
      const Vec12<double> xp = Geometry::gather(x, candidates_.vertices(uk));
      // (vertex-face: the foot of the vertex outside the triangle by more than the test's
      // slack rules out `inside` before a frame is built; most candidates are a sheet's own
      // neighbours, beside each other)
      if constexpr (VF)
        if (!Geometry::may_be_plane_active(xp, kAnyDistance)) continue;
      Frame<double> f;
      if (Kind::frame(xp, f) != Status::ok || !Geometry::inside(f) || !foot_consistent<Kind>(xp, f)) continue;
      if (std::abs(f.l) > 1e-3 * spec_.penalty.distance) side = f.l < 0 ? -1 : 1;
    }
  }

  /// Plane mode: the frame exists and is well conditioned (edges at least ~3° from
  /// parallel, PairGeometry::well_conditioned), the closest points of the plane (line)
  /// distance lie inside the primitives, and L = σ l is below `limit` and (signed) not
  /// deeper than 2d.
  bool plane_active(const Vec12<double>& xp, std::size_t k, double limit, Frame<double>& f, double& sigma) const {
    if (!Geometry::may_be_plane_active(xp, std::max(limit, 2 * spec_.penalty.distance))) return false;
    if (Kind::frame(xp, f) != Status::ok || !Geometry::inside(f) || !foot_consistent<Kind>(xp, f)) return false;
    if (!Geometry::well_conditioned(xp)) return false;
    const signed char side = spec_.signed_length ? sides_[k] : 0;
    sigma = side != 0 ? static_cast<double>(side) : (f.l < 0 ? -1.0 : 1.0);
    const double L = sigma * f.l;
    return L < limit && L >= -2 * spec_.penalty.distance;
  }

  static void fail_infinite(PairOut& o) {
    // A barrier evaluated at L ≤ 0: infinite energy, which the line search rejects.
    o.active = true;
    o.energy = std::numeric_limits<double>::infinity();
    o.length = 0;
    o.g.setZero();
  }

  ContactSettings spec_;
  const Model* model_;
  contact::CandidateSet<VF> candidates_;
  const Eigen::Matrix3Xd* x_start_ = nullptr;
  double inertial_motion_ = 0;                  ///< max |h vᵢⁿ| of the step (cover_reach)
  std::vector<long> previous_;                  ///< per candidate of the last query: its former index, or −1
  std::vector<signed char> sides_;              ///< per candidate: settled side (signed length), or 0
  std::vector<char> declared_, near_;           ///< per candidate: in the pattern; active at the last update_pattern
  std::vector<std::size_t> active_at_pattern_;  ///< the candidates active at the last update_pattern, ascending
  Eigen::Matrix3Xd pattern_x_;                  ///< the state of the last update_pattern
  bool pattern_x_valid_ = false;                ///< active_at_pattern_ belongs to the current candidates
  std::vector<std::size_t> declared_at_evaluation_;  ///< is_active at the last full evaluation, ascending
  Eigen::Matrix3Xd evaluated_x_;                     ///< the state of that evaluation
  bool evaluated_x_valid_ = false;                   ///< declared_at_evaluation_ is usable
  std::size_t chunks_ = 0;                           ///< chunks of the last evaluation
  std::vector<std::vector<std::size_t>> declares_;   ///< per chunk: its pairs is_active would declare
  std::vector<char> unsure_;                         ///< per chunk: some declaration unknown
  std::vector<std::vector<PairOut>> actives_;        ///< per chunk, active pairs only
  std::vector<std::vector<PairHessian>> hessians_;   ///< per chunk, active pairs only
  /// The candidates that can be active on the segment of the last max_step (ascending), per
  /// chunk while it is built, and that segment: x₀ + s dx, s ∈ [0, segment_t_].
  std::vector<std::size_t> segment_;
  std::vector<std::vector<std::size_t>> segments_;
  Eigen::Matrix3Xd segment_x_, segment_dx_;
  double segment_t_ = 0;
  double segment_slack_ = 0;    ///< the list's allowance for a state up to on_segment's tolerance off the segment
  bool segment_valid_ = false;  ///< segment_ belongs to the current candidates
  /// A reach that PairGeometry::may_be_plane_active's distance test never rejects (its
  /// square times a triangle's |n|² stays finite): what settle_sides passes to use the foot test alone.
  static constexpr double kAnyDistance = 1e150;
  /// on_segment's tolerance per coordinate, relative to max(|x₀|, 1): far above the rounding
  /// of x₀ + α dx (a few ε), far below any distance that matters.
  static constexpr double kSegmentTolerance = 1e-12;
  ContactStats stats_;
  RestAreas areas_;                         ///< rest areas (area_weighted), else empty
  std::vector<FrictionContact<4>> frozen_;  ///< the step's frozen friction pairs (friction)
  double eps_ = 0;                          ///< ε_v h
  int rounds_ = 0;                          ///< solves of this step with friction frozen so far
  FrictionStats friction_stats_;
};

/// Throws ArgumentError unless the settings are consistent (fields named as the scene's keys).
void check_contact(const ContactSettings& s) {
  check_penalty(s.penalty, "penalty.");
  check_friction(s.friction);
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
  if (settings.area_weighted) {
    const RestAreas area = rest_areas(model);
    for (Eigen::Index t = 0; t < area.triangle.size(); ++t)
      if (!(area.triangle[t] > 0))
        throw ArgumentError("area_weighted",
                            "triangle " + std::to_string(t) + " has no rest area to weigh its contacts by");
  }
  return std::make_unique<SelfContact<true>>(settings, model);
}

std::unique_ptr<Effect> make_self_edge_edge(const Model& model, const ContactSettings& settings) {
  check_contact(settings);
  check_penalty_for_model(settings.penalty, model, "penalty.");
  if (model.edges.cols() < 2) throw ArgumentError("", "self_edge_edge needs at least two edges");
  if (settings.area_weighted) {
    const Eigen::VectorXd area = rest_areas(model).edge;
    for (Eigen::Index e = 0; e < area.size(); ++e)
      if (!(area[e] > 0))
        throw ArgumentError("area_weighted", "edge " + std::to_string(e) + " (vertices " +
                                                 std::to_string(model.edges(0, e)) + ", " +
                                                 std::to_string(model.edges(1, e)) +
                                                 ") borders no triangle of positive area (a strand segment?): it has "
                                                 "no area to weigh its contacts by");
  }
  return std::make_unique<SelfContact<false>>(settings, model);
}

}  // namespace pce::sim
