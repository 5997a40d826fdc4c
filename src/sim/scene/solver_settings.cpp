// SPDX-License-Identifier: MIT
// The scene's settings and the command line's overrides of them (solver_settings.hpp).
#include "solver_settings.hpp"

#include "../effects/arguments.hpp"

#include <string>

namespace pce::sim {

namespace {

/// The scene's time step dt (s): from a microsecond (beyond any vibration a stiffness
/// ≤ 1e12 on a mass a density ≥ 1e-9 gives needs to resolve) to one second (a frame of a
/// slow-motion sequence; a step's free fall g·dt² stays ≤ kMaxCoordinate). Keeps M/dt²,
/// v = Δx/dt and the time frames·dt (≤ 1e7 s) finite and normal.
constexpr double kMinDt = 1e-6, kMaxDt = 1.0;
/// Time steps per frame: at most this many (dt/substeps stays ≥ 1e-9 s, a thousandth of kMinDt).
constexpr long kMaxSubsteps = 1000;

/// The `solver` object into `solver`; returns its `broad_phase`.
BroadPhaseKind parse_solver(const Params& s, SolverSettings& solver) {
  s.only({"mode", "iterations", "substeps", "acceleration", "chebyshev_rho", "sweep_tolerance", "redetect_share",
          "tolerance", "max_iterations", "linear_solver", "linear_tolerance", "threads", "broad_phase"});
  solver.mode = s.choice<SolverMode>("mode", SolverMode::newton);
  if (s.has("iterations") && solver.mode != SolverMode::block_descent)
    s.fail("iterations",
           "only \"mode\": \"block_descent\" takes a number of iterations (Newton's cap is "
           "\"max_iterations\")");
  solver.iterations = static_cast<int>(s.integer("iterations", long{kDefaultBlockIterations}, 1, 100000));
  for (const char* key : {"acceleration", "chebyshev_rho", "sweep_tolerance", "redetect_share"})
    if (s.has(key) && solver.mode != SolverMode::block_descent)
      s.fail(key, "only \"mode\": \"block_descent\" takes it");
  solver.acceleration = s.choice<Acceleration>("acceleration", Acceleration::none);
  solver.chebyshev_rho = s.number("chebyshev_rho", solver.chebyshev_rho, 0, 1);
  if (!(solver.chebyshev_rho > 0 && solver.chebyshev_rho < 1))
    s.fail("chebyshev_rho",
           "expected a number in (0, 1) (a sweep's spectral radius), got " + args::text(solver.chebyshev_rho));
  if (s.has("chebyshev_rho") && solver.acceleration != Acceleration::chebyshev)
    s.fail("chebyshev_rho", "only \"acceleration\": \"chebyshev\" takes it");
  solver.sweep_tolerance = s.nonnegative("sweep_tolerance", 0.0);
  solver.redetect_share = s.number("redetect_share", 0.0, 0, 1);
  // absent: 0, the mode's default (SolverSettings::steps_per_frame), after the overrides
  if (s.has("substeps")) solver.substeps = static_cast<int>(s.integer("substeps", 1L, 1, kMaxSubsteps));
  solver.tolerance = s.positive("tolerance", solver.tolerance);
  solver.max_iterations = static_cast<int>(s.integer("max_iterations", 50L, 1, 100000));
  solver.linear = s.choice<LinearSolver>("linear_solver", LinearSolver::direct);
  if (!linear_solver_available(solver.linear))
    s.fail("linear_solver", "\"" + std::string(name_of(solver.linear)) +
                                "\" needs hypre, and this pce::sim was built without it (CMake found no "
                                "hypre or no MPI; docs/simulation.md section 5.3)");
  solver.linear_tolerance = s.number("linear_tolerance", solver.linear_tolerance, 0, 1);
  if (!(solver.linear_tolerance > 0 && solver.linear_tolerance < 1))
    s.fail("linear_tolerance", "expected a number in (0, 1) (the Krylov solvers' relative residual), got " +
                                   args::text(solver.linear_tolerance));
  solver.threads = static_cast<int>(s.integer("threads", 0L, 0, 1024));
  return s.choice<BroadPhaseKind>("broad_phase", BroadPhaseKind::fcl);
}

/// The command line's overrides into `sim`'s frames and solver and `broad_phase`; an
/// override of the sweeps (--iterations) is named at the key it replaces.
void apply_overrides(const Params& root, const SceneOverrides& overrides, Simulation& sim,
                     BroadPhaseKind& broad_phase) {
  if (overrides.frames) sim.frames = *overrides.frames;
  if (overrides.threads) sim.solver.threads = *overrides.threads;
  if (overrides.single_solve && *overrides.single_solve) sim.solver.mode = SolverMode::single_solve;
  if (overrides.mode) sim.solver.mode = *overrides.mode;
  if (overrides.iterations) {
    if (sim.solver.mode != SolverMode::block_descent)
      root.fail("solver.iterations",
                "a number of sweeps (--iterations) needs the block_descent mode, and this "
                "scene's is " +
                    std::string(name_of(sim.solver.mode)) + " (--mode block_descent selects it)");
    if (*overrides.iterations < 1) root.fail("solver.iterations", "expected an integer >= 1 (--iterations)");
    sim.solver.iterations = *overrides.iterations;
  }
  if (overrides.acceleration) {
    if (sim.solver.mode != SolverMode::block_descent)
      root.fail("solver.acceleration",
                "an acceleration (--acceleration) needs the block_descent mode, and this "
                "scene's is " +
                    std::string(name_of(sim.solver.mode)));
    sim.solver.acceleration = *overrides.acceleration;
  }
  if (overrides.substeps) {
    if (!(*overrides.substeps >= 1 && *overrides.substeps <= kMaxSubsteps))
      root.fail("solver.substeps", "expected an integer in [1, " + std::to_string(kMaxSubsteps) + "] (--substeps)");
    sim.solver.substeps = *overrides.substeps;
  }
  if (overrides.tolerance) sim.solver.tolerance = *overrides.tolerance;
  if (overrides.broad_phase) broad_phase = *overrides.broad_phase;
}

}  // namespace

BroadPhaseKind parse_settings(const Params& root, const SceneOverrides& overrides, Scene& scene) {
  Simulation& sim = scene.simulation;
  sim.solver.dt = root.number("dt");
  if (!(sim.solver.dt >= kMinDt && sim.solver.dt <= kMaxDt))
    root.fail("dt", "expected a number in [" + args::limit_text(kMinDt) + ", " + args::limit_text(kMaxDt) +
                        "] (the time steps pce::sim accepts, in s), got " + args::text(sim.solver.dt));
  sim.frames = static_cast<int>(root.integer("frames", std::nullopt, 1, 10000000));
  scene.output_every = static_cast<int>(root.integer("output_every", 1L, 1, 10000000));
  if (root.has("view_direction")) {
    scene.view_direction = root.vec3("view_direction");
    if (!(scene.view_direction.norm() > 0)) root.fail("view_direction", "expected a non-zero direction");
  }
  scene.allow_initial_intersections = root.boolean("allow_initial_intersections", false);
  BroadPhaseKind broad_phase = BroadPhaseKind::fcl;
  if (root.has("solver")) broad_phase = parse_solver(root.object("solver"), sim.solver);
  apply_overrides(root, overrides, sim, broad_phase);
  return broad_phase;
}

}  // namespace pce::sim
