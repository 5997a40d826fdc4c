// SPDX-License-Identifier: MIT
/// @file
/// How effects are built from a scene: every effect file of `effects/` defines the public
/// builder `make_<name>` (`pce/sim/effects.hpp`) and knows nothing of the scene;
/// `scene/effect_loaders.cpp` holds a `load_<name>` factory per effect that reads the scene
/// object and calls it, and `scene/registry.cpp` maps the scene's effect names to those
/// factories. Internal.
#pragma once

#include "params.hpp"

#include <pce/sim/broad_phase.hpp>
#include <pce/sim/effect.hpp>
#include <pce/sim/obstacle.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace pce::sim {

/// What a factory may read: the built model (masses included), the obstacles, the broad
/// phase to use and a self-contact entry's mesh pairs.
struct BuildContext {
  /// The model the effect acts on: the scene's, or `restrict_to_meshes` of it for an entry
  /// with `meshes`.
  const Model* model = nullptr;
  const std::vector<Obstacle>* obstacles = nullptr;
  BroadPhaseKind broad_phase = BroadPhaseKind::fcl;
  /// A self-contact entry's `meshes` given as pairs (`ContactSettings::mesh_pairs`); empty:
  /// every pair of `model`'s meshes.
  std::vector<std::array<std::string, 2>> mesh_pairs;
};

using EffectFactory = std::unique_ptr<Effect> (*)(const Params& params, const BuildContext& ctx);

}  // namespace pce::sim
