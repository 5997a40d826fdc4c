// SPDX-License-Identifier: MIT
/// @file
/// What every solver's time step shares (internal to `Simulation`, docs/simulation.md §5):
/// the inertia term, the state the step starts from, the iterate, the per-effect timings
/// and the frame's statistics, and the energy passes and failure reports both solvers use.
/// Newton (solver/newton.*) and block descent (solver/block_descent.*) each keep their own
/// state besides, between steps.
#pragma once

#include "util/stopwatch.hpp"

#include <pce/sim/effect.hpp>
#include <pce/sim/simulation.hpp>

#include <memory>
#include <string>
#include <vector>

namespace pce::sim::solver {

/// The inertia term of the incremental potential for one step,
/// Σᵢ mᵢ/(2h²) |yᵢ − x̃ᵢ|², x̃ = xⁿ + h vⁿ: its energy, gradient and Hessian (the diagonal
/// mᵢ/h² I), written here alone.
class Inertia {
 public:
  /// For the step of size h from xⁿ = `x` with vⁿ = `v`.
  void start(const Model& model, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, double h);
  /// The energy at y, summed over the 3n coordinates (the line search's and the accepted
  /// state's passes).
  double energy(const Eigen::Matrix3Xd& y) const;
  /// The energy at y summed vertex by vertex, as Newton's assembly sums it (its rounding
  /// differs from `energy`'s in the last bits; both are kept so that results do not change).
  double assembled_energy(const Eigen::Matrix3Xd& y) const;
  /// Sets `g` to the gradient mᵢ/h² (yᵢ − x̃ᵢ).
  void gradient(const Eigen::Matrix3Xd& y, Eigen::Matrix3Xd& g) const;
  /// mᵢ/h² per coordinate, the Hessian's diagonal (3n).
  const Eigen::VectorXd& diagonal() const { return mass3_; }
  /// mᵢ/h² of vertex i.
  double vertex_mass(int i) const { return (*mass_)[i] / (h_ * h_); }
  /// x̃ = xⁿ + h vⁿ.
  const Eigen::Matrix3Xd& target() const { return target_; }

 private:
  const Eigen::VectorXd* mass_ = nullptr;
  double h_ = 0;
  Eigen::VectorXd mass3_;
  Eigen::Matrix3Xd target_;
};

/// One time step as every solver sees it (see the file comment).
struct Step {
  Step(const Model& model, std::vector<std::unique_ptr<Effect>>& effects, const SolverSettings& settings)
      : model(model), effects(effects), settings(settings), n(model.vertex_count()) {}
  const Model& model;
  std::vector<std::unique_ptr<Effect>>& effects;
  const SolverSettings& settings;
  int n;
  Clock::time_point t_frame = Clock::now();
  FrameStats st;
  std::vector<double> effect_ms;      ///< per effect, in scene order
  Eigen::Matrix3Xd x_start, v_start;  ///< xⁿ and vⁿ
  Inertia inertia;
  double h = 0;        ///< the step's size: dt/substeps (`SolverSettings`)
  double scale = 1;    ///< ℓ, the rest bounding-box diagonal (residuals are max|Δx|/(h ℓ))
  Eigen::Matrix3Xd y;  ///< the iterate: xⁿ⁺¹ when the solver returns
  /// The energy at y (valid when `evaluated_at_y`).
  double E_accepted = 0;
  /// The effects' last evaluation was at y with their current candidates, and E_accepted is
  /// its energy; otherwise `Simulation` evaluates once more at the accepted state.
  bool evaluated_at_y = false;

  /// The incremental potential at y (inertia and every effect, each effect's time added to
  /// `effect_ms`).
  double potential(const Eigen::Matrix3Xd& at);
  /// Throws the SimulationError that names what is not finite at `at` (the position of a
  /// vertex, else the first effect with a non-finite energy or gradient), `where` saying
  /// when ("at Newton iteration 3").
  [[noreturn]] void fail_non_finite(const Eigen::Matrix3Xd& at, const std::string& where) const;
  /// The effects that implement interface `Hook` (`NewtonHooks`, `BlockDescentHooks`,
  /// `Requery`, …), with their indices in scene order.
  template <class Hook> std::vector<std::pair<std::size_t, Hook*>> find() const {
    std::vector<std::pair<std::size_t, Hook*>> found;
    for (std::size_t k = 0; k < effects.size(); ++k)
      if (Hook* h = dynamic_cast<Hook*>(effects[k].get())) found.emplace_back(k, h);
    return found;
  }
};

/// A way to solve a time step: from s.y = xⁿ, leaves xⁿ⁺¹ in s.y and fills its part of s.st.
/// Kept by `Simulation` between steps while the mode stays the same.
class StepSolver {
 public:
  virtual ~StepSolver() = default;
  /// Solves the step (the effects' begin_step has run).
  virtual void solve(Step& s) = 0;
  /// Adds the solver's own counters to the frame's (after the effects' are merged).
  virtual void report(Step& /*s*/) const {}
};

/// Newton (modes newton and single_solve, solver/newton.cpp).
std::unique_ptr<StepSolver> make_newton();
/// Block descent (mode block_descent, solver/block_descent.cpp).
std::unique_ptr<StepSolver> make_block_descent();

}  // namespace pce::sim::solver
