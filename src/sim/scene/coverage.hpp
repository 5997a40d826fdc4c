// SPDX-License-Identifier: MIT
/// @file
/// What each effect entry covers, and the checks between the entries of one type
/// (coverage.cpp, docs/simulation.md §2.5): an entry's `meshes` (names, or for self contact
/// pairs of names) and an obstacle_contact entry's `obstacles` are read against the model
/// and the obstacles, and the entries of one type must neither overlap nor leave a gap, nor
/// name a mesh without what the type acts on. The scene loader reads and checks all of this
/// from the parsed entries before it builds the first effect. Internal.
#pragma once

#include "params.hpp"
#include "registry.hpp"

#include <pce/sim/model.hpp>
#include <pce/sim/obstacle.hpp>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace pce::sim {

/// An entry's `meshes`, read: the mesh indices it names (sorted), or its pairs (a ≤ b).
struct MeshSelection {
  bool given = false;                     ///< the entry has `meshes`
  std::vector<int> meshes;                ///< named meshes (the union of its pairs when pairs)
  std::vector<std::array<int, 2>> pairs;  ///< named pairs, when given as pairs
};

/// Reads entry `p`'s `meshes` against `model`: a non-empty list of mesh names, or with
/// `pairs_allowed` (self contact) of pairs of names. An unknown name, a mesh or pair named
/// twice, or a pair where names are expected is an error at its JSON path.
MeshSelection read_meshes(const Params& p, const Model& model, bool pairs_allowed);

/// One effect entry as read before anything is built: its registered type, its `meshes`
/// and, for obstacle_contact, the obstacles it lists (`listed_obstacles`).
struct EffectEntry {
  std::size_t index = 0;  ///< k of `effects[k]`
  const RegisteredEffect* type = nullptr;
  MeshSelection meshes;        ///< not given for a type without coverage (pins)
  std::vector<int> obstacles;  ///< indices into the scene's obstacles
};

/// Throws for the first entry, type by type (in the order of their first entries), that
/// overlaps another of its type (a mesh, mesh pair or mesh and obstacle in both), names a
/// mesh or pair without what its type acts on, or leaves a gap (a mesh, or mesh pair, with
/// it in no entry; for obstacle contact a mesh in no entry). Errors name the entry
/// (`effects[k].meshes`, or `effects[k]` without the key) and the other entries involved.
void check_coverage(const std::vector<EffectEntry>& entries, const std::string& file, const Model& model,
                    const std::vector<Obstacle>& obstacles);

}  // namespace pce::sim
