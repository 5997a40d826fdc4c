// SPDX-License-Identifier: MIT
// Backward Euler by projected Newton on the incremental potential (simulation.hpp).
#include "effects/arguments.hpp"
#include "solver/linear_state.hpp"
#include "solver/step_state.hpp"
#include "util/names.hpp"
#include "util/stopwatch.hpp"

#include <pce/sim/contact_effect.hpp>
#include <pce/sim/effects.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/simulation.hpp>

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pce::sim {

double Simulation::potential(const Eigen::Matrix3Xd& y, std::vector<double>* effect_ms) {
  const Eigen::Map<const Eigen::VectorXd> d(y.data() - 0, y.size());
  const Eigen::Map<const Eigen::VectorXd> t(x_tilde_.data(), x_tilde_.size());
  double E = 0.5 * (mass3_.array() * (d - t).array().square()).sum();
  for (std::size_t k = 0; k < effects.size(); ++k) {
    double ms = 0;
    {
      const ScopedTimer timer(ms);
      E += effects[k]->evaluate(y, nullptr, nullptr);
    }
    if (effect_ms) (*effect_ms)[k] += ms;
  }
  return E;
}

const char* to_string(StopReason reason) { return name_of(reason).data(); }

void Simulation::start_at_rest() {
  x = model.rest;
  v = Eigen::Matrix3Xd::Zero(3, model.vertex_count());
  frame = 0;
  time = 0;
}

void Simulation::check() const {
  const Eigen::Index n = model.rest.cols();
  const std::string count = std::to_string(n);
  if (n == 0) throw ArgumentError("model", "the model has no vertices (build it with build_model)");
  if (model.mass.size() != n || !(model.mass.array() > 0).all() || !model.mass.allFinite())
    throw ArgumentError("model.mass", "expected " + count + " finite masses > 0, one per vertex");
  if (x.cols() != n || v.cols() != n)
    throw ArgumentError("x", "x has " + std::to_string(x.cols()) + " columns and v " + std::to_string(v.cols()) +
                                 ", the model " + count + " vertices (start_at_rest() sets both)");
  if (!(std::isfinite(solver.dt) && solver.dt > 0)) throw ArgumentError("solver.dt", "expected a finite number > 0");
  if (!(std::isfinite(solver.tolerance) && solver.tolerance > 0))
    throw ArgumentError("solver.tolerance", "expected a finite number > 0");
  if (solver.max_iterations < 1) throw ArgumentError("solver.max_iterations", "expected at least 1");
  if (solver.iterations < 1) throw ArgumentError("solver.iterations", "expected at least 1");
  if (!(std::isfinite(solver.reuse_tolerance) && solver.reuse_tolerance > 0))
    throw ArgumentError("solver.reuse_tolerance", "expected a finite number > 0");
  if (solver.reuse_max_cg_iterations < 0) throw ArgumentError("solver.reuse_max_cg_iterations", "expected at least 0");
  for (std::size_t k = 0; k < effects.size(); ++k)
    if (!effects[k]) throw ArgumentError("effects[" + std::to_string(k) + "]", "expected an effect, got null");
}

void Simulation::fail_non_finite(const Eigen::Matrix3Xd& y, int frame_number, const std::string& where) {
  const std::string head = "frame " + std::to_string(frame_number) + ", " + where + ": ";
  const auto first_bad_column = [](const Eigen::Matrix3Xd& m) {
    for (Eigen::Index i = 0; i < m.cols(); ++i)
      if (!m.col(i).allFinite()) return static_cast<int>(i);
    return -1;
  };
  if (const int i = first_bad_column(y); i >= 0)
    throw SimulationError(frame_number, "", i, head + "the position of vertex " + std::to_string(i) + " is not finite");
  // The inertia term is finite at a finite y: one of the effects is to blame. Each is
  // evaluated alone, in scene order, and the first with a non-finite energy or gradient named.
  Eigen::Matrix3Xd g(3, y.cols());
  for (const auto& e : effects) {
    g.setZero();
    const double E = e->evaluate(y, &g, nullptr);
    const int i = first_bad_column(g);
    if (i >= 0)
      throw SimulationError(frame_number, e->name(), i,
                            head + "effect \"" + e->name() + "\" gives a non-finite gradient at vertex " +
                                std::to_string(i) + " (energy " + std::to_string(E) + ")");
    if (!std::isfinite(E))
      throw SimulationError(
          frame_number, e->name(), -1,
          head + "effect \"" + e->name() + "\" gives a non-finite energy (" + std::to_string(E) + ")");
  }
  throw SimulationError(frame_number, "", -1, head + "the energy or its gradient is not finite");
}

double Simulation::friction_load(const StepState& s, const Eigen::Matrix3Xd& step) const {
  const Eigen::Matrix3Xd &y = s.y, &x_start = s.x_start;
  double load = 0;
  Eigen::Matrix<double, 12, 1> dx, ddx;
  for (const auto& [k, e] : s.contacts)
    for (const FrozenFriction& c : e->frozen_friction()) {
      for (int j = 0; j < 4; ++j) {
        const int v = c.vertices[static_cast<std::size_t>(j)];
        dx.segment<3>(3 * j) = y.col(v) - x_start.col(v);
        ddx.segment<3>(3 * j) = step.col(v);
      }
      load = std::max(load, friction_model_force(c.friction, dx, ddx).norm() / c.friction.mu_lambda);
    }
  return load;
}

bool Simulation::has_friction(const StepState& s) const {
  for (const auto& [k, e] : s.contacts)
    if (!e->frozen_friction().empty()) return true;
  return false;
}

FrameStats Simulation::step() {
  const auto t_frame = Clock::now();
  check();
  if (!linear_) linear_ = std::make_shared<LinearState>();
  if (solver.threads > 0) omp_set_num_threads(solver.threads);
  LinearState& ls = *linear_;
  ls.start_step();
  StepState s(ls, model.vertex_count());
  s.t_frame = t_frame;
  predict(s);
  // One solve, or more when an effect freezes quantities again at a solve's result
  // (update_lagged: friction with lagged_iterations > 1).
  if (solver.mode == SolverMode::block_descent) {
    block_descent(s);
  } else {
    do newton(s);
    while (update_lagged(s));
  }
  accept(s);
  report(s);
  return s.st;
}

void Simulation::set_obstacle_pose(const std::string& name, const Eigen::Isometry3d& pose) {
  const auto it = std::find_if(obstacles.begin(), obstacles.end(), [&](const Obstacle& o) { return o.name == name; });
  if (it == obstacles.end()) {
    const std::string names = names_of(obstacles);
    throw ArgumentError("name", "no obstacle named \"" + name +
                                    "\" (the obstacles: " + (names.empty() ? std::string("none") : names) + ")");
  }
  args::position("translation", pose.translation());
  args::rotation("rotation", pose.linear());
  const PlacedPose placed{time + 0.5 * solver.dt, pose};
  it->place(placed);
  for (const std::unique_ptr<Effect>& e : effects)
    if (auto* contact = dynamic_cast<ObstacleContactEffect*>(e.get())) contact->place_obstacle(name, placed);
}

/// Per-step constants (M/h² per coordinate, the inertial target x̃ = xⁿ + h vⁿ, the length
/// scale ℓ), every effect's begin_step, the frozen friction contacts, the pattern.
void Simulation::predict(StepState& s) {
  const int n = s.n;
  const double h = solver.dt;
  s.st.frame = frame + 1;
  s.effect_ms.assign(effects.size(), 0.0);
  mass3_.resize(3 * n);
  for (int i = 0; i < n; ++i) mass3_.segment<3>(3 * i).setConstant(model.mass[i] / (h * h));
  s.x_start = x;
  s.v_start = v;
  x_tilde_ = x + h * v;
  scale_ = std::max((model.rest.rowwise().maxCoeff() - model.rest.rowwise().minCoeff()).norm(), 1e-12);
  StepContext ctx;
  ctx.frame = frame + 1;
  ctx.time = time + h;
  ctx.dt = h;
  ctx.model = &model;
  ctx.x_start = &s.x_start;
  ctx.v_start = &s.v_start;
  for (std::size_t k = 0; k < effects.size(); ++k) {
    {
      const ScopedTimer timer(s.effect_ms[k]);
      effects[k]->begin_step(ctx);
    }
    if (ContactEffect* c = as_contact(effects[k].get())) s.contacts.emplace_back(k, c);
  }
  if (solver.mode != SolverMode::block_descent) rebuild_pattern(s);  // block descent assembles no matrix
  s.y = s.x_start;
  s.g.resize(3, n);
  s.dxm.resize(3, n);
  s.y1.resize(3, n);
  s.dx.resize(3 * n);
  s.rhs.resize(3 * n);
}

/// The Hessian's pattern from every effect's declaration (a new symbolic analysis when it
/// changed).
void Simulation::rebuild_pattern(StepState& s) {
  double ms = 0;
  {
    const ScopedTimer timer(ms);
    Pattern pattern;
    for (const auto& e : effects) e->declare(pattern);
    if (s.ls.H.set_pattern(s.n, pattern)) s.ls.analyzed = false;
  }
  s.st.assembly_ms += ms;
  s.st.counters[Counter::pattern_ms] += ms;
  s.st.counters[Counter::pattern_builds] += 1;
}

/// One solve: Newton iterations from y until a direction below the tolerance (with friction:
/// within Coulomb's bound, docs/simulation.md §5.2), a failed line search or the cap.
void Simulation::newton(StepState& s) {
  static const bool trace = std::getenv("PCE_SIM_TRACE") != nullptr;  // one line per Newton iteration on stderr
  const bool single_solve = solver.mode == SolverMode::single_solve;
  const int cap = single_solve ? 1 : std::max(1, solver.max_iterations);
  FrameStats& st = s.st;
  for (int it = 0; it < cap; ++it) {
    assemble(s, it);
    solve_direction(s, it);
    s.E_accepted = s.E;
    // A step below the tolerance ends the iterations, unless Newton's model asked a frozen
    // friction contact for more than Coulomb's μλ over it: static friction's Hessian
    // (2μλ/(ε_v h)) holds over a slip of ε_v h only, so it makes a step small far from the
    // solution when the contact must slide (docs/simulation.md §5.2).
    const bool small_step = st.residual < solver.tolerance;
    bool converged = small_step && !has_friction(s);
    s.covered = cover(s);
    const bool accepted = line_search(s, it, small_step, converged);
    if (trace)
      std::fprintf(
          stderr,
          "  it %d E %.9g slope %.3g alpha %.3g residual %.3g friction_load %.3g accepted %d factorizations %d "
          "cg_iterations %d covered %d\n",
          it, s.E, -s.rhs.dot(s.dx), st.iterations.back().alpha, st.residual, st.iterations.back().friction_load,
          accepted, static_cast<int>(s.ls.counters.at(Counter::factorizations)),
          static_cast<int>(s.ls.counters.at(Counter::cg_iterations)), int(s.covered));
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
      if (!stiffen_held(s)) {
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
/// contacts); the energy into s.E. A non-finite energy or gradient ends the run.
void Simulation::assemble(StepState& s, int it) {
  const int n = s.n;
  const double h = solver.dt;
  bool changed_pattern = false;
  for (const auto& [k, c] : s.contacts) {
    const ScopedTimer timer(s.effect_ms[k]);
    changed_pattern = c->update_pattern(s.y) || changed_pattern;
  }
  if (changed_pattern) rebuild_pattern(s);
  {
    const ScopedTimer timer(s.st.assembly_ms);
    s.ls.H.set_zero();
    s.ls.H.add_diagonal(mass3_);
  }
  s.g = (s.y - x_tilde_);
  for (int i = 0; i < n; ++i) s.g.col(i) *= model.mass[i] / (h * h);
  double E = 0.5 * ((s.y - x_tilde_).colwise().squaredNorm().transpose().array() * model.mass.array()).sum() / (h * h);
  for (std::size_t k = 0; k < effects.size(); ++k) {
    const ScopedTimer timer(s.effect_ms[k]);
    E += effects[k]->evaluate(s.y, &s.g, &s.ls.H);
  }
  s.E = E;
  if (!std::isfinite(E) || !s.g.allFinite())
    fail_non_finite(s.y, s.st.frame, "at Newton iteration " + std::to_string(it + 1));
}

/// The Newton direction H Δx = −g and its residual max|Δx|/(h ℓ); a failed solve ends the run.
void Simulation::solve_direction(StepState& s, int it) {
  FrameStats& st = s.st;
  bool solved = false;
  {
    const ScopedTimer timer(st.solve_ms);
    s.rhs = -Eigen::Map<const Eigen::VectorXd>(s.g.data(), s.g.size());
    solved = s.ls.solve(solver, s.rhs, s.dx);
  }
  if (!solved || !s.dx.allFinite())
    throw SimulationError(st.frame, "", -1,
                          "frame " + std::to_string(st.frame) + ": the linear solve failed at Newton iteration " +
                              std::to_string(it + 1) + (solved ? " (a non-finite direction)" : ""));
  ++st.newton_iterations;
  s.dxm = Eigen::Map<const Eigen::Matrix3Xd>(s.dx.data(), 3, s.n);
  st.residual = s.dxm.colwise().norm().maxCoeff() / (solver.dt * scale_);
}

/// Contact effects whose candidates would go stale along the step query again over it (the
/// pairs active at y, hence the pattern, stay those of the new candidates); true if any did.
/// Each effect covers with its own candidate set and broad phase, so with two threads or
/// more the effects cover side by side (a vertex-face and an edge-edge effect usually query
/// at the same iteration); what each computes does not depend on it.
bool Simulation::cover(StepState& s) {
  bool covered = false;
  const long count = static_cast<long>(s.contacts.size());
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1) reduction(|| : covered) if (count > 1)
  for (long j = 0; j < count; ++j) {
    const auto [k, c] = s.contacts[static_cast<std::size_t>(j)];
    try {
      const ScopedTimer timer(s.effect_ms[k]);
      covered = c->cover_step(s.y, s.dxm) || covered;
    } catch (...) {
#pragma omp critical(pce_sim_cover_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
  return covered;
}

/// Backtracking line search (Armijo) from the largest step every effect allows; records the
/// iteration; true when a trial was accepted (y moves there). With friction, a direction
/// below the tolerance sets `converged` by the friction test at the step taken.
bool Simulation::line_search(StepState& s, int it, bool small_step, bool& converged) {
  FrameStats& st = s.st;
  const ScopedTimer timer(st.line_search_ms);
  double alpha = 1.0;
  NewtonIteration record;
  record.residual = st.residual;
  for (const auto& [k, e] : s.contacts)
    if (const double t = e->max_step(s.y, s.dxm); t < alpha) {
      alpha = t;
      record.limited_by = e->name();
    }
  // The Armijo test compares trials with an energy of the same candidates (the sum's
  // rounding depends on them): after a new query, the energy at y again.
  if (s.covered) {
    s.E = s.E_accepted = potential(s.y, &s.effect_ms);
    s.evaluated_at_y = true;
    if (!std::isfinite(s.E)) fail_non_finite(s.y, st.frame, "at Newton iteration " + std::to_string(it + 1));
  }
  record.step_limit = alpha;
  const double slope = -s.rhs.dot(s.dx);  // gᵀΔx < 0 for a descent direction
  bool accepted = false;
  // Trial steps whose largest vertex motion is below a hundredth of the stopping
  // tolerance's are not tried: such a step cannot change the outcome, and trying them
  // (40 halvings) made a step at a kink of the energy cost ~40 energy passes.
  const double smallest = 0.01 * solver.tolerance / std::max(st.residual, 1e-300);
  for (int tries = 0; tries < 40 && alpha > 0 && (tries == 0 || alpha >= smallest); ++tries, alpha *= 0.5) {
    s.y1 = s.y + alpha * s.dxm;
    const double E1 = potential(s.y1, &s.effect_ms);
    s.evaluated_at_y = false;
    if (std::isfinite(E1) && E1 <= s.E + 1e-4 * alpha * slope) {
      if (small_step && has_friction(s)) {
        record.friction_load = st.friction_load = friction_load(s, alpha * s.dxm);
        converged = st.friction_load <= 1 + kCoulombMargin;
      }
      s.y = s.y1;
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

/// Contact effects stiffen the pairs their last max_step held at their minimum separation
/// (docs/simulation.md §4.6); true when one did (the energy at y changed).
bool Simulation::stiffen_held(StepState& s) {
  bool stiffened = false;
  for (const auto& [k, c] : s.contacts) {
    const ScopedTimer timer(s.effect_ms[k]);
    stiffened = c->stiffen_held(s.y) || stiffened;
  }
  if (stiffened) s.evaluated_at_y = false;
  return stiffened;
}

/// After an accepted update: the held pairs stiffened; contact effects whose candidates went
/// stale at y query again; the pattern follows.
void Simulation::refresh(StepState& s) {
  bool changed = false;
  stiffen_held(s);
  for (const auto& [k, c] : s.contacts)
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

/// Effects that freeze quantities at a solve's result (friction with lagged_iterations > 1)
/// do so; true when one did, and the step is solved again from y.
bool Simulation::update_lagged(StepState& s) {
  bool again = false;
  for (const auto& [k, c] : s.contacts) {
    const ScopedTimer timer(s.effect_ms[k]);
    again = c->update_lagged(s.y) || again;
  }
  if (!again) return false;
  rebuild_pattern(s);
  s.evaluated_at_y = false;
  return true;
}

/// The accepted y becomes xⁿ⁺¹ (and (y − xⁿ)/h the velocity). The energy and every counter
/// (contact counts, minimum distances) describe the accepted state: when the last evaluation
/// was elsewhere (a rejected trial) or with other candidates (a refresh since), one more
/// energy pass there.
void Simulation::accept(StepState& s) {
  FrameStats& st = s.st;
  const double h = solver.dt;
  if (!s.y.allFinite()) fail_non_finite(s.y, st.frame, "after the line search");
  if (!s.evaluated_at_y) {
    {
      const ScopedTimer timer(st.line_search_ms);
      s.E_accepted = potential(s.y, &s.effect_ms);
    }
    if (!std::isfinite(s.E_accepted)) fail_non_finite(s.y, st.frame, "at the accepted state");
  }
  v = (s.y - s.x_start) / h;
  x = s.y;
  ++frame;
  time += h;
  st.energy = s.E_accepted;
  st.kinetic_energy = 0.5 * (v.colwise().squaredNorm().transpose().array() * model.mass.array()).sum();
}

/// The frame's statistics: per-effect time, merged counters, the stage split.
void Simulation::report(StepState& s) {
  FrameStats& st = s.st;
  const LinearState& ls = s.ls;
  for (std::size_t k = 0; k < effects.size(); ++k) {
    st.effect_ms.emplace_back(effects[k]->name(), s.effect_ms[k]);
    EffectCounters c;
    effects[k]->report(c);
    st.counters.merge(c);  // summed, distances by their minimum (CounterInfo::minimum)
  }
  const auto counter = [&](Counter key) { return st.counters.has(key) ? st.counters.at(key) : 0.0; };
  st.broad_phase_ms = counter(Counter::broad_phase_ms);
  st.pair_ms = counter(Counter::pair_ms);
  st.assembly_ms += counter(Counter::scatter_ms);
  st.counters[Counter::pattern_blocks] = static_cast<double>(ls.H.block_count());
  st.counters.merge(ls.counters);
  st.wall_ms = ms_since(s.t_frame);
}

}  // namespace pce::sim
