// SPDX-License-Identifier: MIT
// The Newton system's linear solvers (linear_state.hpp).
#include "solver/linear_state.hpp"

#include "util/stopwatch.hpp"

#include <omp.h>

#include <algorithm>

namespace pce::sim::solver {

namespace {

/// factor_reuse's back-off. A CG failure costs the whole CG cap and then a factorisation
/// anyway. After one failure CG is tried again at the next solve (with the factor just
/// made, which is usually a good preconditioner); after the second failure in a row the next
/// solve refactors without trying CG, after the third the next 2, then 4, … up to this
/// many; a CG success resets the count. Where the kept factor is a poor preconditioner (in
/// contact the Hessian changes a lot from one Newton iteration to the next) this bounds the
/// CG work spent in vain to about one attempt per this many solves; where it is a good one
/// (free fall) CG is tried every time. The rule counts solves, not time, so runs are
/// reproducible.
constexpr int kMaxReuseBackoff = 16;

/// Runs CHOLMOD (and the other factorisations) with OpenMP's parallel regions inactive.
/// SuiteSparse 5's supernodal factorisation opens a region of CHOLMOD_OMP_NUM_THREADS = 4
/// threads (a compile-time constant that neither omp_set_num_threads nor `--threads`
/// reaches) around its scatter and clear loops; on a 2-core machine those regions cost
/// more in waking and parking threads than the copies they share out, and they made a
/// `--threads 1` run use four. The dense work is in BLAS, which is serial here.
class SerialRegions {
 public:
  SerialRegions() : levels_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
  ~SerialRegions() { omp_set_max_active_levels(levels_); }
  SerialRegions(const SerialRegions&) = delete;
  SerialRegions& operator=(const SerialRegions&) = delete;

 private:
  int levels_;
};
}  // namespace

/// Symbolic analysis when the pattern changed, then the numerical factorisation, each
/// timed; false when the factorisation fails.
template <class Factorization> bool LinearState::factor(Factorization& f, const SparseMatrix& A) {
  factored = nullptr;
  if (!analyzed) {
    {
      const ScopedTimer timer(counters, Counter::analyze_ms);
      f.analyzePattern(A);
    }
    counters[Counter::analyses] += 1;
    analyzed = true;
  }
  {
    const ScopedTimer timer(counters, Counter::factorize_ms);
    f.factorize(A);
  }
  counters[Counter::factorizations] += 1;
  if (f.info() != Eigen::Success) return false;
  factored = &f;
  return true;
}

/// A factor object as CG's preconditioner: z = f⁻¹ r (one forward and back substitution).
template <class Factorization> class FactorPreconditioner final : public Preconditioner {
 public:
  explicit FactorPreconditioner(const Factorization& f) : f_(f) {}
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override { z = f_.solve(r); }

 private:
  const Factorization& f_;
};

/// factor_reuse with the factor object `f`: CG preconditioned by the kept factor; when
/// there is none, or CG does not converge, a new factorisation of the current H, whose
/// solve is the exact direction. After repeated CG failures the next `reuse_skip` solves
/// refactor without trying CG (the back-off, see kMaxReuseBackoff). False when the
/// factorisation or its solve fails.
template <class Factorization> bool LinearState::reuse_solve(Factorization& f, const SparseMatrix& A,
                                                             const Eigen::VectorXd& rhs, double eta, int max_iterations,
                                                             Eigen::VectorXd& dx) {
  if (factored == &f && reuse_skip == 0) {
    // The kept factor is an SPD operator on vectors of size 3n, whatever H's pattern now.
    prepare_csr();
    if (krylov.solve(csr, FactorPreconditioner<Factorization>(f), rhs, eta, max_iterations, dx,
                     counters[Counter::cg_iterations])) {
      reuse_failures = 0;
      return true;
    }
    ++reuse_failures;
    if (reuse_failures >= 2) reuse_skip = std::min(1 << std::min(reuse_failures - 2, 30), kMaxReuseBackoff);
  } else if (reuse_skip > 0) {
    --reuse_skip;
  }
  if (!factor(f, A)) return false;
  dx = f.solve(rhs);
  return f.info() == Eigen::Success;
}

void LinearState::prepare_csr() {
  const SparseMatrix& A = H.matrix();
  if (!csr_current || !csr.fits(A)) {
    const ScopedTimer timer(counters, Counter::analyze_ms);
    csr.build(A);
    counters[Counter::analyses] += 1;
    csr_current = true;
  }
  csr.update(A);
}

bool LinearState::krylov_solve(const SolverSettings& settings, const Eigen::VectorXd& rhs, Eigen::VectorXd& dx,
                               double eta) {
  prepare_csr();
  const Preconditioner* M = &jacobi;
  if (settings.linear == LinearSolver::amg) {
    // A hierarchy of an earlier iteration of this step (any pattern of the same size) is
    // reused for up to amg_setup_reuse further solves.
    const bool reuse = amg.ready() && amg_age >= 0 && amg_age < settings.amg_setup_reuse;
    if (reuse) {
      ++amg_age;
    } else {
      const ScopedTimer timer(counters, Counter::preconditioner_ms);
      counters[Counter::preconditioner_setups] += 1;
      if (!amg.setup(csr, positions)) return false;
      amg_age = 0;
    }
    M = &amg;
  } else {
    const ScopedTimer timer(counters, Counter::preconditioner_ms);
    counters[Counter::preconditioner_setups] += 1;
    if (!jacobi.setup(csr)) return false;
  }
  return krylov.solve(csr, *M, rhs, eta, settings.linear_max_iterations, dx, counters[Counter::cg_iterations]);
}

/// Solves H dx = rhs; false when the factorisation or the iteration fails.
bool LinearState::solve(const SolverSettings& settings, const Eigen::VectorXd& rhs, Eigen::VectorXd& dx, double eta) {
  const SparseMatrix& A = H.matrix();
  if (dump) dump->write(A, rhs);
  if (settings.linear != last) {
    analyzed = false;  // another solver's analysis, or none
    last = settings.linear;
  }
  if (settings.linear == LinearSolver::pcg || settings.linear == LinearSolver::amg)
    return krylov_solve(settings, rhs, dx, eta);
  const SerialRegions serial;
  switch (settings.linear) {
    case LinearSolver::pcg:
    case LinearSolver::amg:
      return false;  // solved above
    case LinearSolver::factor_reuse:
#ifdef PCE_SIM_HAVE_CHOLMOD
      return reuse_solve(cholmod, A, rhs, settings.reuse_tolerance, settings.reuse_max_cg_iterations, dx);
#else
      return reuse_solve(ldlt, A, rhs, settings.reuse_tolerance, settings.reuse_max_cg_iterations, dx);
#endif
    case LinearSolver::cg:
      cg.setTolerance(1e-8);
      cg.setMaxIterations(static_cast<Eigen::Index>(4 * rhs.size()));
      cg.compute(A);
      dx = cg.solve(rhs);
      counters[Counter::cg_iterations] += static_cast<double>(cg.iterations());
      return cg.info() == Eigen::Success;
    case LinearSolver::direct:
#ifdef PCE_SIM_HAVE_CHOLMOD
      if (!factor(cholmod, A)) return false;
      dx = cholmod.solve(rhs);
      return cholmod.info() == Eigen::Success;
#else
      [[fallthrough]];
#endif
    case LinearSolver::ldlt:
      if (!factor(ldlt, A)) return false;
      dx = ldlt.solve(rhs);
      return ldlt.info() == Eigen::Success;
  }
  return false;
}

}  // namespace pce::sim::solver

namespace pce::sim {

bool linear_solver_available(LinearSolver solver) { return solver != LinearSolver::amg || solver::hypre_available(); }

}  // namespace pce::sim
