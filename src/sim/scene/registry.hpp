// SPDX-License-Identifier: MIT
/// @file
/// The effect registry (internal): scene effect names and their factories.
#pragma once

#include "factory.hpp"

#include <string>
#include <vector>

namespace pce::sim {

struct RegisteredEffect {
  const char* name;
  EffectFactory make;
  bool pair_contact;  ///< takes the `hessian` override (self contact through pce pairs)
};

const std::vector<RegisteredEffect>& effect_registry();

}  // namespace pce::sim
