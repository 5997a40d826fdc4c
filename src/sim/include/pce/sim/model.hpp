// SPDX-License-Identifier: MIT
/// @file
/// The simulated system: every deformable mesh of a scene concatenated into one set of
/// vertices (the unknowns), with the topology the effects and contacts need and the lumped
/// vertex masses. Kinematic obstacles are not part of it (`pce/sim/obstacle.hpp`).
#pragma once

#include <pce/sim/mesh.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace pce::sim {

struct Obstacle;

/// Where one scene mesh lives inside the model.
struct MeshRange {
  std::string name;      ///< the scene's mesh name
  int first_vertex = 0;  ///< global index of its vertex 0
  /// Number of its vertices.
  int vertex_count = 0;
  /// Global index of its first triangle (column of `Model::triangles`).
  int first_triangle = 0;
  /// Number of its triangles.
  int triangle_count = 0;
  /// Global index of its first segment (column of `Model::segments`).
  int first_segment = 0;
  /// Number of its segments.
  int segment_count = 0;
  /// Global index of its first tetrahedron (column of `Model::tetrahedra`).
  int first_tetrahedron = 0;
  /// Number of its tetrahedra (> 0: a volume, whose triangles are its boundary faces).
  int tetrahedron_count = 0;
};

/// All deformable vertices and elements, in global vertex indices.
struct Model {
  Eigen::Matrix3Xd rest;        ///< rest positions (the scene's frame 0), one column per vertex
  Eigen::Matrix3Xi triangles;   ///< cloth triangles
  Eigen::Matrix2Xi segments;    ///< strand segments
  Eigen::Matrix4Xi tetrahedra;  ///< volume elements, positively oriented
  Eigen::Matrix2Xi edges;       ///< unique triangle edges followed by the strand segments
  Eigen::VectorXd mass;         ///< lumped vertex masses (kg), > 0
  /// Per triangle: 1 for a volume's boundary face (contact sees it, the cloth effects
  /// stretching and bending do not), 0 for cloth; empty: all cloth.
  std::vector<char> boundary_triangle;
  /// Per vertex: 1 if it is a corner of a triangle or an end of a segment (it takes part in
  /// contact), 0 for a vertex inside a volume (contact leaves it out); empty: all 1.
  std::vector<char> surface_vertex;
  /// Where each scene mesh lives, in scene order.
  std::vector<MeshRange> meshes;

  /// Number of deformable vertices (columns of `rest`).
  int vertex_count() const { return static_cast<int>(rest.cols()); }
  /// Whether triangle `t` is a volume's boundary face (`boundary_triangle`).
  bool is_boundary_triangle(Eigen::Index t) const {
    return !boundary_triangle.empty() && boundary_triangle[static_cast<std::size_t>(t)] != 0;
  }
  /// Whether vertex `v` takes part in contact (`surface_vertex`).
  bool is_surface_vertex(Eigen::Index v) const {
    return surface_vertex.empty() || surface_vertex[static_cast<std::size_t>(v)] != 0;
  }
};

/// Densities (areal kg/m², linear kg/m) a model accepts: [1e-9, 1e6]. Graphene, the
/// thinnest sheet there is, weighs 7.6e-7 kg/m²; a metre of osmium 2.3e4 kg/m². The lower
/// bound keeps every vertex mass (and so M/h²) normal and far from 0, so a force the
/// elastic Hessian does not see cannot push a vertex by an overflowing F h²/m.
inline constexpr double kMinDensity = 1e-9;
/// The upper bound of `kMinDensity`'s range.
inline constexpr double kMaxDensity = 1e6;

/// One deformable mesh of a model and its material (a scene's `meshes[k]`).
struct ModelMesh {
  /// Its name (unique in the model; pin groups and errors use it).
  std::string name{};
  /// Positions and elements (checked by `validate`).
  Mesh mesh{};
  /// Density in [1e-9, 1e6]: of the tetrahedra (kg/m³) for a volume, else areal density of
  /// the triangles (kg/m²).
  double density = 0.1;
  double linear_density = 0.005;  ///< linear density of the segments (kg/m), in [1e-9, 1e6]
};

/// The model of `meshes`, concatenated in order: global vertex indices, the unique triangle
/// edges followed by the segments as `edges`, and lumped masses (each tetrahedron of a volume
/// gives each corner density·volume/4; each triangle of a cloth each corner density·area/3;
/// each segment each end linear_density·length/2). Throws
/// `ArgumentError` naming `meshes[k]` (or one of its fields) for an invalid mesh, an empty
/// or duplicate name, a density outside [`kMinDensity`, `kMaxDensity`], more than
/// `kMaxVertices` vertices in all, or a vertex left without mass.
Model build_model(const std::vector<ModelMesh>& meshes);

/// The model as an effect restricted to some of its meshes sees it (scene key `meshes`,
/// docs/simulation.md §2.5): the same vertices, rest positions and mesh ranges, with only the
/// named meshes' triangles, segments, tetrahedra and edges (in the model's order, so that
/// naming every mesh gives the model itself); the other meshes' vertices have mass 0 and take
/// part in no contact (`surface_vertex` 0), and their ranges hold no elements. An effect built
/// on it acts on those meshes only and keeps a pointer to it: it must outlive the effect.
/// Throws `ArgumentError` (`meshes`) for an empty list, an unknown or a repeated name.
Model restrict_to_meshes(const Model& model, const std::vector<std::string>& meshes);

/// Rest areas of a model's elements, for area-weighted contact (docs/simulation.md §4):
/// each triangle's area, and the lumped areas of vertices (a third of every triangle they
/// are a corner of) and edges (a third of every triangle they border). A vertex or edge of
/// strands alone has lumped area 0.
struct RestAreas {
  Eigen::VectorXd vertex;    ///< per vertex (m²)
  Eigen::VectorXd triangle;  ///< per triangle (m²)
  Eigen::VectorXd edge;      ///< per edge, in `Model::edges` order (m²)
};

/// The rest areas of `model` (rest positions; see `RestAreas`).
RestAreas rest_areas(const Model& model);

/// What every effect may read when a time step begins.
struct StepContext {
  int frame = 0;    ///< the frame being computed (1 for the first step)
  double time = 0;  ///< time at the end of the step (s)
  double dt = 0;    ///< step size (s)
  /// The model being simulated.
  const Model* model = nullptr;
  const Eigen::Matrix3Xd* x_start = nullptr;  ///< positions at the start of the step
  const Eigen::Matrix3Xd* v_start = nullptr;  ///< velocities at the start of the step
  /// The simulation's obstacles, whose poses (motions and poses put between steps) an effect
  /// that meets them reads; null when the step has none to tell.
  const std::vector<Obstacle>* obstacles = nullptr;
};

}  // namespace pce::sim
