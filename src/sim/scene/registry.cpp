// SPDX-License-Identifier: MIT
// The effect registry: each scene effect name and its `load_<name>` factory
// (effect_loaders.cpp, which reads the scene object and calls the public builder
// `make_<name>`, pce/sim/effects.hpp). The scene loader knows the effects only through this
// list.
#include "registry.hpp"

#include "effect_loaders.hpp"

namespace pce::sim {

namespace {

bool any(const MeshRange& /*a*/, const MeshRange& /*b*/) { return true; }
bool cloth(const MeshRange& a, const MeshRange& /*b*/) { return a.triangle_count > 0 && a.tetrahedron_count == 0; }
bool strands(const MeshRange& a, const MeshRange& /*b*/) { return a.segment_count > 0; }
bool volume(const MeshRange& a, const MeshRange& /*b*/) { return a.tetrahedron_count > 0; }
/// Vertices of one against triangles of the other: one of them has triangles.
bool faces(const MeshRange& a, const MeshRange& b) { return a.triangle_count > 0 || b.triangle_count > 0; }

}  // namespace

const std::vector<RegisteredEffect>& effect_registry() {
  static const std::vector<RegisteredEffect> registry = {
      {"gravity", load_gravity, false, Coverage::meshes, any, "vertices"},
      {"stretching", load_stretching, false, Coverage::meshes, cloth, "cloth triangles"},
      {"bending", load_bending, false, Coverage::meshes, cloth, "cloth triangles"},
      {"strand_stretching", load_strand_stretching, false, Coverage::meshes, strands, "segments"},
      {"strand_bending", load_strand_bending, false, Coverage::meshes, strands, "segments"},
      {"pins", load_pins, false, Coverage::none, any, ""},
      {"damping", load_damping, false, Coverage::meshes, any, "vertices"},
      {"self_vertex_face", load_self_vertex_face, true, Coverage::mesh_pairs, faces, "triangles on one side"},
      {"self_edge_edge", load_self_edge_edge, true, Coverage::mesh_pairs, any, "edges"},
      {"obstacle_contact", load_obstacle_contact, false, Coverage::meshes_and_obstacles, any, "vertices"},
      {"volume_elasticity", load_volume_elasticity, false, Coverage::meshes, volume, "tetrahedra"},
  };
  return registry;
}

}  // namespace pce::sim
