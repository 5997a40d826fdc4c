// SPDX-License-Identifier: MIT
/// @file
/// An effect is one term of the incremental potential the solver minimises (gravity,
/// stretching, bending, pins, damping, contact, …). The solver loops over the scene's
/// effects through this interface without knowing any of them by name; only the effects a
/// scene declares are constructed (`pce/sim/scene.hpp`), so nothing else costs time.
///
/// The solver makes a few virtual calls per effect and Newton iteration (update_pattern,
/// evaluate, cover_step, max_step, still_valid, and evaluate again per line-search trial),
/// never one per element or pair.
#pragma once

#include <pce/friction/lagged_friction.hpp>
#include <pce/sim/block_hessian.hpp>
#include <pce/sim/counters.hpp>
#include <pce/sim/model.hpp>

#include <array>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace pce::sim {

/// Numbers an effect reports for the frame's statistics (`stats.json`), e.g. contact counts:
/// typed counters (`pce/sim/counters.hpp`).
using EffectCounters = Counters;

/// One contact's friction, frozen for the step, as Newton's stopping rule reads it
/// (`Effect::frozen_friction`): its vertices (up to four; unused ones have weight 0) and the
/// lagged quantities of `pce/friction/lagged_friction.hpp`.
struct FrozenFriction {
  std::array<int, 4> vertices{};       ///< the contact's vertices, in the order of the weights
  LaggedFriction<double, 4> friction;  ///< weights (0 for unused vertices), basis, offset, μλ, ε
};

/// One term of the incremental potential (see the file comment); the solver calls these
/// in the order begin_step, declare, then per Newton iteration update_pattern, evaluate,
/// cover_step, max_step, still_valid (and refresh when that says no), update_lagged after
/// each solve, and report once per frame.
class Effect {
 public:
  virtual ~Effect() = default;
  /// The scene's name of the effect (`"stretching"`, `"self_vertex_face"`, …).
  virtual const char* name() const = 0;
  /// Once per time step, before Newton: update prescribed data (pin targets, releases,
  /// obstacle poses, candidate pairs).
  virtual void begin_step(const StepContext& /*ctx*/) {}
  /// Declares the vertex tuples the Hessian couples (after `begin_step`, and again whenever
  /// `update_pattern` reports growth).
  virtual void declare(Pattern& pattern) const = 0;
  /// Called before each Newton iteration's assembly at `x`: an effect whose coupled tuples
  /// depend on the state (contact: only the pairs active at `x` couple their vertices)
  /// updates what it declares and returns true when that changed, so the solver rebuilds
  /// the pattern (and the linear solver its symbolic analysis); an unchanged declaration
  /// keeps both.
  virtual bool update_pattern(const Eigen::Matrix3Xd& /*x*/) { return false; }
  /// Returns the energy at `x` (3×n); when `gradient` is non-null adds ∇E to it, when
  /// `hessian` is non-null adds a positive-semidefinite approximation of ∇²E to it.
  virtual double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) = 0;
  /// Called once per Newton iteration with the Newton step `dx` from `x`, before
  /// `max_step`: a contact effect whose candidates would not stay valid along the step
  /// queries again over it (so that max_step need not cut the step short for the
  /// candidates' sake) and returns true; the solver then re-evaluates the energy at `x`
  /// with the new candidates. The active pairs at `x` are the same. With more than one
  /// thread the solver calls the effects' cover_step side by side, so an effect's
  /// cover_step may touch only that effect's own state.
  virtual bool cover_step(const Eigen::Matrix3Xd& /*x*/, const Eigen::Matrix3Xd& /*dx*/) { return false; }
  /// Largest fraction t ∈ (0, 1] of the step `dx` from `x` that this effect allows (a
  /// barrier keeps every active length above 0); 1 for effects without a domain limit.
  virtual double max_step(const Eigen::Matrix3Xd& /*x*/, const Eigen::Matrix3Xd& /*dx*/) { return 1.0; }
  /// Called after each accepted Newton update; returns false when the effect needs a new
  /// `begin_step`-time query (a contact effect whose candidates went stale).
  virtual bool still_valid(const Eigen::Matrix3Xd& /*x*/) { return true; }
  /// Re-runs the per-step query at the current positions (after `still_valid` said no).
  virtual void refresh(const Eigen::Matrix3Xd& /*x*/) {}
  /// Called when a solve of the time step has ended at `x`: an effect with quantities frozen
  /// at the step's start (friction's normal forces and bases) that is to freeze them again
  /// at `x` does so and returns true, and the solver solves the step again from `x` (friction's
  /// `lagged_iterations` − 1 times per step); false: nothing changed.
  virtual bool update_lagged(const Eigen::Matrix3Xd& /*x*/) { return false; }
  /// Counters for the frame's statistics (contact counts, minimum distance, …).
  virtual void report(EffectCounters& /*counters*/) const {}
  /// The state this effect carries from one step to the next that `begin_step` does not
  /// rebuild from the step context, as bytes (checkpoints, `pce/sim/checkpoint.hpp`): empty
  /// for an effect whose every step is a function of (frame, time, xⁿ, vⁿ). Self contact
  /// writes its tracked pairs with their settled sides and declarations.
  virtual std::string save_state() const { return {}; }
  /// Restores what `save_state` wrote (on an effect built from the same scene). Throws
  /// std::invalid_argument when `state` is not something `save_state` of this effect writes.
  virtual void load_state(const std::string& state) {
    if (!state.empty()) throw std::invalid_argument(std::string(name()) + ": unexpected saved state");
  }

  /// The friction contacts this effect froze for the step (μλ > 0 only): Newton's stopping
  /// rule checks that its model does not ask more of any than Coulomb's μλ (docs/simulation.md
  /// §5.2). The solver reads it at each step below the tolerance; the effect sets it in
  /// `begin_step` and `update_lagged`. Empty for every effect without friction.
  const std::vector<FrozenFriction>& frozen_friction() const { return frozen_friction_; }

 protected:
  /// What `frozen_friction` returns; the effect keeps it current.
  std::vector<FrozenFriction> frozen_friction_;
};

}  // namespace pce::sim
