// SPDX-License-Identifier: MIT
/// @file
/// The effect registry (internal): scene effect names and their factories.
#pragma once

#include "factory.hpp"

#include <string>
#include <vector>

namespace pce::sim {

/// What an entry's `meshes` key selects, for the checks that entries of one type neither
/// overlap nor leave gaps (docs/simulation.md §2.5).
enum class Coverage {
  none,                  ///< no `meshes` key (pins: each group names its mesh)
  meshes,                ///< the meshes it acts on
  mesh_pairs,            ///< the pairs of meshes whose primitives it makes meet
  meshes_and_obstacles,  ///< (mesh, obstacle) pairs: its meshes against its `obstacles`
};

struct RegisteredEffect {
  const char* name;
  EffectFactory make;
  bool pair_contact;  ///< takes the `hessian` override (self contact through pce pairs)
  Coverage coverage;
  /// Whether a mesh has what the effect acts on (its elements; for mesh pairs: whether the
  /// pair of meshes a, b has pairs of its primitives).
  bool (*has)(const MeshRange& a, const MeshRange& b);
  const char* what;  ///< what `has` asks for, for messages ("cloth triangles")
};

const std::vector<RegisteredEffect>& effect_registry();

}  // namespace pce::sim
