// SPDX-License-Identifier: MIT
/// @file
/// What Newton's solver (`Simulation::step` in modes `newton` and `single_solve`,
/// docs/simulation.md §5.2) tells the effects that implement this interface, beyond what it
/// asks of every `Effect`. It finds them among the scene's effects once per time step
/// (`dynamic_cast`) and calls, per Newton iteration from the iterate y:
///
///     begin_iteration(y)            before the iteration's assembly (the pattern may change)
///     cover_step(y, Δx)             with the iteration's direction, before the line search
///     begin_line_search(y, Δx)      the line search begins: the largest fraction allowed
///       evaluate(y + α Δx) …        the trials (`Effect::evaluate`)
///     end_line_search(y')           the line search ended at y' (its trial, or y)
///     Requery::still_valid / refresh  after an accepted trial (pce/sim/requery.hpp)
///
/// and end_solve(y) when a solve of the step has ended; frozen_friction is read by the
/// stopping rule. Block descent never calls these.
#pragma once

#include <pce/friction/lagged_friction.hpp>

#include <Eigen/Core>

#include <array>
#include <vector>

namespace pce::sim {

/// One contact's friction, frozen for the step, as Newton's stopping rule reads it
/// (`NewtonHooks::frozen_friction`): its vertices (up to four; unused ones have weight 0)
/// and the lagged quantities of `pce/friction/lagged_friction.hpp`.
struct FrozenFriction {
  std::array<int, 4> vertices{};       ///< the contact's vertices, in the order of the weights
  LaggedFriction<double, 4> friction;  ///< weights (0 for unused vertices), basis, offset, μλ, ε
};

/// Newton's hooks (see the file comment). Every function has a default that does nothing.
class NewtonHooks {
 public:
  virtual ~NewtonHooks() = default;

  /// Newton: an iteration begins at the iterate `x`, before its assembly. An effect whose
  /// coupled tuples depend on the state (only the pairs active at `x` couple their vertices)
  /// updates what it declares and returns true when that changed, so the solver rebuilds the
  /// pattern (and the linear solver its symbolic analysis); an unchanged declaration keeps
  /// both. An effect may also note what it needs of the iterate (obstacle contact: its held
  /// pairs closer than their floor at `x`).
  virtual bool begin_iteration(const Eigen::Matrix3Xd& /*x*/) { return false; }
  /// Newton: the iteration's direction `dx` from `x` is known, before `begin_line_search`.
  /// An effect whose candidates would not stay valid along the step queries again over it
  /// (so that the step bound need not cut the step short for the candidates' sake) and
  /// returns true; the solver then re-evaluates the energy at `x` with the new candidates.
  /// The active pairs at `x` are the same. With more than one thread the solver calls the
  /// effects' cover_step side by side, so an effect's cover_step may touch only that
  /// effect's own state.
  virtual bool cover_step(const Eigen::Matrix3Xd& /*x*/, const Eigen::Matrix3Xd& /*dx*/) { return false; }
  /// Newton: a line search begins at `x` along `dx`; its trials are x + α dx, α halving from
  /// the smallest value the effects return. Returns the largest fraction t ∈ (0, 1] of `dx`
  /// this effect allows (a barrier keeps every active length above 0; the minimum separation
  /// keeps its floors); 1 without a domain limit.
  virtual double begin_line_search(const Eigen::Matrix3Xd& /*x*/, const Eigen::Matrix3Xd& /*dx*/) { return 1.0; }
  /// Newton: the line search begun last ended with the iterate at `x` (its accepted trial;
  /// or, when it found none, where it began, unless the direction was below the tolerance:
  /// that solve ends without this call). An effect whose line search held pairs at their
  /// minimum separation stiffens the penalties of those the search pressed in
  /// (docs/simulation.md §4.6) and returns true: the energy at `x` changed (a failed search
  /// is then tried again from `x`). False: nothing changed.
  virtual bool end_line_search(const Eigen::Matrix3Xd& /*x*/) { return false; }
  /// Newton: a solve of the time step has ended at `x`. An effect with quantities frozen at
  /// the step's start (friction's normal forces and bases) that is to freeze them again at
  /// `x` does so, or one whose energy is to change there (obstacle contact stiffening a pair
  /// the solve left below its minimum separation), and returns true; the solver then solves
  /// the step again from `x` (friction's `lagged_iterations` − 1 times per step, the floor's
  /// at most 8). False: nothing changed.
  virtual bool end_solve(const Eigen::Matrix3Xd& /*x*/) { return false; }
  /// The friction contacts this effect froze for the step (μλ > 0 only): Newton's stopping
  /// rule checks that its model does not ask more of any than Coulomb's μλ
  /// (docs/simulation.md §5.2). Empty without friction.
  virtual const std::vector<FrozenFriction>& frozen_friction() const { return no_friction_; }

 private:
  std::vector<FrozenFriction> no_friction_;
};

}  // namespace pce::sim
