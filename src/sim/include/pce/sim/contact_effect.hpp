// SPDX-License-Identifier: MIT
/// @file
/// The base of the contact effects (self contact, obstacle contact): an `Effect` that also
/// implements Newton's hooks, block descent's hooks, the re-query and the carried state
/// (`pce/sim/newton_hooks.hpp`, `pce/sim/block_descent_hooks.hpp`, `pce/sim/requery.hpp`,
/// `pce/sim/carried_state.hpp`), each with a default that does nothing. No solver asks for a
/// `ContactEffect`: each asks for its own interface; this class only gathers them for the
/// effects (and tests) that have all of them.
#pragma once

#include <pce/sim/block_descent_hooks.hpp>
#include <pce/sim/carried_state.hpp>
#include <pce/sim/effect.hpp>
#include <pce/sim/newton_hooks.hpp>
#include <pce/sim/requery.hpp>

#include <string>

namespace pce::sim {

/// A contact effect (see the file comment).
class ContactEffect : public Effect, public NewtonHooks, public BlockDescentHooks, public Requery, public CarriedState {
 public:
  using Effect::Effect;

  /// True: no query to go stale.
  bool still_valid(const Eigen::Matrix3Xd& /*x*/) override { return true; }
  /// Nothing to query.
  void refresh(const Eigen::Matrix3Xd& /*x*/) override {}
  /// Empty: nothing carried.
  std::string save_state() const override { return {}; }
  /// Accepts the empty state only (std::invalid_argument otherwise).
  void load_state(const std::string& state) override;
};

/// `effect` as a ContactEffect, or null when it is none.
inline ContactEffect* as_contact(Effect* effect) { return dynamic_cast<ContactEffect*>(effect); }

}  // namespace pce::sim
