// SPDX-License-Identifier: MIT
// Backward Euler by projected Newton on the incremental potential (modes newton and
// single_solve; pce/sim/simulation.hpp, docs/simulation.md §5.2). Per iteration from the
// iterate y: the effects that implement NewtonHooks begin the iteration at y (the pattern
// follows the pairs active there), inertia and every effect assemble the gradient and the
// PSD Hessian, H Δx = −g is solved, the hooks cover the step and bound it as the line search
// begins, the backtracking (Armijo) line search takes a trial, the hooks hear where it
// ended, and the effects whose candidates went stale (Requery) query again. A solve ends at
// a direction below the tolerance (with friction: whose friction residual is too), a failed
// line search or the cap; the hooks' end_solve may ask for another solve from its result.
#include "solver/linear_state.hpp"
#include "solver/step.hpp"

#include <pce/sim/newton_hooks.hpp>
#include <pce/sim/requery.hpp>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace pce::sim::solver {

namespace {

/// Newton's solver: its linear solver and Hessian (kept between steps), and one step's
/// iterate buffers and hooks.
class Newton final : public StepSolver {
 public:
  void solve(Step& s) override;
  void report(Step& s) const override {
    s.st.counters[Counter::pattern_blocks] = static_cast<double>(ls_.H.block_count());
    s.st.counters.merge(ls_.counters);
  }

 private:
  // The stages of a step, in order (docs/simulation.md §5.2).
  void rebuild_pattern(Step& s);
  void newton(Step& s);
  void assemble(Step& s, int it);
  void solve_direction(Step& s, int it);
  bool cover(Step& s);
  bool line_search(Step& s, int it, bool small_step, bool& converged);
  bool end_line_search(Step& s);
  void refresh(Step& s);
  bool end_solve(Step& s);
  /// The friction test at the step `step` from the iterate (displacements from xⁿ), over the
  /// hooks' frozen friction contacts: returns friction's residual, maxᵢ |δfᵢ| h/(mᵢ ℓ) with
  /// δfᵢ = Σₖ wₖᵢ T (φₖ − Fₖ) the error of Newton's model of the friction force at vertex i
  /// (`pce::friction_model_force` minus `pce::friction_force` after the step), and sets
  /// `load` to maxₖ |φₖ|/(μλ)ₖ (docs/simulation.md §5.2).
  double friction_residual(const Step& s, const Eigen::Matrix3Xd& step, double& load);
  /// Whether any hook froze a friction contact for this step.
  bool has_friction() const;

  LinearState ls_;
  std::vector<std::pair<std::size_t, NewtonHooks*>> hooks_;  ///< this step's, with their effects' indices
  std::vector<std::pair<std::size_t, Requery*>> requery_;    ///< this step's, with their effects' indices
  Eigen::Matrix3Xd g_, dxm_, y1_;                            ///< the iterate's gradient, the direction, a trial
  Eigen::Matrix3Xd friction_error_;                          ///< the friction test's δf per vertex
  Eigen::VectorXd dx_, rhs_;                                 ///< the direction and −g as vectors
  double E_ = 0;                                             ///< the energy at y with the current candidates
  bool covered_ = false;                                     ///< a hook queried again over this iteration's step
};

void Newton::solve(Step& s) {
  ls_.start_step();
  hooks_ = s.find<NewtonHooks>();
  requery_ = s.find<Requery>();
  const int n = s.n;
  g_.resize(3, n);
  dxm_.resize(3, n);
  y1_.resize(3, n);
  dx_.resize(3 * n);
  rhs_.resize(3 * n);
  rebuild_pattern(s);
  // One solve, or more when a hook asks for another from a solve's result (end_solve:
  // friction with lagged_iterations > 1, the obstacles' floor).
  do newton(s);
  while (end_solve(s));
}

double Newton::friction_residual(const Step& s, const Eigen::Matrix3Xd& step, double& load) {
  load = 0;
  friction_error_.setZero(3, s.n);
  Eigen::Matrix<double, 12, 1> dx, ddx;
  for (const auto& [k, e] : hooks_)
    for (const FrozenFriction& c : e->frozen_friction()) {
      for (int j = 0; j < 4; ++j) {
        const int v = c.vertices[static_cast<std::size_t>(j)];
        dx.segment<3>(3 * j) = s.y.col(v) - s.x_start.col(v);
        ddx.segment<3>(3 * j) = step.col(v);
      }
      const Eigen::Vector2d model = friction_model_force(c.friction, dx, ddx);
      load = std::max(load, model.norm() / c.friction.mu_lambda);
      const Eigen::Matrix<double, 12, 1> moved = dx + ddx;
      const Eigen::Vector3d error = c.friction.basis * (model - friction_force(c.friction, moved));
      for (int j = 0; j < 4; ++j)
        friction_error_.col(c.vertices[static_cast<std::size_t>(j)]) += c.friction.weights[j] * error;
    }
  // |δfᵢ| / (mᵢ/h²) is the move the error asks of vertex i if only its inertia resisted;
  // over h ℓ, in the residual's units.
  double residual = 0;
  for (int i = 0; i < s.n; ++i)
    if (const double m = s.inertia.vertex_mass(i); m > 0)
      residual = std::max(residual, friction_error_.col(i).norm() / m);
  return residual / (s.h * s.scale);
}

bool Newton::has_friction() const {
  for (const auto& [k, e] : hooks_)
    if (!e->frozen_friction().empty()) return true;
  return false;
}

/// The Hessian's pattern from every effect's declaration (a new symbolic analysis when it
/// changed).
void Newton::rebuild_pattern(Step& s) {
  double ms = 0;
  {
    const ScopedTimer timer(ms);
    Pattern pattern;
    for (const auto& e : s.effects) e->declare(pattern);
    if (ls_.H.set_pattern(s.n, pattern)) ls_.pattern_changed();
  }
  s.st.assembly_ms += ms;
  s.st.counters[Counter::pattern_ms] += ms;
  s.st.counters[Counter::pattern_builds] += 1;
}

/// One solve: Newton iterations from y until a direction below the tolerance (with friction:
/// and friction's residual, docs/simulation.md §5.2), a failed line search or the cap.
void Newton::newton(Step& s) {
  static const bool trace = std::getenv("PCE_SIM_TRACE") != nullptr;  // one line per Newton iteration on stderr
  const SolverSettings& solver = s.settings;
  const bool single_solve = solver.mode == SolverMode::single_solve;
  const int cap = single_solve ? 1 : std::max(1, solver.max_iterations);
  FrameStats& st = s.st;
  for (int it = 0; it < cap; ++it) {
    assemble(s, it);
    solve_direction(s, it);
    s.E_accepted = E_;
    // A step below the tolerance ends the iterations, unless Newton's model of the friction
    // force erred over it by more than the tolerance allows: static friction's Hessian
    // (2μλ/(ε_v h)) holds over a slip of ε_v h only, so it makes a step small far from the
    // solution when the contact must slide (docs/simulation.md §5.2).
    const bool small_step = st.residual < solver.tolerance;
    bool converged = small_step && !has_friction();
    covered_ = cover(s);
    const bool accepted = line_search(s, it, small_step, converged);
    if (trace)
      std::fprintf(
          stderr,
          "  it %d E %.9g slope %.3g alpha %.3g residual %.3g friction_residual %.3g friction_load %.3g accepted %d "
          "factorizations %d cg_iterations %d covered %d\n",
          it, E_, -rhs_.dot(dx_), st.iterations.back().alpha, st.residual, st.iterations.back().friction_residual,
          st.iterations.back().friction_load, accepted, static_cast<int>(ls_.counters.at(Counter::factorizations)),
          static_cast<int>(ls_.counters.at(Counter::cg_iterations)), int(covered_));
    if (!accepted) {
      // A direction below the tolerance whose trial does not pass Armijo is rounding, not a
      // failure: the iterate already meets the tolerance, and the energy's change along such
      // a direction (a free fall's second one is ~1e-13) is below its own rounding. (Its
      // friction test would pass: at a zero step the model's force is the force, ≤ μλ.)
      if (small_step) {
        st.stop = StopReason::rounding;
        return;
      }
      // A step the minimum separation cut to nothing (a pair held at its floor, pressed
      // further in): the held pairs' penalties grow, and Newton goes on from y with them.
      if (!end_line_search(s)) {
        ++st.line_search_failures;
        st.stop = StopReason::line_search;
        return;
      }
    } else {
      refresh(s);
      if (converged) {
        st.stop = StopReason::tolerance;
        return;
      }
    }
    if (it + 1 == cap) {
      st.stop = single_solve ? StopReason::single_solve : StopReason::iteration_cap;
      st.hit_iteration_cap = !single_solve;
    }
  }
}

/// Gradient and Hessian at y: inertia, then every effect (the pattern grows with the active
/// contacts); the energy into E_. A non-finite energy or gradient ends the run.
void Newton::assemble(Step& s, int it) {
  bool changed_pattern = false;
  for (const auto& [k, c] : hooks_) {
    const ScopedTimer timer(s.effect_ms[k]);
    changed_pattern = c->begin_iteration(s.y) || changed_pattern;
  }
  if (changed_pattern) rebuild_pattern(s);
  {
    const ScopedTimer timer(s.st.assembly_ms);
    ls_.H.set_zero();
    ls_.H.add_diagonal(s.inertia.diagonal());
  }
  s.inertia.gradient(s.y, g_);
  double E = s.inertia.assembled_energy(s.y);
  for (std::size_t k = 0; k < s.effects.size(); ++k) {
    const ScopedTimer timer(s.effect_ms[k]);
    E += s.effects[k]->evaluate(s.y, &g_, &ls_.H);
  }
  E_ = E;
  if (!std::isfinite(E) || !g_.allFinite()) s.fail_non_finite(s.y, "at Newton iteration " + std::to_string(it + 1));
}

/// The Newton direction H Δx = −g and its residual max|Δx|/(h ℓ); a failed solve ends the run.
void Newton::solve_direction(Step& s, int it) {
  FrameStats& st = s.st;
  bool solved = false;
  {
    const ScopedTimer timer(st.solve_ms);
    rhs_ = -Eigen::Map<const Eigen::VectorXd>(g_.data(), g_.size());
    ls_.positions = &s.y;
    solved = ls_.solve(s.settings, rhs_, dx_, s.settings.linear_tolerance);
  }
  if (!solved || !dx_.allFinite())
    throw SimulationError(st.frame, "", -1,
                          "frame " + std::to_string(st.frame) + ": the linear solve failed at Newton iteration " +
                              std::to_string(it + 1) + (solved ? " (a non-finite direction)" : ""));
  ++st.newton_iterations;
  dxm_ = Eigen::Map<const Eigen::Matrix3Xd>(dx_.data(), 3, s.n);
  st.residual = dxm_.colwise().norm().maxCoeff() / (s.h * s.scale);
}

/// Hooks whose candidates would go stale along the step query again over it (the pairs
/// active at y, hence the pattern, stay those of the new candidates); true if any did. Each
/// effect covers with its own candidate set and broad phase, so with two threads or more
/// the effects cover side by side (a vertex-face and an edge-edge effect usually query at the
/// same iteration); what each computes does not depend on it.
bool Newton::cover(Step& s) {
  bool covered = false;
  const long count = static_cast<long>(hooks_.size());
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1) reduction(|| : covered) if (count > 1)
  for (long j = 0; j < count; ++j) {
    const auto [k, c] = hooks_[static_cast<std::size_t>(j)];
    try {
      const ScopedTimer timer(s.effect_ms[k]);
      covered = c->cover_step(s.y, dxm_) || covered;
    } catch (...) {
#pragma omp critical(pce_sim_cover_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  return covered;
}

/// Backtracking line search (Armijo) from the largest step every hook allows as it begins;
/// records the iteration; true when a trial was accepted (y moves there). With friction, a
/// direction below the tolerance sets `converged` by the friction test at the step taken.
bool Newton::line_search(Step& s, int it, bool small_step, bool& converged) {
  FrameStats& st = s.st;
  const ScopedTimer timer(st.line_search_ms);
  double alpha = 1.0;
  NewtonIteration record;
  record.residual = st.residual;
  for (const auto& [k, e] : hooks_)
    if (const double t = e->begin_line_search(s.y, dxm_); t < alpha) {
      alpha = t;
      record.limited_by = s.effects[k]->name();
    }
  // The Armijo test compares trials with an energy of the same candidates (the sum's
  // rounding depends on them): after a new query, the energy at y again.
  if (covered_) {
    E_ = s.E_accepted = s.potential(s.y);
    s.evaluated_at_y = true;
    if (!std::isfinite(E_)) s.fail_non_finite(s.y, "at Newton iteration " + std::to_string(it + 1));
  }
  record.step_limit = alpha;
  const double slope = -rhs_.dot(dx_);  // gᵀΔx < 0 for a descent direction
  bool accepted = false;
  // Trial steps whose largest vertex motion is below a hundredth of the stopping
  // tolerance's are not tried: such a step cannot change the outcome, and trying them
  // (40 halvings) made a step at a kink of the energy cost ~40 energy passes.
  const double smallest = 0.01 * s.settings.tolerance / std::max(st.residual, 1e-300);
  for (int tries = 0; tries < 40 && alpha > 0 && (tries == 0 || alpha >= smallest); ++tries, alpha *= 0.5) {
    y1_ = s.y + alpha * dxm_;
    const double E1 = s.potential(y1_);
    s.evaluated_at_y = false;
    if (std::isfinite(E1) && E1 <= E_ + 1e-4 * alpha * slope) {
      if (small_step && has_friction()) {
        record.friction_residual = st.friction_residual = friction_residual(s, alpha * dxm_, record.friction_load);
        st.friction_load = record.friction_load;
        converged = st.friction_residual < s.settings.tolerance;
      }
      s.y = y1_;
      s.E_accepted = E1;
      accepted = true;
      s.evaluated_at_y = true;
      break;
    }
  }
  record.alpha = accepted ? alpha : 0.0;
  st.iterations.push_back(record);
  return accepted;
}

/// The hooks hear where the line search ended; true when one stiffened a held pair (the
/// energy at y changed, docs/simulation.md §4.6).
bool Newton::end_line_search(Step& s) {
  bool stiffened = false;
  for (const auto& [k, c] : hooks_) {
    const ScopedTimer timer(s.effect_ms[k]);
    stiffened = c->end_line_search(s.y) || stiffened;
  }
  if (stiffened) s.evaluated_at_y = false;
  return stiffened;
}

/// After an accepted trial: the hooks hear of it; effects whose candidates went stale at y
/// query again; the pattern follows.
void Newton::refresh(Step& s) {
  bool changed = false;
  end_line_search(s);
  for (const auto& [k, c] : requery_)
    if (!c->still_valid(s.y)) {
      {
        const ScopedTimer timer(s.effect_ms[k]);
        c->refresh(s.y);
      }
      changed = true;
      s.evaluated_at_y = false;
    }
  if (changed) rebuild_pattern(s);
}

/// A solve ended: hooks that freeze quantities at its result (friction with
/// lagged_iterations > 1) or change their energy there (the obstacles' floor) do so; true
/// when one did, and the step is solved again from y.
bool Newton::end_solve(Step& s) {
  bool again = false;
  for (const auto& [k, c] : hooks_) {
    const ScopedTimer timer(s.effect_ms[k]);
    again = c->end_solve(s.y) || again;
  }
  if (!again) return false;
  rebuild_pattern(s);
  s.evaluated_at_y = false;
  return true;
}

}  // namespace

std::unique_ptr<StepSolver> make_newton() { return std::make_unique<Newton>(); }

}  // namespace pce::sim::solver
