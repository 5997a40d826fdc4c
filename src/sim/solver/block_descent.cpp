// SPDX-License-Identifier: MIT
// Vertex block descent (Chen, Macklin, Yang & Kim 2024, "Vertex block descent", ACM TOG
// 43(4)) on the incremental potential, with per-vertex conservative bounds (Chen et al.
// 2025, "Offset geometric contact"): docs/simulation.md §5.5.
//
// A step: (1) the first move from xⁿ towards x̃ + h² a (x̃ = xⁿ + h vⁿ the inertial
// prediction, a the acceleration fields', gravity's, `AccelerationField`: the paper's initialisation), each
// vertex as far as the obstacles let it alone (`BlockDescentHooks::limit_moves`), then the whole
// move as far as every contact effect finds safe (`BlockDescentHooks::safe_step`: conservative
// advancement over the candidates and the obstacles' surfaces); (2) the contact effects' per-vertex
// bounds at that state (`vertex_bounds`); (3) `iterations` sweeps: the vertices are
// coloured so that no two of one colour share an element or a contact pair the sweep can
// find active (greedy, solver/colouring.*; again whenever those pairs change; the
// elements' couplings from `Effect::declare` of the effects without block descent's hooks), and colour by
// colour every vertex takes one Newton step on its own 3×3 problem
//     (mᵢ/h² I + Hᵢᵢ) Δxᵢ = −(mᵢ/h² (xᵢ − x̃ᵢ) + ∂E/∂xᵢ),
// with Hᵢᵢ the diagonal blocks of the effects' PSD Hessians (`Effect::evaluate_local`),
// cut to the ball of its bound about the bounds' state and to a trust region about its
// position at the sweep's start (twice its move in the sweep before, at least an eighth of
// its bound: what a contact effect's local terms of the sweep can reach is listed from
// these radii, `begin_sweep`, so they stay short). A sweep after which a vertex was
// cut, or an effect's candidates went stale (`Requery::still_valid`), measures the bounds
// again at its result; with `redetect_share` > 0, only one after which more than that share
// of the vertices were cut (Offset geometric contact's rule: until then a stale set's new
// pairs add no terms, and the bounds about the state they were measured at still hold). The vertices of a colour read
// the positions of the colour's start and are written after all have been computed, so nothing depends on the thread
// count. With `Acceleration::chebyshev`, after each sweep the vertices no active contact pair acted on in it are
// extrapolated (Chebyshev's semi-iteration, `accelerate`), cut to their bounds; an extrapolation that raises the
// incremental potential above the last accepted iterate's is undone and the recurrence restarts. A sweep whose residual
// is at most `sweep_tolerance` ends the step.
#include "solver/colouring.hpp"
#include "solver/step.hpp"

#include <pce/sim/block_descent_hooks.hpp>
#include <pce/sim/requery.hpp>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace pce::sim::solver {

namespace {

/// A vertex's trust region in a sweep: this many times its move in the sweep before…
constexpr double kTrustGrowth = 2;
/// …and at least this share of its bound.
constexpr double kTrustShare = 0.125;

/// Block descent's solver: what it keeps between steps (buffers and the colouring of the
/// elements) and one step's hooks.
class BlockDescent final : public StepSolver {
 public:
  void solve(Step& s) override;

 private:
  void first_move(Step& s);
  void measure_bounds(Step& s);
  /// Returns true when the sweep's residual met `sweep_tolerance`.
  bool sweep(Step& s, int index);
  /// Chebyshev's extrapolation of the sweep just done (from `older_`), see the file comment;
  /// returns the vertices it moved to their bound.
  long accelerate(Step& s, SweepRecord& record);
  /// Queries the candidate sets that are stale at y again; returns whether one was.
  bool refresh_stale(Step& s);
  /// The incremental potential at y with candidates valid there (`refresh_stale` first).
  double energy_at_y(Step& s);
  /// One colour's vertices, each by its own 3×3 Newton step cut to its bound and trust
  /// region; returns the largest move and adds the vertices that used their bound to `cut`.
  double move_colour(Step& s, const std::vector<int>& colour, int index, long& cut);

  std::vector<std::pair<std::size_t, BlockDescentHooks*>> hooks_;  ///< this step's, with their effects' indices
  std::vector<std::pair<std::size_t, Requery*>> requery_;          ///< this step's, with their effects' indices
  Colouring colouring_;
  LocalTerms terms_;
  Eigen::VectorXd bound_;    ///< per vertex: how far it may move from `anchor_`
  Eigen::VectorXd reach_;    ///< per vertex: how far it can move in the current sweep
  Eigen::Matrix3Xd anchor_;  ///< the state the bounds were measured at
  Eigen::Matrix3Xd next_;    ///< a colour's new positions
  std::vector<char> cut_, bad_;
  std::vector<double> motion_;
  Eigen::VectorXd moved_;   ///< per vertex: its move in the last sweep
  Eigen::VectorXd limit_;   ///< per vertex: the fraction of the first move the one-vertex effects allow
  Eigen::Matrix3Xd field_;  ///< per vertex: the state-independent acceleration (gravity), a
  // Chebyshev's acceleration (`accelerate`):
  Eigen::Matrix3Xd before_;     ///< the sweep's start, x⁽ᵏ⁾
  Eigen::Matrix3Xd older_;      ///< the sweep before's start, x⁽ᵏ⁻¹⁾
  Eigen::Matrix3Xd plain_;      ///< the sweep's own result x̄, to undo an extrapolation to
  std::vector<char> coupled_;   ///< per vertex: a contact pair acted on it in the sweep (`LocalTerms::contact`)
  int run_ = 0;                 ///< sweeps since the recurrence (re)started
  double omega_ = 1;            ///< ω of the last sweep
  double accepted_energy_ = 0;  ///< the potential at the last accepted iterate (run_ > 0)
  bool refreshed_ = false;      ///< energy_at_y queried a candidate set again in this sweep
};

void BlockDescent::solve(Step& s) {
  hooks_ = s.find<BlockDescentHooks>();
  requery_ = s.find<Requery>();
  first_move(s);
  // The elements' couplings (unchanged from step to step unless an effect's declaration is).
  {
    const ScopedTimer timer(s.st.assembly_ms);
    Pattern elements;
    for (const auto& e : s.effects)
      if (!dynamic_cast<const BlockDescentHooks*>(e.get())) e->declare(elements);
    colouring_.set_static(s.n, elements.pairs());
    colouring_.restart();
  }
  measure_bounds(s);
  run_ = 0;
  if (s.settings.acceleration == Acceleration::chebyshev) {  // reported, 0 or not
    s.st.counters[Counter::accelerated_sweeps] += 0;
    s.st.counters[Counter::acceleration_restarts] += 0;
  }
  bool met = false;
  for (int k = 0; k < s.settings.iterations && !met; ++k) met = sweep(s, k);
  // The accepted state's energy and counters are to see every pair within reach there.
  refresh_stale(s);
  s.st.counters[Counter::colours] = static_cast<double>(colouring_.colours().size());
  s.st.stop = met ? StopReason::tolerance : StopReason::sweeps;
  s.evaluated_at_y = false;
}

/// (1) The first move: inertia and the acceleration fields (gravity), x̃ + h² a. Hooks of
/// one-vertex pairs stop the vertices they must (`limit_moves`), then the move they leave is
/// cut to what every hook finds safe: a vertex landing on an obstacle does not hold back the
/// rest of its sheet.
void BlockDescent::first_move(Step& s) {
  const int n = s.n;
  const double h = s.h;
  field_.setZero(3, n);
  for (const auto& [k, a] : s.find<AccelerationField>()) a->add_acceleration(field_);
  Eigen::Matrix3Xd dx = (s.inertia.target() - s.x_start) + h * h * field_;
  limit_.setOnes(n);
  for (const auto& [k, c] : hooks_) {
    const ScopedTimer timer(s.effect_ms[k]);
    c->limit_moves(s.y, dx, limit_);
  }
  for (int i = 0; i < n; ++i) dx.col(i) *= limit_[i];
  double t = 1;
  for (const auto& [k, c] : hooks_) {
    const ScopedTimer timer(s.effect_ms[k]);
    t = std::min(t, c->safe_step(s.y, dx));
  }
  s.y = s.x_start + t * dx;
  s.st.counters[Counter::first_move] = t * limit_.mean();
}

/// (2) The bounds at y.
void BlockDescent::measure_bounds(Step& s) {
  bound_.setConstant(s.n, std::numeric_limits<double>::infinity());
  for (const auto& [k, c] : hooks_) {
    const ScopedTimer timer(s.effect_ms[k]);
    c->vertex_bounds(s.y, bound_);
  }
  anchor_ = s.y;
  s.st.counters[Counter::bound_measurements] += 1;
}

/// (3) One sweep over every colour; the bounds again after it when a vertex used its bound
/// or a candidate set went stale.
bool BlockDescent::sweep(Step& s, int index) {
  const int n = s.n;
  const bool chebyshev = s.settings.acceleration == Acceleration::chebyshev;
  if (chebyshev) before_ = s.y;
  refreshed_ = false;
  coupled_.assign(static_cast<std::size_t>(n), 0);
  if (index == 0) moved_.setZero(n);
  reach_.resize(n);
  for (int i = 0; i < n; ++i)
    reach_[i] = std::min(bound_[i] + (s.y.col(i) - anchor_.col(i)).norm(),
                         std::max(kTrustGrowth * moved_[i], kTrustShare * bound_[i]));
  Pattern couplings;
  for (const auto& [k, c] : hooks_) {
    const ScopedTimer timer(s.effect_ms[k]);
    c->begin_sweep(s.y, reach_, couplings);
  }
  {
    const ScopedTimer timer(s.st.assembly_ms);
    if (colouring_.colour(couplings.pairs())) s.st.counters[Counter::colourings] += 1;
  }
  double largest = 0;
  long cut = 0;
  for (const std::vector<int>& colour : colouring_.colours())
    largest = std::max(largest, move_colour(s, colour, index, cut));
  SweepRecord record;
  if (chebyshev) cut += accelerate(s, record);
  FrameStats& st = s.st;
  ++st.sweeps;
  record.residual = largest / (s.h * s.scale);
  record.bound_clamps = cut;
  st.residual = record.residual;
  st.sweep_records.push_back(record);
  st.counters[Counter::bound_clamps] += static_cast<double>(cut);
  // The bounds again: after any cut or stale set, or (redetect_share > 0) only once more
  // than that share of the vertices were cut (the bounds about anchor_ keep holding).
  const double share = s.settings.redetect_share;
  bool stale = share > 0 ? static_cast<double>(cut) > share * n : cut > 0 || refreshed_;
  if (!(share > 0))
    for (const auto& [k, c] : requery_) stale = !c->still_valid(s.y) || stale;
  const bool met = record.residual <= s.settings.sweep_tolerance;
  if (stale && index + 1 < s.settings.iterations && !met) measure_bounds(s);
  return met;
}

bool BlockDescent::refresh_stale(Step& s) {
  bool any = false;
  for (const auto& [k, c] : requery_)
    if (!c->still_valid(s.y)) {
      const ScopedTimer timer(s.effect_ms[k]);
      c->refresh(s.y);
      any = true;
    }
  return any;
}

double BlockDescent::energy_at_y(Step& s) {
  if (refresh_stale(s)) refreshed_ = true;
  const ScopedTimer timer(s.st.line_search_ms);
  return s.potential(s.y);
}

long BlockDescent::accelerate(Step& s, SweepRecord& record) {
  const int n = s.n;
  const double rho2 = s.settings.chebyshev_rho * s.settings.chebyshev_rho;
  // ω₁ = 1 (the sweep as it is), ω₂ = 2/(2 − ρ²), ω_k = 4/(4 − ρ² ω_{k−1}).
  const double omega = run_ == 0 ? 1.0 : run_ == 1 ? 2 / (2 - rho2) : 4 / (4 - rho2 * omega_);
  long cut = 0;
  if (run_ == 0) {
    accepted_energy_ = energy_at_y(s);
  } else {
    plain_ = s.y;
    for (int i = 0; i < n; ++i) {
      if (coupled_[static_cast<std::size_t>(i)]) continue;
      Eigen::Vector3d p = older_.col(i) + omega * (plain_.col(i) - older_.col(i));
      const Eigen::Vector3d r = p - anchor_.col(i);
      const double rn = r.norm();
      if (rn > bound_[i]) {
        p = anchor_.col(i) + (bound_[i] / rn) * r;
        ++cut;
      }
      s.y.col(i) = p;
      moved_[i] = std::max(moved_[i], (p - before_.col(i)).norm());
    }
    const double E = energy_at_y(s);
    s.st.counters[Counter::accelerated_sweeps] += 1;
    if (E > accepted_energy_ || !std::isfinite(E)) {
      // Undone: the sweep's own result stands, and the recurrence starts again from it.
      s.y = plain_;
      s.st.counters[Counter::acceleration_restarts] += 1;
      accepted_energy_ = energy_at_y(s);
      record.energy = accepted_energy_;
      run_ = 1;
      omega_ = 1;
      older_ = before_;
      return 0;
    }
    accepted_energy_ = E;
    record.accelerated = true;
  }
  record.energy = accepted_energy_;
  omega_ = omega;
  ++run_;
  older_ = before_;
  return cut;
}

double BlockDescent::move_colour(Step& s, const std::vector<int>& colour, int index, long& cut) {
  const auto m = static_cast<long>(colour.size());
  terms_.reset(colour.size());
  for (std::size_t k = 0; k < s.effects.size(); ++k) {
    const ScopedTimer timer(s.effect_ms[k]);
    s.effects[k]->evaluate_local(s.y, colour, terms_);
  }
  const ScopedTimer timer(s.st.solve_ms);
  next_.resize(3, m);
  cut_.assign(static_cast<std::size_t>(m), 0);
  bad_.assign(static_cast<std::size_t>(m), 0);
  motion_.assign(static_cast<std::size_t>(m), 0.0);
  const Eigen::Matrix3Xd& target = s.inertia.target();
#pragma omp parallel for schedule(static) if (m >= 64)
  for (long j = 0; j < m; ++j) {
    const auto uj = static_cast<std::size_t>(j);
    const int i = colour[uj];
    const double mh = s.inertia.vertex_mass(i);
    const Eigen::Vector3d yi = s.y.col(i);
    const Eigen::Vector3d g = terms_.gradient.col(j) + mh * (yi - target.col(i));
    const Eigen::Matrix3d H = terms_.hessian[uj] + mh * Eigen::Matrix3d::Identity();
    const Eigen::LLT<Eigen::Matrix3d> llt(H);
    Eigen::Vector3d p = yi - llt.solve(g);
    if (llt.info() != Eigen::Success || !p.allFinite()) {
      bad_[uj] = 1;
      p = yi;
    }
    const Eigen::Vector3d r = p - anchor_.col(i);
    const double rn = r.norm();
    if (rn > bound_[i]) p = anchor_.col(i) + (bound_[i] / rn) * r;
    // then the trust region (p and yᵢ both lie in the bound's ball, so their chord does)
    const double step = (p - yi).norm();
    if (step > reach_[i]) p = yi + (reach_[i] / step) * (p - yi);
    // the vertex used its bound: it ends on the ball's surface
    cut_[uj] = rn > bound_[i] && (p - anchor_.col(i)).norm() >= bound_[i] * (1 - 1e-9);
    coupled_[static_cast<std::size_t>(i)] = terms_.contact[uj];
    motion_[uj] = (p - yi).norm();
    next_.col(j) = p;
  }
  double largest = 0;
  for (long j = 0; j < m; ++j) {
    const auto uj = static_cast<std::size_t>(j);
    if (bad_[uj]) s.fail_non_finite(s.y, "at block descent sweep " + std::to_string(index + 1));
    s.y.col(colour[uj]) = next_.col(j);
    moved_[colour[uj]] = motion_[uj];
    cut += cut_[uj];
    largest = std::max(largest, motion_[uj]);
  }
  return largest;
}

}  // namespace

std::unique_ptr<StepSolver> make_block_descent() { return std::make_unique<BlockDescent>(); }

}  // namespace pce::sim::solver
