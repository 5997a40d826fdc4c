// SPDX-License-Identifier: MIT
// pce-linear-bench: times the Newton linear solvers on systems a run wrote with
// PCE_SIM_DUMP_SYSTEM=DIR (src/sim/solver/system_dump.hpp), one solver at a time, the way
// Newton calls them (one LinearState; a new step, in the file names, starts amg's reuse
// count). Per system: the solve's wall time, the setup inside it (direct: analysis and
// factorisation; pcg, amg: the preconditioner), CG iterations and the true relative
// residual ‖rhs − H dx‖/‖rhs‖; then their means. docs/simulation.md §5.3 quotes it.
//
//   pce-linear-bench --solver pcg --eta 1e-2 --threads 1 DIR/system_s0006_i*.bin
#include "solver/system_dump.hpp"
#include "util/stopwatch.hpp"

#include <pce/core/enum_names.hpp>

#include <CLI/CLI.hpp>
#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace pce::sim;

namespace {

/// The step number in a dump's file name (system_s<step>_i<iteration>.bin), or -1.
int step_of(const std::string& path) {
  const auto at = path.rfind("system_s");
  return at == std::string::npos ? -1 : std::atoi(path.c_str() + at + 8);
}

/// A counter of `c`, 0 when it was not reported.
double counter(const Counters& c, Counter key) { return c.has(key) ? c.at(key) : 0.0; }

/// The fastest of `repeat` solves: its wall time, the setup within it and its CG iterations.
struct Timing {
  bool solved = true;
  double ms = 1e300, setup_ms = 0, iterations = 0;
};

/// Solves `repeat` times (the same system); the fastest solve's Timing.
Timing time_solve(solver::LinearSystem& system, const SolverSettings& settings, const Eigen::VectorXd& rhs,
                  Eigen::VectorXd& dx, double eta, int repeat) {
  Timing best;
  for (int k = 0; k < repeat; ++k) {
    const Counters before = system.counters();
    const auto t = Clock::now();
    if (!system.solve(settings, rhs, dx, eta)) return Timing{false};
    const double ms = ms_since(t);
    if (ms >= best.ms) continue;
    best.ms = ms;
    const Counters& c = system.counters();
    best.setup_ms = 0;
    for (const Counter key : {Counter::analyze_ms, Counter::factorize_ms, Counter::preconditioner_ms})
      best.setup_ms += counter(c, key) - counter(before, key);
    best.iterations = counter(c, Counter::cg_iterations) - counter(before, Counter::cg_iterations);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pce-linear-bench: Newton's linear solvers on dumped systems (PCE_SIM_DUMP_SYSTEM)"};
  std::vector<std::string> files;
  std::string solver_name = "direct";
  double eta = 1e-3;
  int threads = 1, reuse = 0, repeat = 1;
  app.add_option("files", files, "system files (system_s<step>_i<iteration>.bin)")->required();
  app.add_option("--solver", solver_name, "direct, factor_reuse, ldlt, cg, pcg or amg");
  app.add_option("--eta", eta, "relative residual of pcg and amg");
  app.add_option("--threads", threads, "OpenMP threads");
  app.add_option("--amg-reuse", reuse,
                 "amg: solves of a step that reuse the hierarchy (SolverSettings::amg_setup_reuse)");
  app.add_option("--repeat", repeat, "solves per system (the fastest is reported)");
  CLI11_PARSE(app, argc, argv);
  SolverSettings settings;
  const auto parsed = pce::parse<LinearSolver>(solver_name);
  if (!parsed) {
    std::fprintf(stderr, "pce-linear-bench: unknown solver %s\n", solver_name.c_str());
    return 2;
  }
  settings.linear = *parsed;
  settings.amg_setup_reuse = reuse;
  omp_set_num_threads(threads);
  solver::LinearSystem system;
  Eigen::SparseMatrix<double> A;
  Eigen::VectorXd rhs, dx;
  {
    // One untimed solve of the first system by another solver object: amg's first setup
    // initialises MPI and hypre, a once-per-process cost that is not the solver's.
    solver::LinearSystem warm_up;
    if (solver::read_system(files.front(), A, rhs)) {
      warm_up.start_step();
      warm_up.set_matrix(A);
      warm_up.solve(settings, rhs, dx, eta);
    }
  }
  int step = -2, count = 0;
  double total_ms = 0, total_setup = 0, total_iterations = 0, worst = 0;
  std::printf("file solve_ms setup_ms cg_iterations relative_residual\n");
  for (const std::string& file : files) {
    if (!solver::read_system(file, A, rhs)) {
      std::fprintf(stderr, "pce-linear-bench: cannot read %s\n", file.c_str());
      return 1;
    }
    if (step_of(file) != step) system.start_step();
    step = step_of(file);
    system.set_matrix(A);
    const Timing t = time_solve(system, settings, rhs, dx, eta, repeat);
    if (!t.solved) {
      std::fprintf(stderr, "pce-linear-bench: the solve of %s failed\n", file.c_str());
      return 1;
    }
    const double best = t.ms, setup = t.setup_ms, iterations = t.iterations;
    const Eigen::VectorXd residual = rhs - A.selfadjointView<Eigen::Upper>() * dx;
    const double relative = residual.norm() / rhs.norm();
    std::printf("%s %.2f %.2f %.0f %.3g\n", file.c_str(), best, setup, iterations, relative);
    total_ms += best;
    total_setup += setup;
    total_iterations += iterations;
    worst = std::max(worst, relative);
    ++count;
  }
  std::printf(
      "mean over %d systems (%s, eta %g, %d threads, amg reuse %d): solve %.2f ms, setup %.2f ms, %.1f CG "
      "iterations, worst relative residual %.3g\n",
      count, solver_name.c_str(), eta, threads, reuse, total_ms / count, total_setup / count, total_iterations / count,
      worst);
  return 0;
}
