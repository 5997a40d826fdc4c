// SPDX-License-Identifier: MIT
// A simulation's time step (pce/sim/simulation.hpp): the step's constants and every effect's
// begin_step, the solver of the mode (solver/newton.cpp, solver/block_descent.cpp), the
// accepted state and the frame's statistics.
#include "effects/arguments.hpp"
#include "solver/step.hpp"
#include "util/names.hpp"

#include <pce/sim/input_error.hpp>
#include <pce/sim/simulation.hpp>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace pce::sim {

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
  if (solver.substeps < 0) throw ArgumentError("solver.substeps", "expected at least 1 (or 0: the mode's default)");
  if (!(std::isfinite(solver.tolerance) && solver.tolerance > 0))
    throw ArgumentError("solver.tolerance", "expected a finite number > 0");
  if (solver.max_iterations < 1) throw ArgumentError("solver.max_iterations", "expected at least 1");
  if (solver.iterations < 1) throw ArgumentError("solver.iterations", "expected at least 1");
  if (!(solver.redetect_share >= 0 && solver.redetect_share <= 1))
    throw ArgumentError("solver.redetect_share", "expected a number in [0, 1]");
  if (!(std::isfinite(solver.reuse_tolerance) && solver.reuse_tolerance > 0))
    throw ArgumentError("solver.reuse_tolerance", "expected a finite number > 0");
  if (solver.reuse_max_cg_iterations < 0) throw ArgumentError("solver.reuse_max_cg_iterations", "expected at least 0");
  if (!(std::isfinite(solver.linear_tolerance) && solver.linear_tolerance > 0 && solver.linear_tolerance < 1))
    throw ArgumentError("solver.linear_tolerance", "expected a finite number in (0, 1)");
  if (solver.linear_max_iterations < 1) throw ArgumentError("solver.linear_max_iterations", "expected at least 1");
  if (solver.amg_setup_reuse < 0) throw ArgumentError("solver.amg_setup_reuse", "expected at least 0");
  if (!linear_solver_available(solver.linear))
    throw ArgumentError("solver.linear", "\"" + std::string(name_of(solver.linear)) +
                                             "\" needs hypre, and this pce::sim was built without it");
  for (std::size_t k = 0; k < effects.size(); ++k)
    if (!effects[k]) throw ArgumentError("effects[" + std::to_string(k) + "]", "expected an effect, got null");
}

namespace {

/// The step's constants (the inertia term, the length scale ℓ) for a step of size h ending
/// at time `t_end`, and every effect's begin_step.
void begin(solver::Step& s, const Simulation& sim, const std::vector<Obstacle>& obstacles, double t_end, double h) {
  s.h = h;
  s.st.frame = sim.frame + 1;
  s.effect_ms.assign(s.effects.size(), 0.0);
  s.x_start = sim.x;
  s.v_start = sim.v;
  s.inertia.start(sim.model, sim.x, sim.v, h);
  s.scale = std::max((sim.model.rest.rowwise().maxCoeff() - sim.model.rest.rowwise().minCoeff()).norm(), 1e-12);
  StepContext ctx;
  ctx.frame = sim.frame + 1;
  ctx.time = t_end;
  ctx.dt = h;
  ctx.model = &sim.model;
  ctx.x_start = &s.x_start;
  ctx.v_start = &s.v_start;
  ctx.obstacles = &obstacles;
  for (std::size_t k = 0; k < s.effects.size(); ++k) {
    const ScopedTimer timer(s.effect_ms[k]);
    s.effects[k]->begin_step(ctx);
  }
  s.y = s.x_start;
}

/// The frame's statistics: per-effect time, merged counters, the stage split, the solver's
/// own counters.
void report(solver::Step& s, const solver::StepSolver& step_solver) {
  FrameStats& st = s.st;
  for (std::size_t k = 0; k < s.effects.size(); ++k) {
    st.effect_ms.emplace_back(s.effects[k]->name(), s.effect_ms[k]);
    EffectCounters c;
    s.effects[k]->report(c);
    st.counters.merge(c);  // summed, distances by their minimum (CounterInfo::minimum)
  }
  const auto counter = [&](Counter key) { return st.counters.has(key) ? st.counters.at(key) : 0.0; };
  st.broad_phase_ms = counter(Counter::broad_phase_ms);
  st.pair_ms = counter(Counter::pair_ms);
  st.assembly_ms += counter(Counter::scatter_ms);
  step_solver.report(s);
  st.wall_ms = ms_since(s.t_frame);
}

/// The accepted y becomes xⁿ⁺¹ (and (y − xⁿ)/h the velocity). The energy and every counter
/// (contact counts, minimum distances) describe the accepted state: when the last evaluation
/// was elsewhere (a rejected trial) or with other candidates (a refresh since), one more
/// energy pass there.
void accept(solver::Step& s, Simulation& sim, const solver::StepSolver& step_solver, double t_end) {
  FrameStats& st = s.st;
  if (!s.y.allFinite()) s.fail_non_finite(s.y, "after the line search");
  if (!s.evaluated_at_y) {
    {
      const ScopedTimer timer(st.line_search_ms);
      s.E_accepted = s.potential(s.y);
    }
    if (!std::isfinite(s.E_accepted)) s.fail_non_finite(s.y, "at the accepted state");
  }
  sim.v = (s.y - s.x_start) / s.h;
  sim.x = s.y;
  sim.time = t_end;
  st.energy = s.E_accepted;
  st.kinetic_energy = 0.5 * (sim.v.colwise().squaredNorm().transpose().array() * sim.model.mass.array()).sum();
  report(s, step_solver);
}

/// Adds a later step's statistics to its frame's (the rules of `FrameStats`); `substep` is
/// its index in the frame.
void follow(FrameStats& frame, FrameStats& later, int substep) {
  for (NewtonIteration& it : later.iterations) it.substep = substep;
  for (SweepRecord& r : later.sweep_records) r.substep = substep;
  if (substep == 0) {
    frame = std::move(later);
    return;
  }
  frame.newton_iterations += later.newton_iterations;
  frame.sweeps += later.sweeps;
  frame.residual = std::max(frame.residual, later.residual);
  frame.friction_residual = std::max(frame.friction_residual, later.friction_residual);
  frame.friction_load = std::max(frame.friction_load, later.friction_load);
  if (frame.stop != StopReason::line_search && frame.stop != StopReason::iteration_cap) frame.stop = later.stop;
  frame.energy = later.energy;
  frame.kinetic_energy = later.kinetic_energy;
  frame.line_search_failures += later.line_search_failures;
  frame.hit_iteration_cap = frame.hit_iteration_cap || later.hit_iteration_cap;
  frame.broad_phase_ms += later.broad_phase_ms;
  frame.pair_ms += later.pair_ms;
  frame.assembly_ms += later.assembly_ms;
  frame.solve_ms += later.solve_ms;
  frame.line_search_ms += later.line_search_ms;
  for (std::size_t k = 0; k < frame.effect_ms.size() && k < later.effect_ms.size(); ++k)
    frame.effect_ms[k].second += later.effect_ms[k].second;  // the same effects, in scene order
  frame.iterations.insert(frame.iterations.end(), later.iterations.begin(), later.iterations.end());
  frame.sweep_records.insert(frame.sweep_records.end(), later.sweep_records.begin(), later.sweep_records.end());
  frame.counters.follow(later.counters);
}

}  // namespace

FrameStats Simulation::step() {
  const auto t_frame = Clock::now();
  check();
  if (solver.threads > 0) omp_set_num_threads(solver.threads);
  const bool block = solver.mode == SolverMode::block_descent;
  if (!solver_ || block_descent_ != block) {
    solver_ = block ? solver::make_block_descent() : solver::make_newton();
    block_descent_ = block;
  }
  // substeps steps of h = dt/S; step k ends at t0 + dt·k/S, the last exactly at t0 + dt. A
  // step that fails leaves the state of the frame's start.
  const int substeps = solver.steps_per_frame();
  const double h = solver.dt / substeps, t0 = time;
  const Eigen::Matrix3Xd x0 = substeps > 1 ? x : Eigen::Matrix3Xd(), v0 = substeps > 1 ? v : Eigen::Matrix3Xd();
  FrameStats frame_stats;
  try {
    for (int k = 0; k < substeps; ++k) {
      const double t_end = k + 1 == substeps ? t0 + solver.dt : t0 + solver.dt * (k + 1) / substeps;
      solver::Step s(model, effects, solver);
      s.t_frame = k == 0 ? t_frame : Clock::now();
      begin(s, *this, obstacles, t_end, h);
      solver_->solve(s);
      accept(s, *this, *solver_, t_end);
      follow(frame_stats, s.st, k);
    }
  } catch (...) {
    if (substeps > 1) {
      x = x0;
      v = v0;
      time = t0;
    }
    throw;
  }
  ++frame;
  frame_stats.substeps = substeps;
  if (substeps > 1) frame_stats.wall_ms = ms_since(t_frame);
  return frame_stats;
}

void Simulation::set_obstacle_pose(const std::string& name, const Eigen::Isometry3d& pose) {
  Obstacle* const it = find_named(obstacles, name);
  if (!it) {
    const std::string names = names_of(obstacles);
    throw ArgumentError("name", "no obstacle named \"" + name +
                                    "\" (the obstacles: " + (names.empty() ? std::string("none") : names) + ")");
  }
  args::position("translation", pose.translation());
  args::rotation("rotation", pose.linear());
  it->place(PlacedPose{time + 0.5 * solver.dt / solver.steps_per_frame(), pose});
}

}  // namespace pce::sim
