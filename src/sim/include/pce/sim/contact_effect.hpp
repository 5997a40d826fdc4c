// SPDX-License-Identifier: MIT
/// @file
/// What only contact effects do, beyond an `Effect`: bound the Newton step (a barrier keeps
/// every active length above 0), query their candidates again along a step or after it, let
/// the pairs active at a state shape the Hessian's pattern, freeze friction for a step, and
/// carry state from one step to the next. The solver discovers these effects among the
/// scene's (`dynamic_cast`, once per time step) and calls the functions below on them alone;
/// they are called in the order update_pattern (before each Newton iteration's assembly),
/// cover_step, max_step, stiffen_held, still_valid (and refresh when that says no) per Newton
/// iteration, update_lagged after each solve. Block descent calls cover_step and safe_step
/// once per step (its first move), then vertex_bounds, and per sweep begin_sweep (the
/// colouring follows the couplings it declares), evaluate_local per colour and still_valid
/// (vertex_bounds again when that says no).
#pragma once

#include <pce/friction/lagged_friction.hpp>
#include <pce/sim/effect.hpp>

#include <array>
#include <string>
#include <vector>

namespace pce::sim {

/// One contact's friction, frozen for the step, as Newton's stopping rule reads it
/// (`ContactEffect::frozen_friction`): its vertices (up to four; unused ones have weight 0)
/// and the lagged quantities of `pce/friction/lagged_friction.hpp`.
struct FrozenFriction {
  std::array<int, 4> vertices{};       ///< the contact's vertices, in the order of the weights
  LaggedFriction<double, 4> friction;  ///< weights (0 for unused vertices), basis, offset, μλ, ε
};

/// A contact effect (see the file comment). Every function has a default that does nothing.
class ContactEffect : public Effect {
 public:
  using Effect::Effect;

  /// Called before each Newton iteration's assembly at `x`: an effect whose coupled tuples
  /// depend on the state (only the pairs active at `x` couple their vertices) updates what
  /// it declares and returns true when that changed, so the solver rebuilds the pattern (and
  /// the linear solver its symbolic analysis); an unchanged declaration keeps both.
  virtual bool update_pattern(const Eigen::Matrix3Xd& /*x*/) { return false; }
  /// Called once per Newton iteration with the Newton step `dx` from `x`, before
  /// `max_step`: an effect whose candidates would not stay valid along the step queries
  /// again over it (so that max_step need not cut the step short for the candidates' sake)
  /// and returns true; the solver then re-evaluates the energy at `x` with the new
  /// candidates. The active pairs at `x` are the same. With more than one thread the solver
  /// calls the effects' cover_step side by side, so an effect's cover_step may touch only
  /// that effect's own state.
  virtual bool cover_step(const Eigen::Matrix3Xd& /*x*/, const Eigen::Matrix3Xd& /*dx*/) { return false; }
  /// Largest fraction t ∈ (0, 1] of the step `dx` from `x` that this effect allows (a
  /// barrier keeps every active length above 0); 1 without a domain limit.
  virtual double max_step(const Eigen::Matrix3Xd& /*x*/, const Eigen::Matrix3Xd& /*dx*/) { return 1.0; }
  /// Called after each accepted Newton update to `x`, before `still_valid`: an effect whose
  /// last max_step held pairs at their minimum separation stiffens the penalties of those
  /// that came within twice of it (docs/simulation.md §4.6) and returns true; the energy at
  /// `x` is then evaluated afresh. False: nothing changed.
  virtual bool stiffen_held(const Eigen::Matrix3Xd& /*x*/) { return false; }
  /// Called after each accepted Newton update; returns false when the effect needs a new
  /// `begin_step`-time query (its candidates went stale).
  virtual bool still_valid(const Eigen::Matrix3Xd& /*x*/) { return true; }
  /// Re-runs the per-step query at the current positions (after `still_valid` said no).
  virtual void refresh(const Eigen::Matrix3Xd& /*x*/) {}
  /// Called when a solve of the time step has ended at `x`: an effect with quantities frozen
  /// at the step's start (friction's normal forces and bases) that is to freeze them again
  /// at `x` does so, or one whose energy is to change there (obstacle contact stiffening a
  /// pair the solve left below its minimum separation), and returns true; the solver then
  /// solves the step again from `x` (friction's `lagged_iterations` − 1 times per step, the
  /// floor's at most 8). False: nothing changed.
  virtual bool update_lagged(const Eigen::Matrix3Xd& /*x*/) { return false; }
  /// Block descent (docs/simulation.md §5.5): the largest fraction t ∈ (0, 1] of the move dx
  /// from x along which no pair this effect sees can cross (its candidates and the set's
  /// validity for self contact, the obstacles' surfaces for obstacle contact), whether or
  /// not the effect bounds Newton's steps. The default is `max_step`.
  virtual double safe_step(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& dx) { return max_step(x, dx); }
  /// Block descent's first move, before safe_step: an effect whose pairs each hold one
  /// vertex (obstacle contact: the obstacles do not move during the sweeps) lowers limit[i],
  /// the fraction of dxᵢ vertex i alone may move (every other vertex moving any part of its
  /// own), so that the vertices it stops do not stop the rest; the solver then takes the
  /// largest safe_step of the move they leave. The default limits nothing.
  virtual void limit_moves(const Eigen::Matrix3Xd& /*x*/, const Eigen::Matrix3Xd& /*dx*/, Eigen::VectorXd& /*limit*/) {}
  /// Block descent: queries the effect's candidates again at x and lowers `bound[i]` (one
  /// entry per vertex, +∞ where nothing limits) to a distance vertex i may move away from x
  /// while every other vertex also stays within its bound, such that no pair of the effect
  /// crosses or comes closer than its minimum separation (a pair already closer keeps nine
  /// tenths of its distance), and no pair that is not a candidate comes within reach of
  /// crossing. The default (no domain to keep) leaves `bound` as it is.
  virtual void vertex_bounds(const Eigen::Matrix3Xd& /*x*/, Eigen::VectorXd& /*bound*/) {}
  /// Block descent, before each sweep from x in which vertex i moves at most `reach[i]`: an
  /// effect lists what its evaluate_local calls of the sweep can find active, so that they
  /// visit only that (and not the default's whole evaluation), and declares in `couplings`
  /// the vertex tuples those couple (the colouring keeps them apart).
  virtual void begin_sweep(const Eigen::Matrix3Xd& /*x*/, const Eigen::VectorXd& /*reach*/, Pattern& /*couplings*/) {}
  /// The friction contacts this effect froze for the step (μλ > 0 only): Newton's stopping
  /// rule checks that its model does not ask more of any than Coulomb's μλ
  /// (docs/simulation.md §5.2). Empty without friction.
  virtual const std::vector<FrozenFriction>& frozen_friction() const { return no_friction_; }
  /// The state this effect carries from one step to the next that `begin_step` does not
  /// rebuild from the step context, as bytes (checkpoints, `pce/sim/checkpoint.hpp`): empty
  /// when every step is a function of (frame, time, xⁿ, vⁿ). Self contact writes its
  /// tracked pairs with their settled sides and declarations.
  virtual std::string save_state() const { return {}; }
  /// Restores what `save_state` wrote (on an effect built from the same scene). Throws
  /// std::invalid_argument when `state` is not something `save_state` of this effect writes.
  virtual void load_state(const std::string& state);
  /// Updates the pattern to the pairs active at `x` (update_pattern), then the default
  /// evaluate_local: the blocks of the active pairs are then declared.
  void evaluate_local(const Eigen::Matrix3Xd& x, const std::vector<int>& vertices, LocalTerms& terms) override;

 private:
  std::vector<FrozenFriction> no_friction_;
};

/// `effect` as a ContactEffect, or null when it is none.
inline ContactEffect* as_contact(Effect* effect) { return dynamic_cast<ContactEffect*>(effect); }

}  // namespace pce::sim
