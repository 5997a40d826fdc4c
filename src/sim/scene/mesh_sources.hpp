// SPDX-License-Identifier: MIT
/// @file
/// The scene's meshes and where they come from (mesh_sources.cpp): a mesh file (OBJ or a
/// tetrahedral mesh), a generator, or vertices and elements written in the scene; a `meshes`
/// entry is one of them with its transform and densities. Internal.
#pragma once

#include "params.hpp"

#include <pce/sim/mesh.hpp>
#include <pce/sim/model.hpp>

#include <filesystem>
#include <string>

namespace pce::sim {

/// The mesh file at `key` (a path relative to `base`, the scene's directory), read as a
/// tetrahedral mesh or an OBJ by its name; errors name the scene field and the mesh file.
Mesh read_mesh_file(const Params& p, const std::string& key, const std::filesystem::path& base);

/// A `meshes` entry: its `name`, exactly one source (`file`, `generator` or `vertices` with
/// its elements), its `transform`, then the mesh checked by `validate`, and its densities.
ModelMesh parse_mesh(const Params& p, const std::filesystem::path& base);

}  // namespace pce::sim
