// SPDX-License-Identifier: MIT
// The effect registry: each scene effect name and its `load_<name>` factory
// (effect_loaders.cpp, which reads the scene object and calls the public builder
// `make_<name>`, pce/sim/effects.hpp). The scene loader knows the effects only through this
// list.
#include "registry.hpp"

#include "effect_loaders.hpp"

namespace pce::sim {

const std::vector<RegisteredEffect>& effect_registry() {
  static const std::vector<RegisteredEffect> registry = {
      {"gravity", load_gravity, false},
      {"stretching", load_stretching, false},
      {"bending", load_bending, false},
      {"strand_stretching", load_strand_stretching, false},
      {"strand_bending", load_strand_bending, false},
      {"pins", load_pins, false},
      {"damping", load_damping, false},
      {"self_vertex_face", load_self_vertex_face, true},
      {"self_edge_edge", load_self_edge_edge, true},
      {"obstacle_contact", load_obstacle_contact, false},
      {"volume_elasticity", load_volume_elasticity, false},
  };
  return registry;
}

}  // namespace pce::sim
