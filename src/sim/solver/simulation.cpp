// SPDX-License-Identifier: MIT
// Backward Euler by projected Newton on the incremental potential (simulation.hpp).
#include <pce/sim/input_error.hpp>
#include <pce/sim/simulation.hpp>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#ifdef PCE_SIM_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pce::sim {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
using SpMat = Eigen::SparseMatrix<double>;

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

/// The linear solver and the global Hessian, kept between steps (no allocation per
/// iteration once the pattern is built).
struct Simulation::LinearState {
  BlockHessian H;
  /// The factor object's symbolic analysis is that of H's current pattern (cleared when the
  /// pattern changes; `factor` analyses again before it factorises).
  bool analyzed = false;
#ifdef PCE_SIM_HAVE_CHOLMOD
  Eigen::CholmodDecomposition<SpMat, Eigen::Upper> cholmod;
#endif
  Eigen::SimplicialLDLT<SpMat, Eigen::Upper> ldlt;
  Eigen::ConjugateGradient<SpMat, Eigen::Upper> cg;
  /// The factor object that holds a complete numerical factor (of some earlier H, maybe of
  /// another pattern), or null: what factor_reuse may precondition with.
  const void* factored = nullptr;
  double analyze_ms = 0, factorize_ms = 0;  ///< this step's symbolic and numeric factorisation time
  int analyses = 0;                         ///< symbolic analyses this step
  int factorizations = 0;                   ///< numerical factorisations this step
  int cg_iterations = 0;                    ///< conjugate-gradient iterations this step (factor_reuse, cg)
  Eigen::VectorXd r, z, p, q;               ///< factor_reuse's CG vectors
  int reuse_failures = 0;                   ///< factor_reuse: CG failures since the last CG success
  int reuse_skip = 0;                       ///< factor_reuse: solves still to refactor without trying CG

  /// Symbolic analysis when the pattern changed, then the numerical factorisation, each
  /// timed; false when the factorisation fails.
  template <class Factorization> bool factor(Factorization& f, const SpMat& A) {
    factored = nullptr;
    if (!analyzed) {
      const auto t0 = Clock::now();
      f.analyzePattern(A);
      analyze_ms += ms_since(t0);
      ++analyses;
      analyzed = true;
    }
    const auto t0 = Clock::now();
    f.factorize(A);
    factorize_ms += ms_since(t0);
    ++factorizations;
    if (f.info() != Eigen::Success) return false;
    factored = &f;
    return true;
  }

  /// factor_reuse: solves H dx = rhs by conjugate gradients preconditioned by `f`, the
  /// factor of an earlier H (one forward and back substitution per iteration), from dx = 0.
  /// True when ‖rhs − H dx‖ ≤ `eta` ‖rhs‖ within `max_iterations` and dx is a descent
  /// direction (rhsᵀdx > 0, rhs = −g); false when it is not, or when pᵀHp or rᵀz is not > 0
  /// (the preconditioned operator is not SPD along the search direction, or a value is not
  /// finite). The loop is written out rather than Eigen's ConjugateGradient with an
  /// adapter preconditioner class pointing at the factor: twenty lines in which every exit
  /// (converged, breakdown, cap) is explicit and counted, where Eigen's loop reports only
  /// success or no convergence and does not stop at pᵀHp ≤ 0.
  template <class Factorization> bool preconditioned_cg(const Factorization& f, const SpMat& A,
                                                        const Eigen::VectorXd& rhs, double eta, int max_iterations,
                                                        Eigen::VectorXd& dx) {
    const double target = eta * rhs.norm();
    dx.setZero(rhs.size());
    if (rhs.norm() == 0) return true;
    r = rhs;
    z = f.solve(r);
    p = z;
    double rz = r.dot(z);
    for (int k = 0; k < max_iterations; ++k) {
      q.noalias() = A.selfadjointView<Eigen::Upper>() * p;
      const double pq = p.dot(q);
      if (!(pq > 0) || !(rz > 0)) return false;
      const double alpha = rz / pq;
      dx += alpha * p;
      r -= alpha * q;
      ++cg_iterations;
      if (r.norm() <= target) return rhs.dot(dx) > 0;
      z = f.solve(r);
      const double rz_next = r.dot(z);
      p = z + (rz_next / rz) * p;
      rz = rz_next;
    }
    return false;
  }

  /// factor_reuse with the factor object `f`: CG preconditioned by the kept factor; when
  /// there is none, or CG does not converge, a new factorisation of the current H, whose
  /// solve is the exact direction. After repeated CG failures the next `reuse_skip` solves
  /// refactor without trying CG (the back-off, see kMaxReuseBackoff). False when the
  /// factorisation or its solve fails.
  template <class Factorization> bool reuse_solve(Factorization& f, const SpMat& A, const Eigen::VectorXd& rhs,
                                                  double eta, int max_iterations, Eigen::VectorXd& dx) {
    if (factored == &f && reuse_skip == 0) {
      if (preconditioned_cg(f, A, rhs, eta, max_iterations, dx)) {
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

  /// Solves H dx = rhs; false when the factorisation or the iteration fails.
  bool solve(const SolverSettings& settings, const Eigen::VectorXd& rhs, Eigen::VectorXd& dx) {
    const SpMat& A = H.matrix();
    const SerialRegions serial;
    switch (settings.linear) {
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
        cg_iterations += static_cast<int>(cg.iterations());
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
};

double Simulation::potential(const Eigen::Matrix3Xd& y, std::vector<double>* effect_ms) {
  const Eigen::Map<const Eigen::VectorXd> d(y.data() - 0, y.size());
  const Eigen::Map<const Eigen::VectorXd> t(x_tilde_.data(), x_tilde_.size());
  double E = 0.5 * (mass3_.array() * (d - t).array().square()).sum();
  for (std::size_t k = 0; k < effects.size(); ++k) {
    const auto t0 = Clock::now();
    E += effects[k]->evaluate(y, nullptr, nullptr);
    if (effect_ms) (*effect_ms)[k] += ms_since(t0);
  }
  return E;
}

double Simulation::friction_load(const Eigen::Matrix3Xd& y, const Eigen::Matrix3Xd& x_start,
                                 const Eigen::Matrix3Xd& step) const {
  double load = 0;
  Eigen::Matrix<double, 12, 1> dx, ddx;
  for (const FrozenFriction& c : friction_) {
    for (int j = 0; j < 4; ++j) {
      const int v = c.vertices[static_cast<std::size_t>(j)];
      dx.segment<3>(3 * j) = y.col(v) - x_start.col(v);
      ddx.segment<3>(3 * j) = step.col(v);
    }
    load = std::max(load, friction_model_force(c.friction, dx, ddx).norm() / c.friction.mu_lambda);
  }
  return load;
}

void Simulation::gather_friction() {
  friction_.clear();
  for (const auto& e : effects)
    friction_.insert(friction_.end(), e->frozen_friction().begin(), e->frozen_friction().end());
}

const char* to_string(StopReason reason) {
  switch (reason) {
    case StopReason::tolerance:
      return "tolerance";
    case StopReason::rounding:
      return "rounding";
    case StopReason::line_search:
      return "line_search";
    case StopReason::iteration_cap:
      return "iteration_cap";
    case StopReason::single_solve:
      return "single_solve";
  }
  return "";
}

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

FrameStats Simulation::step() {
  const auto t_frame = Clock::now();
  check();
  if (!linear_) linear_ = std::make_shared<LinearState>();
  if (solver.threads > 0) omp_set_num_threads(solver.threads);
  static const bool trace_ = std::getenv("PCE_SIM_TRACE") != nullptr;  // one line per Newton iteration on stderr
  LinearState& ls = *linear_;
  ls.analyze_ms = ls.factorize_ms = 0;
  ls.analyses = ls.factorizations = ls.cg_iterations = 0;
  const int n = model.vertex_count();
  const double h = solver.dt;
  FrameStats st;
  st.frame = frame + 1;
  std::vector<double> effect_ms(effects.size(), 0.0);

  // Per-step constants: M/h² per coordinate, the inertial target, the length scale.
  mass3_.resize(3 * n);
  for (int i = 0; i < n; ++i) mass3_.segment<3>(3 * i).setConstant(model.mass[i] / (h * h));
  const Eigen::Matrix3Xd x_start = x, v_start = v;
  x_tilde_ = x + h * v;
  scale_ = std::max((model.rest.rowwise().maxCoeff() - model.rest.rowwise().minCoeff()).norm(), 1e-12);

  StepContext ctx;
  ctx.frame = frame + 1;
  ctx.time = time + h;
  ctx.dt = h;
  ctx.model = &model;
  ctx.x_start = &x_start;
  ctx.v_start = &v_start;
  for (std::size_t k = 0; k < effects.size(); ++k) {
    const auto t0 = Clock::now();
    effects[k]->begin_step(ctx);
    effect_ms[k] += ms_since(t0);
  }
  gather_friction();
  const auto rebuild_pattern = [&] {
    const auto t0 = Clock::now();
    Pattern pattern;
    for (const auto& e : effects) e->declare(pattern);
    if (ls.H.set_pattern(n, pattern)) ls.analyzed = false;
    const double ms = ms_since(t0);
    st.assembly_ms += ms;
    st.counters[Counter::pattern_ms] += ms;
    st.counters[Counter::pattern_builds] += 1;
  };
  rebuild_pattern();

  Eigen::Matrix3Xd y = x_start, g(3, n), dxm(3, n), y1(3, n);
  Eigen::VectorXd dx(3 * n), rhs(3 * n);
  const int cap = solver.single_solve ? 1 : std::max(1, solver.max_iterations);
  double E_accepted = 0;
  // The effects' last evaluation was at y with the current candidates: set when a trial
  // is accepted, cleared by a refresh (and by a trial that is not).
  bool evaluated_at_y = false;
  // One solve, or more when an effect freezes quantities again at a solve's result
  // (update_lagged: friction with lagged_iterations > 1).
  for (;;) {
    for (int it = 0; it < cap; ++it) {
      // Gradient and Hessian: inertia, then every effect (the pattern grows with the
      // active contacts).
      bool changed_pattern = false;
      for (std::size_t k = 0; k < effects.size(); ++k) {
        const auto tp = Clock::now();
        changed_pattern = effects[k]->update_pattern(y) || changed_pattern;
        effect_ms[k] += ms_since(tp);
      }
      if (changed_pattern) rebuild_pattern();
      auto t0 = Clock::now();
      ls.H.set_zero();
      ls.H.add_diagonal(mass3_);
      st.assembly_ms += ms_since(t0);
      g = (y - x_tilde_);
      for (int i = 0; i < n; ++i) g.col(i) *= model.mass[i] / (h * h);
      double E =
          0.5 * ((y - x_tilde_).colwise().squaredNorm().transpose().array() * model.mass.array()).sum() / (h * h);
      for (std::size_t k = 0; k < effects.size(); ++k) {
        t0 = Clock::now();
        E += effects[k]->evaluate(y, &g, &ls.H);
        effect_ms[k] += ms_since(t0);
      }
      if (!std::isfinite(E) || !g.allFinite())
        fail_non_finite(y, st.frame, "at Newton iteration " + std::to_string(it + 1));
      // Newton direction.
      t0 = Clock::now();
      rhs = -Eigen::Map<const Eigen::VectorXd>(g.data(), g.size());
      const bool solved = ls.solve(solver, rhs, dx);
      st.solve_ms += ms_since(t0);
      if (!solved || !dx.allFinite())
        throw SimulationError(st.frame, "", -1,
                              "frame " + std::to_string(st.frame) + ": the linear solve failed at Newton iteration " +
                                  std::to_string(it + 1) + (solved ? " (a non-finite direction)" : ""));
      ++st.newton_iterations;
      dxm = Eigen::Map<const Eigen::Matrix3Xd>(dx.data(), 3, n);
      st.residual = dxm.colwise().norm().maxCoeff() / (h * scale_);
      E_accepted = E;
      // A step below the tolerance ends the iterations, unless Newton's model asked a frozen
      // friction contact for more than Coulomb's μλ over it: static friction's Hessian
      // (2μλ/(ε_v h)) holds over a slip of ε_v h only, so it makes a step small far from the
      // solution when the contact must slide (docs/simulation.md §5.2).
      const bool small_step = st.residual < solver.tolerance;
      bool converged = small_step && friction_.empty();
      // Contact effects whose candidates would go stale along the step query again over it
      // (the pairs active at y, hence the pattern, stay those of the new candidates). Each
      // effect covers with its own candidate set and broad phase, so with two threads or more
      // the effects cover side by side (a vertex-face and an edge-edge effect usually query
      // at the same iteration); what each computes does not depend on it.
      bool covered = false;
      {
        const long count = static_cast<long>(effects.size());
        std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1) reduction(|| : covered) if (count > 1)
        for (long k = 0; k < count; ++k) {
          const auto uk = static_cast<std::size_t>(k);
          try {
            const auto tc = Clock::now();
            covered = effects[uk]->cover_step(y, dxm) || covered;
            effect_ms[uk] += ms_since(tc);
          } catch (...) {
#pragma omp critical(pce_sim_cover_error)
            if (!error) error = std::current_exception();
          }
        }
        if (error) std::rethrow_exception(error);
      }
      // Backtracking line search from the largest step every effect allows.
      t0 = Clock::now();
      double alpha = 1.0;
      NewtonIteration record;
      record.residual = st.residual;
      for (auto& e : effects)
        if (const double t = e->max_step(y, dxm); t < alpha) {
          alpha = t;
          record.limited_by = e->name();
        }
      // The Armijo test compares trials with an energy of the same candidates (the sum's
      // rounding depends on them): after a new query, the energy at y again.
      if (covered) {
        E = E_accepted = potential(y, &effect_ms);
        evaluated_at_y = true;
        if (!std::isfinite(E)) fail_non_finite(y, st.frame, "at Newton iteration " + std::to_string(it + 1));
      }
      record.step_limit = alpha;
      const double slope = -rhs.dot(dx);  // gᵀΔx < 0 for a descent direction
      bool accepted = false;
      // Trial steps whose largest vertex motion is below a hundredth of the stopping
      // tolerance's are not tried: such a step cannot change the outcome, and trying them
      // (40 halvings) made a step at a kink of the energy cost ~40 energy passes.
      const double smallest = 0.01 * solver.tolerance / std::max(st.residual, 1e-300);
      for (int tries = 0; tries < 40 && alpha > 0 && (tries == 0 || alpha >= smallest); ++tries, alpha *= 0.5) {
        y1 = y + alpha * dxm;
        const double E1 = potential(y1, &effect_ms);
        evaluated_at_y = false;
        if (std::isfinite(E1) && E1 <= E + 1e-4 * alpha * slope) {
          if (small_step && !friction_.empty()) {
            record.friction_load = st.friction_load = friction_load(y, x_start, alpha * dxm);
            converged = st.friction_load <= 1 + kCoulombMargin;
          }
          y = y1;
          E_accepted = E1;
          accepted = true;
          evaluated_at_y = true;
          break;
        }
      }
      st.line_search_ms += ms_since(t0);
      record.alpha = accepted ? alpha : 0.0;
      st.iterations.push_back(record);
      if (trace_)
        std::fprintf(
            stderr,
            "  it %d E %.9g slope %.3g alpha %.3g residual %.3g friction_load %.3g accepted %d factorizations %d "
            "cg_iterations %d covered %d\n",
            it, E, slope, alpha, st.residual, record.friction_load, accepted, ls.factorizations, ls.cg_iterations,
            int(covered));
      if (!accepted) {
        // A direction below the tolerance whose trial does not pass Armijo is rounding, not a
        // failure: the iterate already meets the tolerance, and the energy's change along such
        // a direction (a free fall's second one is ~1e-13) is below its own rounding. (Its
        // friction test would pass: at a zero step the model's force is the force, ≤ μλ.)
        if (small_step) {
          st.stop = StopReason::rounding;
        } else {
          ++st.line_search_failures;
          st.stop = StopReason::line_search;
        }
        break;
      }
      // Contact effects whose candidates went stale query again; the pattern follows.
      bool changed = false;
      for (std::size_t k = 0; k < effects.size(); ++k)
        if (!effects[k]->still_valid(y)) {
          t0 = Clock::now();
          effects[k]->refresh(y);
          effect_ms[k] += ms_since(t0);
          changed = true;
          evaluated_at_y = false;
        }
      if (changed) rebuild_pattern();
      if (converged) {
        st.stop = StopReason::tolerance;
        break;
      }
      if (it + 1 == cap) {
        st.stop = solver.single_solve ? StopReason::single_solve : StopReason::iteration_cap;
        st.hit_iteration_cap = !solver.single_solve;
      }
    }
    bool again = false;
    for (std::size_t k = 0; k < effects.size(); ++k) {
      const auto tl = Clock::now();
      again = effects[k]->update_lagged(y) || again;
      effect_ms[k] += ms_since(tl);
    }
    if (!again) break;
    gather_friction();
    rebuild_pattern();
    evaluated_at_y = false;
  }
  if (!y.allFinite()) fail_non_finite(y, st.frame, "after the line search");
  // The energy and every counter (contact counts, minimum distances) describe the accepted
  // state: when the last evaluation was elsewhere (a rejected trial) or with other
  // candidates (a refresh since), one more energy pass there.
  if (!evaluated_at_y) {
    const auto t0 = Clock::now();
    E_accepted = potential(y, &effect_ms);
    st.line_search_ms += ms_since(t0);
    if (!std::isfinite(E_accepted)) fail_non_finite(y, st.frame, "at the accepted state");
  }
  v = (y - x_start) / h;
  x = y;
  ++frame;
  time += h;
  st.energy = E_accepted;
  st.kinetic_energy = 0.5 * (v.colwise().squaredNorm().transpose().array() * model.mass.array()).sum();

  // Statistics: per-effect time, merged counters, the stage split.
  for (std::size_t k = 0; k < effects.size(); ++k) {
    st.effect_ms.emplace_back(effects[k]->name(), effect_ms[k]);
    EffectCounters c;
    effects[k]->report(c);
    st.counters.merge(c);  // summed, distances by their minimum (CounterInfo::minimum)
  }
  const auto counter = [&](Counter key) { return st.counters.has(key) ? st.counters.at(key) : 0.0; };
  st.broad_phase_ms = counter(Counter::broad_phase_ms);
  st.pair_ms = counter(Counter::pair_ms);
  st.assembly_ms += counter(Counter::scatter_ms);
  st.counters[Counter::pattern_blocks] = static_cast<double>(ls.H.block_count());
  st.counters[Counter::analyze_ms] = ls.analyze_ms;
  st.counters[Counter::factorize_ms] = ls.factorize_ms;
  st.counters[Counter::analyses] = ls.analyses;
  st.counters[Counter::factorizations] = ls.factorizations;
  st.counters[Counter::cg_iterations] = ls.cg_iterations;
  st.wall_ms = ms_since(t_frame);
  return st;
}

}  // namespace pce::sim
