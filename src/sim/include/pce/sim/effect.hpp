// SPDX-License-Identifier: MIT
/// @file
/// An effect is one term of the incremental potential the solver minimises (gravity,
/// stretching, bending, pins, damping, contact, …). The solver loops over the scene's
/// effects through this interface without knowing any of them by name; only the effects a
/// scene declares are constructed (`pce/sim/scene.hpp`), so nothing else costs time.
///
/// An `Effect` is what every solver needs of a term, and nothing solver-specific: five
/// virtual functions, `begin_step`, `declare`, `evaluate`, `evaluate_local` and `report`
/// (each but `declare` and `evaluate` has a default). What one solver alone asks of some
/// effects is that solver's own small interface, which an effect may implement as well and
/// which only that solver looks for (`dynamic_cast`, once per time step):
///  * `NewtonHooks` (`pce/sim/newton_hooks.hpp`): Newton's iterations, line searches and
///    solves, told to the effect as they happen (state-dependent patterns, re-queries over a
///    step, step bounds, lagged friction);
///  * `BlockDescentHooks` (`pce/sim/block_descent_hooks.hpp`): block descent's first move,
///    per-vertex bounds and sweeps; `AccelerationField` (same header): its first guess;
///  * `Requery` (`pce/sim/requery.hpp`): candidates that go stale as the state moves, which
///    both solvers check after each accepted update;
///  * `CarriedState` (`pce/sim/carried_state.hpp`): state a checkpoint keeps.
/// `ContactEffect` (`pce/sim/contact_effect.hpp`) is the base of the contact effects, which
/// implement all four. docs/simulation.md §5.6 draws who calls what, and when.
///
/// The solver makes a few virtual calls per effect and iteration, never one per element
/// or pair.
#pragma once

#include <pce/sim/block_hessian.hpp>
#include <pce/sim/counters.hpp>
#include <pce/sim/model.hpp>

#include <string>
#include <utility>
#include <vector>

namespace pce::sim {

/// Numbers an effect reports for the frame's statistics (`stats.json`), e.g. contact counts:
/// typed counters (`pce/sim/counters.hpp`).
using EffectCounters = Counters;

/// Per-vertex terms of the potential, for solvers that update one vertex at a time (block
/// coordinate descent): for each vertex i of a list, the effect's gradient ∂E/∂xᵢ and the
/// 3×3 diagonal block of its positive-semidefinite Hessian approximation, ∂²E/∂xᵢ² — except
/// friction's, whose block is its majorizer (`pce::friction_majorizer_block`, ⪰ the
/// Hessian's block), so that a vertex's step does not overshoot a sliding contact.
struct LocalTerms {
  Eigen::Matrix3Xd gradient;             ///< column j: the gradient at the list's vertex j
  std::vector<Eigen::Matrix3d> hessian;  ///< entry j: the diagonal block of the list's vertex j
  /// Entry j: 1 when a contact pair active at the point of evaluation acted on the list's
  /// vertex j (set by the contact effects; block descent's acceleration leaves such vertices).
  std::vector<char> contact;
  /// Zero terms for `count` vertices.
  void reset(std::size_t count) {
    gradient.setZero(3, static_cast<Eigen::Index>(count));
    hessian.assign(count, Eigen::Matrix3d::Zero());
    contact.assign(count, 0);
  }
};

/// One term of the incremental potential (see the file comment). Every solver calls
/// begin_step once per time step, then declare (Newton: before it assembles; block descent:
/// once per step, for the effects that do not implement `BlockDescentHooks`), then evaluate
/// (Newton: per iteration and line-search trial; both: at the accepted state) or
/// evaluate_local (block descent: per colour of each sweep), and report once per frame.
class Effect {
 public:
  /// `name`: the scene's name of the effect (`"stretching"`, `"self_vertex_face"`, …).
  explicit Effect(std::string name) : name_(std::move(name)) {}
  virtual ~Effect() = default;
  Effect(const Effect&) = delete;
  Effect& operator=(const Effect&) = delete;

  /// The scene's name of the effect.
  const char* name() const { return name_.c_str(); }
  /// Once per time step, before the solver's first call: update prescribed data (pin
  /// targets, releases, obstacle poses, candidate pairs).
  virtual void begin_step(const StepContext& /*ctx*/) {}
  /// Declares the vertex tuples the Hessian couples (after `begin_step`).
  virtual void declare(Pattern& pattern) const = 0;
  /// Returns the energy at `x` (3×n); when `gradient` is non-null adds ∇E to it, when
  /// `hessian` is non-null adds a positive-semidefinite approximation of ∇²E to it.
  virtual double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) = 0;
  /// Adds, for each vertex of `vertices`, the gradient and the diagonal Hessian block of
  /// `evaluate` at `x` to `terms` (sized for the list: `LocalTerms::reset`). The default
  /// evaluates the whole effect and reads those columns and blocks; an effect overrides it
  /// to evaluate only the elements touching the vertices.
  virtual void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms);
  /// Counters for the frame's statistics (contact counts, minimum distance, …).
  virtual void report(EffectCounters& /*counters*/) const {}

 private:
  std::string name_;
};

}  // namespace pce::sim
