// SPDX-License-Identifier: MIT
/// @file
/// What pins.cpp shares beyond its public builders (`make_pins`, `vertices_in_box`): the
/// lookup of a model mesh by name, which the pins' scene loader uses to resolve a group's
/// `mesh`. Internal.
#pragma once

#include <pce/sim/model.hpp>

#include <string>

namespace pce::sim {

/// The model mesh named `name`, or null.
const MeshRange* find_mesh(const Model& model, const std::string& name);

}  // namespace pce::sim
