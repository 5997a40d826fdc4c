// SPDX-License-Identifier: MIT
/// @file
/// State an effect carries from one step to the next that `Effect::begin_step` does not
/// rebuild from the step context: what a checkpoint keeps (`pce/sim/checkpoint.hpp` writes
/// and reads it for each effect that implements this interface; no solver calls it).
#pragma once

#include <string>

namespace pce::sim {

/// Carried state (see the file comment).
class CarriedState {
 public:
  virtual ~CarriedState() = default;
  /// The state as bytes: empty when every step is a function of (frame, time, xⁿ, vⁿ). Self
  /// contact writes its tracked pairs with their settled sides and declarations, obstacle
  /// contact its held pairs' stiffening.
  virtual std::string save_state() const = 0;
  /// Restores what `save_state` wrote (on an effect built from the same scene). Throws
  /// std::invalid_argument when `state` is not something `save_state` of this effect writes.
  virtual void load_state(const std::string& state) = 0;
};

}  // namespace pce::sim
