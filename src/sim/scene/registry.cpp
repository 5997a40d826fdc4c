// SPDX-License-Identifier: MIT
// The effect registry: scene name → factory. The only place that lists every effect.
#include "registry.hpp"

namespace pce::sim {

std::unique_ptr<Effect> make_gravity(const Params&, const BuildContext&);
std::unique_ptr<Effect> make_stretching(const Params&, const BuildContext&);
std::unique_ptr<Effect> make_bending(const Params&, const BuildContext&);
std::unique_ptr<Effect> make_strand_stretching(const Params&, const BuildContext&);
std::unique_ptr<Effect> make_strand_bending(const Params&, const BuildContext&);
std::unique_ptr<Effect> make_pins(const Params&, const BuildContext&);
std::unique_ptr<Effect> make_damping(const Params&, const BuildContext&);
std::unique_ptr<Effect> make_self_vertex_face(const Params&, const BuildContext&);
std::unique_ptr<Effect> make_self_edge_edge(const Params&, const BuildContext&);
std::unique_ptr<Effect> make_obstacle_contact(const Params&, const BuildContext&);

const std::vector<RegisteredEffect>& effect_registry() {
  static const std::vector<RegisteredEffect> registry = {
      {"gravity", make_gravity, false},
      {"stretching", make_stretching, false},
      {"bending", make_bending, false},
      {"strand_stretching", make_strand_stretching, false},
      {"strand_bending", make_strand_bending, false},
      {"pins", make_pins, false},
      {"damping", make_damping, false},
      {"self_vertex_face", make_self_vertex_face, true},
      {"self_edge_edge", make_self_edge_edge, true},
      {"obstacle_contact", make_obstacle_contact, false},
  };
  return registry;
}

std::vector<std::string> effect_names() {
  std::vector<std::string> names;
  for (const auto& e : effect_registry()) names.emplace_back(e.name);
  return names;
}

}  // namespace pce::sim
