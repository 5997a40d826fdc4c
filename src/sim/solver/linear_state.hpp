// SPDX-License-Identifier: MIT
/// @file
/// The Newton system's matrix and the linear solvers of `SolverSettings::linear`, kept
/// between steps (internal to Newton's solver, solver/newton.cpp): a factorisation every iteration (CHOLMOD when
/// built with it, else Eigen's LDLᵀ), factor_reuse's conjugate gradients preconditioned by a
/// kept factor, Eigen's diagonally preconditioned conjugate gradients, or conjugate gradients
/// preconditioned by block Jacobi (pcg) or BoomerAMG (amg; solver/krylov.hpp,
/// solver/hypre_amg.hpp) (docs/simulation.md §5.3).
#pragma once

#include "solver/hypre_amg.hpp"
#include "solver/krylov.hpp"
#include "solver/system_dump.hpp"

#include <pce/sim/block_hessian.hpp>
#include <pce/sim/simulation.hpp>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#ifdef PCE_SIM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

namespace pce::sim::solver {

/// The linear solver and the global Hessian, kept between steps (no allocation per
/// iteration once the pattern is built).
struct LinearState {
  using SparseMatrix = Eigen::SparseMatrix<double>;
  BlockHessian H;
  /// The factor object's symbolic analysis is that of H's current pattern (cleared by
  /// `pattern_changed`; `factor` analyses again before it factorises).
  bool analyzed = false;
  /// H's pattern changed: the factor's analysis and `csr`'s structure are stale.
  void pattern_changed() {
    analyzed = false;
    csr_current = false;
  }
#ifdef PCE_SIM_HAVE_CHOLMOD
  Eigen::CholmodDecomposition<SparseMatrix, Eigen::Upper> cholmod;
#endif
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Upper> ldlt;
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Upper> cg;
  /// The factor object that holds a complete numerical factor (of some earlier H, maybe of
  /// another pattern), or null: what factor_reuse may precondition with.
  const void* factored = nullptr;
  /// This step's counters: `analyze_ms`, `factorize_ms` (timed), `analyses`,
  /// `factorizations`, `cg_iterations` (factor_reuse, cg, pcg, amg) and
  /// `preconditioner_setups`, `preconditioner_ms` (pcg, amg); `start_step` zeroes them.
  Counters counters;
  /// Zeroes the step's counters (each is reported, 0 when nothing happened) and starts the
  /// step's count of amg's setup reuse.
  void start_step() {
    for (const Counter c : {Counter::analyze_ms, Counter::factorize_ms, Counter::analyses, Counter::factorizations,
                            Counter::cg_iterations, Counter::preconditioner_setups, Counter::preconditioner_ms})
      counters[c] = 0;
    amg_age = -1;
    if (dump) dump->start_step();
  }
  int reuse_failures = 0;  ///< factor_reuse: CG failures since the last CG success
  int reuse_skip = 0;      ///< factor_reuse: solves still to refactor without trying CG
  BlockCsr csr;            ///< the CG solvers' H as a full block-CSR matrix
  /// `csr`'s structure is that of H's current pattern (cleared with `analyzed`).
  bool csr_current = false;
  BlockJacobi jacobi;  ///< pcg's preconditioner
  HypreAmg amg;        ///< amg's preconditioner
  /// The positions the system was linearised at (3 × n), or null: amg's rotation modes.
  const Eigen::Matrix3Xd* positions = nullptr;
  Krylov krylov;  ///< pcg's and amg's vectors
  /// amg: solves of this step since the hierarchy was set up (-1: none this step).
  int amg_age = -1;
  /// The solver of the last solve (a change of solver analyses again).
  LinearSolver last = LinearSolver::direct;
  /// Writes each system solved when PCE_SIM_DUMP_SYSTEM is set (solver/system_dump.hpp).
  std::unique_ptr<SystemDump> dump = SystemDump::from_environment();

  /// Solves H dx = rhs with `settings.linear`; false when the factorisation, its solve or the
  /// iteration fails. OpenMP's parallel regions are inactive meanwhile (SerialRegions in
  /// linear_state.cpp).
  /// pcg and amg stop at ‖rhs − H dx‖ ≤ `eta` ‖rhs‖ (Newton's forcing term); the direct
  /// solvers ignore `eta`.
  bool solve(const SolverSettings& settings, const Eigen::VectorXd& rhs, Eigen::VectorXd& dx, double eta);

 private:
  /// Symbolic analysis when the pattern changed, then the numerical factorisation, each
  /// timed; false when the factorisation fails.
  template <class Factorization> bool factor(Factorization& f, const SparseMatrix& A);
  /// `csr` holds H's current values, its structure rebuilt (and counted as an analysis)
  /// when the pattern changed since it was built.
  void prepare_csr();
  /// pcg and amg: CG preconditioned by block Jacobi or BoomerAMG, in parallel (outside
  /// SerialRegions).
  bool krylov_solve(const SolverSettings& settings, const Eigen::VectorXd& rhs, Eigen::VectorXd& dx, double eta);
  /// factor_reuse with the factor object `f`: the same CG (`Krylov::solve`) preconditioned by
  /// `f`, the factor of an earlier H (linear_state.cpp).
  template <class Factorization> bool reuse_solve(Factorization& f, const SparseMatrix& A, const Eigen::VectorXd& rhs,
                                                  double eta, int max_iterations, Eigen::VectorXd& dx);
};

}  // namespace pce::sim::solver
