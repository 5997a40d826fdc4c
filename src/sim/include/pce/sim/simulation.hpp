// SPDX-License-Identifier: MIT
/// @file
/// A simulation: the model, the obstacles, the effects the scene declared and the solver
/// settings, advanced one time step per frame by backward Euler written as an incremental
/// potential (Martin et al. 2011; Li et al. 2020)
///
///     xⁿ⁺¹ = argmin_x  Σᵢ mᵢ/(2h²) |xᵢ − x̃ᵢ|² + Σ_effects E(x),   x̃ = xⁿ + h vⁿ,
///
/// minimised by projected Newton: each effect adds its energy, gradient and PSD Hessian,
/// the Newton direction solves H Δx = −g (by default a factorisation every iteration,
/// CHOLMOD or Eigen's LDLᵀ; or conjugate gradients preconditioned by a kept Cholesky
/// factor; or plain conjugate gradients), a backtracking line search (Armijo) that no effect
/// lets a barrier cross (`NewtonHooks::begin_line_search`), until the scale-aware residual
/// max|Δx|/(h·ℓ) < tolerance (ℓ the rest bounding-box diagonal: a velocity in model sizes
/// per second) with, where friction acts, no frozen contact asked by Newton's model for more
/// than Coulomb's μλ — or the iteration cap. The paper's cheap mode takes a single Newton
/// step per time step; block descent (`SolverMode::block_descent`) sweeps vertex by vertex
/// instead. `Simulation` holds the model, the state, the effects and the obstacles; each
/// solver is an object of its own that keeps its state between steps (src/sim/solver).
#pragma once

#include <pce/core/enum_names.hpp>
#include <pce/sim/broad_phase.hpp>
#include <pce/sim/effect.hpp>
#include <pce/sim/model.hpp>
#include <pce/sim/obstacle.hpp>

#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace pce::sim {

namespace solver {
class StepSolver;
}  // namespace solver

/// How the Newton system H Δx = −g is solved (scene key `solver.linear_solver`):
/// `direct` (the default: a new factorisation every iteration, CHOLMOD when built with it,
/// else Eigen's LDLᵀ), `factor_reuse` (conjugate gradients preconditioned by the last
/// Cholesky factor, kept across iterations and steps, refactored when they do not converge
/// fast; the kept factor is not in a checkpoint, so a resumed run differs slightly), `ldlt` (Eigen's sparse LDLᵀ every
/// iteration), `cg` (conjugate gradients, diagonal preconditioner), `pcg` (conjugate
/// gradients preconditioned by the inverted 3×3 diagonal blocks, to `linear_tolerance`,
/// parallel and the same bits for any thread count) or `amg` (the same loop preconditioned
/// by one V-cycle of hypre's BoomerAMG; only when built with hypre,
/// `linear_solver_available`).
enum class LinearSolver { factor_reuse, direct, ldlt, cg, pcg, amg };

/// The linear solvers' names, in the order the scene format lists them.
inline constexpr EnumNames<LinearSolver, 6> kLinearSolverNames{{
    {LinearSolver::direct, "direct"},
    {LinearSolver::factor_reuse, "factor_reuse"},
    {LinearSolver::ldlt, "ldlt"},
    {LinearSolver::cg, "cg"},
    {LinearSolver::pcg, "pcg"},
    {LinearSolver::amg, "amg"},
}};

/// The table of `LinearSolver`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<LinearSolver, 6>& enum_names(LinearSolver) { return kLinearSolverNames; }

/// Whether this build of pce::sim has `solver` (`amg` needs hypre, found when pce::sim was
/// built; every other solver is always there).
bool linear_solver_available(LinearSolver solver);

/// How a time step is solved (scene key `solver.mode`, docs/simulation.md §5): projected
/// Newton to the tolerance (`newton`), one linearised solve per step (`single_solve`, the
/// paper's cheap mode), or `iterations` sweeps of vertex block descent (`block_descent`:
/// Gauss–Seidel over coloured vertices, one 3×3 Newton step per vertex, each vertex kept
/// within its conservative bound; §5.5).
enum class SolverMode { newton, single_solve, block_descent };

/// The solver modes' names, in the order the scene format lists them.
inline constexpr EnumNames<SolverMode, 3> kSolverModeNames{{
    {SolverMode::newton, "newton"},
    {SolverMode::single_solve, "single_solve"},
    {SolverMode::block_descent, "block_descent"},
}};

/// The table of `SolverMode`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<SolverMode, 3>& enum_names(SolverMode) { return kSolverModeNames; }

/// Block descent's sweeps per time step when the scene does not say (`solver.iterations`).
inline constexpr int kDefaultBlockIterations = 5;
/// Block descent's time steps per frame when the scene does not say (`solver.substeps`);
/// Newton's and a single solve's are 1.
inline constexpr int kDefaultBlockSubsteps = 5;

/// Block descent's acceleration of its sweeps (scene key `solver.acceleration`,
/// docs/simulation.md §5.5): none, or Chebyshev's semi-iterative method (Wang 2015, "A
/// Chebyshev semi-iterative approach for accelerating projective and position-based
/// dynamics", as the VBD paper applies it, §3.7 there): after sweep k each vertex not in
/// contact moves to ω_k (x̄ᵢ − xᵢ⁽ᵏ⁻²⁾) + xᵢ⁽ᵏ⁻²⁾, ω₁ = 1, ω₂ = 2/(2 − ρ²),
/// ω_k = 4/(4 − ρ² ω_{k−1}), kept within its bound; a sweep whose extrapolation raises the
/// energy is undone to x̄ and the recurrence starts again.
enum class Acceleration { none, chebyshev };

/// The accelerations' names, in the order the scene format lists them.
inline constexpr EnumNames<Acceleration, 2> kAccelerationNames{{
    {Acceleration::none, "none"},
    {Acceleration::chebyshev, "chebyshev"},
}};

/// The table of `Acceleration`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<Acceleration, 2>& enum_names(Acceleration) { return kAccelerationNames; }

/// The scene's `solver` block: step size, Newton's stopping rule, linear solver, threads.
struct SolverSettings {
  double dt = 1.0 / 40.0;  ///< a frame's time (s): `substeps` time steps of dt/substeps
  /// Time steps per frame (scene key `solver.substeps`, ≥ 1): each of dt/substeps, solved in
  /// turn by the mode's solver; the frame's statistics cover them all (`FrameStats`). 0: the
  /// mode's default (`steps_per_frame`).
  int substeps = 0;
  int max_iterations = 50;                   ///< Newton iteration cap per step
  double tolerance = 1e-2;                   ///< on max|Δx|/(h·ℓ), 1/s
  SolverMode mode = SolverMode::newton;      ///< Newton, single solve or block descent
  int iterations = kDefaultBlockIterations;  ///< block descent: sweeps over every colour per step
  /// Block descent: the sweeps' acceleration (`solver.acceleration`).
  Acceleration acceleration = Acceleration::none;
  /// Block descent with Chebyshev acceleration: ρ, the estimated spectral radius of a sweep, in
  /// (0, 1) (`solver.chebyshev_rho`; the VBD paper's cloth uses 0.95).
  double chebyshev_rho = 0.95;
  /// Block descent: a step's sweeps stop once one's residual (its largest move over h·ℓ,
  /// `SweepRecord::residual`) is at most this (`solver.sweep_tolerance`; 0: all `iterations`).
  double sweep_tolerance = 0;
  /// Block descent: after a sweep the bounds are measured again (with a broad-phase query
  /// where a candidate set is no longer valid) when more than this share of the vertices
  /// ended on their bound (`solver.redetect_share`, in [0, 1]); 0: when any did, or a
  /// candidate set went stale (until then the stale set's missing pairs add no terms; the
  /// bounds still hold every pair apart).
  double redetect_share = 0;
  LinearSolver linear = LinearSolver::direct;  ///< direct: CHOLMOD when built with it, else LDLᵀ
  /// The time steps of a frame: `substeps`, or when it is 0 the mode's default
  /// (`kDefaultBlockSubsteps` for block descent, 1 otherwise).
  int steps_per_frame() const {
    return substeps > 0 ? substeps : mode == SolverMode::block_descent ? kDefaultBlockSubsteps : 1;
  }
  /// factor_reuse: CG stops at ‖H Δx + g‖ ≤ η ‖g‖, this η (not a scene key).
  double reuse_tolerance = 1e-2;
  /// factor_reuse: CG iterations before it gives up and refactors (not a scene key; 0
  /// refactors every iteration: the directions, and so the run, of `direct`).
  int reuse_max_cg_iterations = 10;
  /// pcg, amg: the Krylov solve stops at ‖H Δx + g‖ ≤ η ‖g‖, this η in (0, 1) (scene key
  /// `solver.linear_tolerance`); the direct solvers ignore it.
  double linear_tolerance = 1e-2;
  /// pcg, amg: iterations before the solve fails (not a scene key; the run then ends with a
  /// SimulationError).
  int linear_max_iterations = 20000;
  /// amg: Newton iterations of a step that reuse the BoomerAMG hierarchy of an earlier
  /// iteration's H (same pattern) before it is set up again; 0 sets it up at every solve (not a scene key).
  int amg_setup_reuse = 0;
  int threads = 0;  ///< 0: OpenMP's default
};

/// One Newton iteration of a step, for diagnosing slow convergence (`stats.json`'s
/// `iterations`): how far the direction went and what cut it short.
struct NewtonIteration {
  int substep = 0;      ///< the frame's time step it belongs to (0-based; `SolverSettings::substeps`)
  double residual = 0;  ///< max|Δx|/(h·ℓ) of this iteration's direction
  /// The friction test's residual at the accepted step, when the direction was below the
  /// tolerance (else 0): maxᵢ |δfᵢ| h/(mᵢ ℓ), δfᵢ the error of Newton's model of the friction
  /// force at vertex i over the step (docs/simulation.md §5.2); the step ended if it was below
  /// the tolerance.
  double friction_residual = 0;
  /// The largest |φ|/(μλ) over the frozen contacts at that step (`pce::friction_model_force`;
  /// above 1 the model asked a contact for more than Coulomb allows); else 0.
  double friction_load = 0;
  double step_limit = 1;        ///< the largest fraction of Δx every effect allowed (`begin_line_search`)
  const char* limited_by = "";  ///< the effect that set step_limit ("" when it is 1)
  double alpha = 0;             ///< the accepted fraction after backtracking (0: the line search failed)
};

/// One sweep of block descent (`stats.json`'s `sweep_records`, docs/simulation.md §6.1).
struct SweepRecord {
  int substep = 0;        ///< the frame's time step it belongs to (0-based; `SolverSettings::substeps`)
  double residual = 0;    ///< the largest vertex move of the sweep, over h·ℓ
  long bound_clamps = 0;  ///< vertices the sweep moved to their bound
  /// With Chebyshev's acceleration: the sweep's extrapolation was kept (false: there was
  /// none, the first sweep of a run, or it was undone).
  bool accelerated = false;
  /// With Chebyshev's acceleration: the incremental potential at the iterate the sweep
  /// accepted (else NaN).
  double energy = std::numeric_limits<double>::quiet_NaN();
};

/// Why a step's solve ended (`stats.json`'s `stop`, docs/simulation.md §5.2): Newton's
/// reasons, or `sweeps` for block descent.
enum class StopReason {
  /// a direction below the tolerance was taken (with friction: its friction residual too);
  /// block descent: a sweep's residual was at most `sweep_tolerance`
  tolerance,
  rounding,       ///< a direction below the tolerance whose trial failed by rounding
  line_search,    ///< the line search found no decrease (`line_search_failures`)
  iteration_cap,  ///< `max_iterations` were used up (`hit_iteration_cap`)
  single_solve,   ///< single-solve mode: one direction, no test
  sweeps,         ///< block-descent mode: its `iterations` sweeps were done
};

/// The reasons' names (`stats.json`'s `stop`), in enumerator order.
inline constexpr EnumNames<StopReason, 6> kStopReasonNames{{
    {StopReason::tolerance, "tolerance"},
    {StopReason::rounding, "rounding"},
    {StopReason::line_search, "line_search"},
    {StopReason::iteration_cap, "iteration_cap"},
    {StopReason::single_solve, "single_solve"},
    {StopReason::sweeps, "sweeps"},
}};

/// The table of `StopReason`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<StopReason, 6>& enum_names(StopReason) { return kStopReasonNames; }

/// The name of `reason` in kStopReasonNames ("tolerance", "rounding", …).
const char* to_string(StopReason reason);

/// What one frame cost and reached (`stats.json`, docs/simulation.md §5). A frame of
/// several time steps (`SolverSettings::substeps`) sums their work (iterations, sweeps,
/// times, work counters), keeps the worst of their residuals and failures, and describes the
/// state of the last (`energy`, `kinetic_energy`, the `state` counters).
struct FrameStats {
  /// Frame number, 1-based.
  int frame = 0;
  /// The frame's time steps (`SolverSettings::substeps`).
  int substeps = 1;
  /// The whole frame (`Simulation::step`), wall-clock ms.
  double wall_ms = 0;
  /// Newton iterations (linear solves) in this frame's steps; 0 in block descent.
  int newton_iterations = 0;
  /// Block descent's sweeps in this frame's steps; 0 in Newton.
  int sweeps = 0;
  /// max|Δx|/(h·ℓ) of a step's last Newton direction, or of its last sweep's largest move
  /// (h the step's size): the largest over the frame's steps.
  double residual = 0;
  /// The friction test's residual at the last direction below the tolerance that was taken
  /// (0 without friction or without such a direction): at or above the tolerance it did not
  /// end the step (`NewtonIteration::friction_residual`); the largest over the steps.
  double friction_residual = 0;
  /// The largest |φ|/(μλ) at that direction (`NewtonIteration::friction_load`), over the steps.
  double friction_load = 0;
  /// Why the solve ended: the first step's that ended by `line_search` or `iteration_cap`,
  /// else the last step's.
  StopReason stop = StopReason::iteration_cap;
  double energy = 0;          ///< incremental potential at the accepted state (the last step's)
  double kinetic_energy = 0;  ///< ½ Σᵢ mᵢ |vᵢ|² at the end of the frame (J)
  /// The steps whose line search found no decrease (which ends a step).
  int line_search_failures = 0;
  /// Newton mode only: a step used up `max_iterations`.
  bool hit_iteration_cap = false;
  ///@{
  /// Wall-clock ms of one stage: broad-phase queries, per-pair evaluation, assembly, linear
  /// solves, line search (they overlap, `docs/simulation.md` §6.1).
  double broad_phase_ms = 0, pair_ms = 0, assembly_ms = 0, solve_ms = 0, line_search_ms = 0;
  ///@}
  std::vector<std::pair<std::string, double>> effect_ms;  ///< per evaluated effect, in scene order
  std::vector<NewtonIteration> iterations;                ///< per Newton iteration, in order
  std::vector<SweepRecord> sweep_records;                 ///< per block-descent sweep, in order
  /// Merged effect counters (contact counts, distances, …) and the solver's (Newton's linear
  /// solver: `factorizations`, `cg_iterations`, `analyses`, `analyze_ms`, `factorize_ms`,
  /// `pattern_blocks`; block descent's: `first_move`, `bound_measurements`, `colours`, …);
  /// over the steps as `Counters::follow` merges them.
  EffectCounters counters;
};

/// A step that cannot go on: the state or an effect's energy or gradient became non-finite,
/// or the linear solve failed. `what()` is one line naming the frame (and, where one is to
/// blame, the effect and the vertex); the simulation keeps the last accepted state.
class SimulationError : public std::runtime_error {
 public:
  /// `effect` empty and `vertex` −1 when no single effect or vertex is to blame.
  SimulationError(int frame, std::string effect, int vertex, const std::string& message)
      : std::runtime_error(message), frame_(frame), effect_(std::move(effect)), vertex_(vertex) {}
  /// The frame (1-based) whose step failed.
  int frame() const { return frame_; }
  /// The effect whose energy or gradient was not finite, or "".
  const std::string& effect() const { return effect_; }
  /// The first vertex with a non-finite gradient or position, or −1.
  int vertex() const { return vertex_; }

 private:
  int frame_;
  std::string effect_;
  int vertex_;
};

/// A whole simulation: the model, its obstacles, the declared effects, the solver settings
/// and the current state; `step()` advances it by one time step (one frame). Effects point
/// into `model` or into `effect_models`, so a Simulation is neither copied nor moved (hold
/// it by `std::unique_ptr`).
class Simulation {
 public:
  Simulation() = default;
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;
  ~Simulation() = default;
  /// The deformable vertices and elements.
  Model model;
  /// The models the effects restricted to some meshes act on (`restrict_to_meshes` of
  /// `model`; a scene's entries with `meshes`): the effects point into them, so they are
  /// declared before `effects` and outlive them.
  std::vector<std::unique_ptr<Model>> effect_models;
  /// The scene's rigid obstacles.
  std::vector<Obstacle> obstacles;
  /// The scene's effects, in scene order: the whole incremental potential.
  std::vector<std::unique_ptr<Effect>> effects;
  /// Step size, stopping rule, linear solver, threads.
  SolverSettings solver;
  int frames = 1;  ///< frames to simulate
  ///@{
  Eigen::Matrix3Xd x, v;  ///< current positions and velocities
  ///@}
  int frame = 0;  ///< frames done
  /// Simulated time (s) at the end of the last step.
  double time = 0;

  /// Sets `x` to the rest shape and `v` to zero, and `frame` and `time` to 0: where a scene
  /// starts.
  void start_at_rest();

  /// Advances one frame: `solver.steps_per_frame()` time steps of `solver.dt` divided by it. Throws
  /// `ArgumentError` before touching anything when the
  /// simulation is not runnable (`x` or `v` not one column per model vertex, a mass not > 0,
  /// `solver.dt` or `solver.tolerance` not > 0, `solver.substeps` < 0, a null effect), and `SimulationError`
  /// ("frame N: …", naming the effect and vertex where one is to blame) when an energy, a
  /// gradient or the state becomes non-finite or the linear solve fails; nothing of that
  /// frame is kept (`x`, `v`, `frame` and `time` stay those of the last accepted step).
  FrameStats step();

  /// Throws `ArgumentError` when the simulation is not runnable (what `step()` checks first).
  void check() const;

  /// Puts the obstacle named `name` at `pose` (x_world = pose * x_local) from the next step
  /// on, replacing its motion until it is put again: adds `PlacedPose{time + h/2, pose}`
  /// (`Obstacle::place`; h = dt/substeps, the time step) to it in `obstacles`, which output
  /// draws and every obstacle contact effect reads its poses from (`StepContext::obstacles`).
  /// The next step (the frame's first) ends with the obstacle at `pose`, and friction sees
  /// its surface move there from its pose at the step's start. Throws `ArgumentError` when no obstacle has that name
  /// ("name"), the translation is not finite or beyond ±`kMaxCoordinate` ("translation"), or
  /// the linear part is no rotation matrix ("rotation": orthonormal to 1e-9, determinant
  /// 1). Placed poses are not in a checkpoint.
  void set_obstacle_pose(const std::string& name, const Eigen::Isometry3d& pose);

 private:
  /// The solver of the current mode (solver/newton.cpp, solver/block_descent.cpp), kept
  /// between steps while the mode is one it solves.
  std::shared_ptr<solver::StepSolver> solver_;
  bool block_descent_ = false;  ///< solver_ is block descent's
};

}  // namespace pce::sim
