// SPDX-License-Identifier: MIT
// Self contact through pce's pair energies: the effects `self_vertex_face` and
// `self_edge_edge` (docs/simulation.md §4). This file wires the pipeline's rooms, one job each:
//  * candidates (candidate_set.*): broad-phase queries with radius r = d + m over a sweep,
//    the fold pairs, the set's validity and re-queries, and the per-pass filter;
//  * activity (activity.hpp): which candidates are active at a state, and how (plane or
//    closest features; fold pairs by their reach), and the settled sides of signed length;
//  * the pair potential (pair_potential.hpp): pce's energy, gradient and projected Hessian
//    of an active pair;
//  * active pairs (active_pairs.*): the sparsity pattern (exactly the pairs active at the
//    state) and the evaluation pass, in ordered chunks (ordered_chunks.hpp) scattered
//    serially in candidate order;
//  * the step bound (step_bound.*): additive CCD over the candidates and the set's
//    validity, with a barrier or `ccd`;
//  * the separation floor (separation_floor.*): pairs the step bound held at their
//    minimum separation have their penalties stiffened;
//  * friction (friction_freezing.*): the pairs active at a step's start, frozen;
//  * saved state (saved_state.*): what a checkpoint keeps;
//  * block descent (local_pairs.*): per-vertex bounds and per-vertex terms.
// No pair that shares a vertex, and no vertex inside a volume, is ever a candidate.
#include "active_pairs.hpp"
#include "friction_freezing.hpp"
#include "local_pairs.hpp"
#include "saved_state.hpp"
#include "separation_floor.hpp"
#include "step_bound.hpp"
#include "util/names.hpp"
#include "util/stopwatch.hpp"

#include <pce/sim/contact_effect.hpp>

#include <algorithm>
#include <memory>

namespace pce::sim {

namespace {

using namespace contact;

/// `ContactSettings::mesh_pairs` as CandidateSet's M×M table (empty: every pair); throws
/// ArgumentError (`meshes`) for a name the model does not have.
std::vector<char> allowed_mesh_pairs(const Model& model, const std::vector<std::array<std::string, 2>>& pairs) {
  if (pairs.empty()) return {};
  const std::size_t M = model.meshes.size();
  const auto index = [&](const std::string& name) {
    if (const MeshRange* r = find_named(model.meshes, name)) return static_cast<std::size_t>(r - model.meshes.data());
    throw ArgumentError("meshes", "unknown mesh \"" + name + "\"");
  };
  std::vector<char> allowed(M * M, 0);
  for (const auto& [a, b] : pairs) {
    const std::size_t i = index(a), j = index(b);
    allowed[i * M + j] = allowed[j * M + i] = 1;
  }
  return allowed;
}

template <bool VF> class SelfContact final : public ContactEffect {
 public:
  SelfContact(const ContactSettings& settings, const Model& model)
      : ContactEffect(VF ? "self_vertex_face" : "self_edge_edge"),
        settings_(settings),
        model_(&model),
        areas_(settings.area_weighted ? rest_areas(model) : RestAreas{}),
        candidates_(model, settings.broad_phase, settings.penalty.distance, bounded(),
                    allowed_mesh_pairs(model, settings.mesh_pairs)),
        classifier_(settings_, candidates_, areas_),
        potential_(settings_, candidates_, classifier_),
        active_(settings_, candidates_, classifier_, potential_),
        step_bound_(candidates_, classifier_),
        floor_(candidates_, classifier_),
        friction_(settings_, candidates_, classifier_),
        local_(settings_, candidates_, classifier_, potential_) {}

  void begin_step(const StepContext& ctx) override {
    x_start_ = ctx.x_start;
    inertial_motion_ = ctx.dt * ctx.v_start->colwise().norm().maxCoeff();
    stats_ = {};
    local_.forget();
    // (a kept set keeps what its passes recorded: each record names the state it was made at)
    if (candidates_.begin_step(*ctx.x_start, *ctx.x_start + ctx.dt * *ctx.v_start, previous_)) carry_over();
    floor_.begin_step(*ctx.x_start);
    if (settings_.friction) friction_.begin_step(ctx);
  }

  bool end_solve(const Eigen::Matrix3Xd& x) override { return settings_.friction && friction_.update_lagged(x); }

  bool end_line_search(const Eigen::Matrix3Xd& x) override {
    return bounded() && !step_bound_.held().empty() && floor_.stiffen(x, step_bound_.held());
  }

  bool still_valid(const Eigen::Matrix3Xd& x) override { return candidates_.still_valid(x); }

  bool cover_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override {
    if (!bounded()) return false;
    // A step may move a vertex 16 d, or twice the farthest inertial motion of the time step
    // when that is larger, and still be covered by one query.
    const double reach = std::max(8 * 2 * settings_.penalty.distance, 2 * inertial_motion_);
    if (!candidates_.cover(x, dx, reach, previous_)) return false;
    carry_over();
    return true;
  }

  double safe_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override {
    const double reach = std::max(8 * 2 * settings_.penalty.distance, 2 * inertial_motion_);
    if (candidates_.cover(x, dx, reach, previous_, true)) carry_over();
    step_bound_.invalidate();
    return step_bound_.max_step(x, dx);
  }

  void vertex_bounds(const Eigen::Matrix3Xd& x, Eigen::VectorXd& bound) override {
    // A set still valid at x has every other pair more than d apart there; after a query at
    // x, more than the query radius.
    double apart = settings_.penalty.distance;
    if (!candidates_.has_query(x) || !candidates_.still_valid(x)) {
      candidates_.query_at(x, previous_);
      carry_over();
      apart = candidates_.query_radius();
    }
    local_.bounds(*model_, x, apart, bound);
  }

  void begin_sweep(const Eigen::Matrix3Xd& x, const Eigen::VectorXd& reach, Pattern& couplings) override {
    const ScopedTimer timer(stats_.pair_ms);
    local_.begin_sweep(x, reach, couplings);
    if (settings_.friction) friction_.declare(couplings);
  }

  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override {
    if (!local_.ready()) {  // no sweep listed its pairs: the pairs active at x, evaluated whole
      active_.update_pattern(x);
      return Effect::evaluate_local(x, vertices, terms);
    }
    {
      const ScopedTimer timer(stats_.pair_ms);
      local_.evaluate(x, vertices, terms);
    }
    if (settings_.friction) friction_.evaluate_local(x, vertices, terms);
  }

  void refresh(const Eigen::Matrix3Xd& x) override {
    candidates_.refresh(x, previous_);
    carry_over();
  }

  void declare(Pattern& pattern) const override {
    active_.declare(pattern);
    if (settings_.friction) friction_.declare(pattern);
  }

  bool begin_iteration(const Eigen::Matrix3Xd& x) override { return active_.update_pattern(x); }

  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) override {
    double energy = active_.evaluate(x, gradient, hessian, step_bound_.segment_at(x), stats_);
    if (settings_.friction) energy += friction_.evaluate(x, gradient, hessian);
    if (!std::isfinite(energy)) return std::numeric_limits<double>::infinity();
    return energy;
  }

  double begin_line_search(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) override {
    step_bound_.invalidate();
    return bounded() ? step_bound_.max_step(x, dx) : 1.0;
  }

  const std::vector<FrozenFriction>& frozen_friction() const override {
    return settings_.friction ? friction_.published() : NewtonHooks::frozen_friction();
  }

  void report(EffectCounters& c) const override {
    const auto& q = candidates_.stats();
    c[VF ? Counter::vertex_face_candidates : Counter::edge_edge_candidates] = static_cast<double>(candidates_.size());
    c[VF ? Counter::vertex_face_declared : Counter::edge_edge_declared] =
        static_cast<double>(std::count(active_.declared().begin(), active_.declared().end(), char(1)));
    c[VF ? Counter::vertex_face_rest_neighbours : Counter::edge_edge_rest_neighbours] =
        static_cast<double>(candidates_.fold_pairs());
    c[VF ? Counter::vertex_face_fold_contacts : Counter::edge_edge_fold_contacts] =
        static_cast<double>(stats_.fold_active);
    c[VF ? Counter::vertex_face_contacts : Counter::edge_edge_contacts] = static_cast<double>(stats_.active);
    c[VF ? Counter::vertex_face_min_distance : Counter::edge_edge_min_distance] = stats_.min_length;
    c[Counter::floor_holds] = static_cast<double>(floor_.holds());
    c[Counter::stiffened_pairs] = static_cast<double>(floor_.stiffened());
    c[Counter::broad_phase_ms] = q.broad_phase_ms + stats_.settle_ms;
    c[Counter::broad_phase_tree_ms] = q.tree_ms;
    c[Counter::broad_phase_queries] = q.queries;
    c[Counter::pair_ms] = stats_.pair_ms;
    c[Counter::scatter_ms] = stats_.scatter_ms;
    if (settings_.friction) friction_.report(c);
  }

  std::string save_state() const override {
    SavedContact s;
    s.pairs = candidates_.pairs();
    s.sides = classifier_.sides();
    s.declared = active_.declared();
    s.stiffening = classifier_.stiffening();
    const Eigen::Matrix3Xd &at = candidates_.query_point(), &to = candidates_.query_to();
    s.with_query = at.cols() == model_->vertex_count() && to.cols() == at.cols() && at.cols() > 0;
    if (s.with_query) {
      s.validity_bound = candidates_.validity_bound();
      s.at = at;
      s.to = to;
    }
    return encode(s);
  }

  void load_state(const std::string& state) override {
    const long first_max = VF ? model_->vertex_count() : model_->edges.cols();
    const long second_max = VF ? model_->triangles.cols() : model_->edges.cols();
    SavedContact s = decode(state, name(), model_->vertex_count(), first_max, second_max);
    if (s.with_query)
      candidates_.restore(std::move(s.pairs), s.at, s.to, s.validity_bound);
    else
      candidates_.restore(std::move(s.pairs));
    classifier_.sides() = std::move(s.sides);
    classifier_.stiffening() = std::move(s.stiffening);
    active_.restore(std::move(s.declared));
    step_bound_.invalidate();
  }

 private:
  /// The effect bounds its steps: a barrier, or `ccd`.
  bool bounded() const { return settings_.penalty.barrier() || settings_.ccd; }

  /// After a query: pairs already tracked keep their side and their declaration (until the
  /// next update_pattern); new pairs start undeclared, with their side settled at xⁿ.
  void carry_over() {
    const ScopedTimer timer(stats_.settle_ms);
    local_.forget();
    active_.carry_over(previous_);
    step_bound_.invalidate();
    floor_.carry_over(previous_);
    std::vector<signed char>& sides = classifier_.sides();
    std::vector<signed char> carried(previous_.size(), 0);
    for (std::size_t k = 0; k < previous_.size(); ++k)
      if (previous_[k] >= 0) carried[k] = sides[static_cast<std::size_t>(previous_[k])];
    sides = std::move(carried);
    if (settings_.signed_length) classifier_.settle_sides(*x_start_);
  }

  ContactSettings settings_;
  const Model* model_;
  RestAreas areas_;  ///< rest areas (area_weighted), else empty
  CandidateSet<VF> candidates_;
  Classifier<VF> classifier_;
  PairPotential<VF> potential_;
  ActivePairs<VF> active_;
  StepBound<VF> step_bound_;
  SeparationFloor<VF> floor_;
  FrictionFreezing<VF> friction_;
  LocalPairs<VF> local_;
  const Eigen::Matrix3Xd* x_start_ = nullptr;
  double inertial_motion_ = 0;  ///< max |h vᵢⁿ| of the step (cover_step's reach)
  std::vector<long> previous_;  ///< per candidate of the last query: its former index, or −1
  ContactStats stats_;
};

/// Throws ArgumentError unless the settings are consistent (fields named as the scene's keys).
void check_contact(const ContactSettings& s) {
  check_penalty(s.penalty, "penalty.");
  check_friction(s.friction);
  check_min_separation(s.min_separation);
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

std::unique_ptr<ContactEffect> make_self_vertex_face(const Model& model, const ContactSettings& settings) {
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

std::unique_ptr<ContactEffect> make_self_edge_edge(const Model& model, const ContactSettings& settings) {
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
