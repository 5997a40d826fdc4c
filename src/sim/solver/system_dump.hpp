// SPDX-License-Identifier: MIT
/// @file
/// Newton's linear systems on disk, for measuring the linear solvers outside a run
/// (benchmarks/bench_linear_solver.cpp, tests/sim/test_krylov.cpp): with the environment
/// variable PCE_SIM_DUMP_SYSTEM=DIR every system Newton solves is written to
/// DIR/system_s<step>_i<iteration>.bin (step and iteration counted from 1 by the solver
/// object, so the frame of a run from frame 0), and PCE_SIM_DUMP_STEPS=A[:B] keeps only
/// steps A..B. Unset, nothing is read or written beyond one getenv when Newton's solver is
/// made. The file: "PCESYS1\n", then int64 size N and int64 entries E, then BlockHessian's
/// upper triangle in compressed columns (N + 1 int32 column starts, E int32 rows, E doubles)
/// and the right-hand side (N doubles), all little-endian as this machine writes them.
#pragma once

#include <pce/sim/counters.hpp>
#include <pce/sim/simulation.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <string>

namespace pce::sim::solver {

struct LinearState;

/// Writes `upper` and `rhs` to `path` in the format above; false when the file cannot be
/// written.
bool write_system(const std::string& path, const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& rhs);
/// Reads a file `write_system` wrote; false when it cannot be read or is not one.
bool read_system(const std::string& path, Eigen::SparseMatrix<double>& upper, Eigen::VectorXd& rhs);

/// The dump PCE_SIM_DUMP_SYSTEM asks for: where, which steps, and the step and iteration.
class SystemDump {
 public:
  /// The dump the environment asks for, or null when PCE_SIM_DUMP_SYSTEM is unset or empty.
  static std::unique_ptr<SystemDump> from_environment();
  /// Counts a new step (its iterations from 1).
  void start_step() {
    ++step_;
    iteration_ = 0;
  }
  /// Writes this iteration's system when its step is in range (a failed write is reported
  /// on stderr once and the run goes on).
  void write(const Eigen::SparseMatrix<double>& upper, const Eigen::VectorXd& rhs);

 private:
  std::string dir_;
  int first_ = 1, last_ = 1 << 30, step_ = 0, iteration_ = 0;
  bool warned_ = false;
};

/// One Newton system solved by a LinearState of its own, as Newton solves it (tests and
/// benchmarks; the LinearState's header needs pce::sim's private definitions).
class LinearSystem {
 public:
  LinearSystem();
  ~LinearSystem();
  LinearSystem(const LinearSystem&) = delete;
  LinearSystem& operator=(const LinearSystem&) = delete;
  /// H's upper triangle (BlockHessian's layout); the analysis is kept when the pattern is
  /// the previous call's.
  void set_matrix(const Eigen::SparseMatrix<double>& upper);
  /// As LinearState::solve.
  bool solve(const SolverSettings& settings, const Eigen::VectorXd& rhs, Eigen::VectorXd& dx, double eta);
  /// As LinearState::start_step (zeroes the counters, starts amg's reuse count).
  void start_step();
  /// The counters since start_step.
  const Counters& counters() const;

 private:
  std::unique_ptr<LinearState> state_;
};

}  // namespace pce::sim::solver
