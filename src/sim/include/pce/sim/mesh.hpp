// SPDX-License-Identifier: MIT
/// @file
/// A simulated mesh: vertex positions, triangles (cloth) and segments (strands), or
/// tetrahedra (a volume, whose triangles are then its boundary surface), plus the unique
/// edges of the triangles (edge-edge contact, bending). Meshes come from OBJ files
/// (`pce/sim/obj.hpp`), tetrahedral mesh files (`pce/sim/tet_io.hpp`) or generators
/// (`pce/sim/generators.hpp`) and are checked once, by `validate`, before anything uses them.
#pragma once

#include <Eigen/Core>

#include <string>

namespace pce::sim {

/// Largest |coordinate| and length (m) of anything a scene places: mesh vertices (after the
/// transform), obstacle positions and sizes, generator sizes, contact distances. 1000 km is
/// beyond any simulated object, and keeps double's resolution there (ε·1e6 = 2e-10 m)
/// below any feature one would model, squared distances ≤ 1e13 and a broad phase's boxes
/// grown by a query radius exact to the last place (`validate` checks it).
inline constexpr double kMaxCoordinate = 1e6;

/// Largest number of vertices of one mesh or one model: 2^24, so that vertex, triangle
/// and edge indices (int, 3·n of them) and the 3n unknowns stay far inside `int`, and the
/// counts generators would make are refused before anything is allocated.
inline constexpr long kMaxVertices = 1L << 24;

/// A triangle mesh (cloth, obstacle surface) and/or a set of segments (strands), or a
/// tetrahedral mesh (a volume).
struct Mesh {
  Eigen::Matrix3Xd positions;  ///< one column per vertex
  Eigen::Matrix3Xi triangles;  ///< vertex indices, counter-clockwise seen from the normal's side
  Eigen::Matrix2Xi segments;   ///< strand segments (OBJ `l` elements)
  /// Tetrahedra (a, b, c, d), positively oriented: (b − a)·((c − a) × (d − a)) > 0. A mesh
  /// with tetrahedra is a volume: its `triangles` are then its boundary surface
  /// (`boundary_faces`) and it has no segments.
  Eigen::Matrix4Xi tetrahedra;

  /// Number of vertices (columns of `positions`).
  Eigen::Index vertex_count() const { return positions.cols(); }
};

/// Rigid placement and uniform scale: x ↦ translation + rotation · (scale · x).
struct Transform {
  /// Added last.
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  /// Applied after the scale.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  /// Uniform scale, applied first.
  double scale = 1.0;
};

/// Applies `t` to every vertex.
void apply(const Transform& t, Mesh& mesh);

/// The unique undirected edges of the triangles (each as (i, j) with i < j), sorted.
Eigen::Matrix2Xi unique_edges(const Eigen::Matrix3Xi& triangles);

/// The boundary surface of positively oriented tetrahedra: every face that belongs to one
/// tetrahedron only, oriented counter-clockwise seen from outside (its normal points out of
/// the volume), in the order of the tetrahedra and their faces (b c d, a d c, a b d, a c b).
/// A face shared by two tetrahedra is interior; one shared by more is left out as well
/// (`validate` refuses such meshes).
Eigen::Matrix3Xi boundary_faces(const Eigen::Matrix4Xi& tetrahedra);

/// Throws `InputError(source, "", …)` unless every position is finite with |xᵢ| ≤
/// `kMaxCoordinate`, every index is in range, no triangle or segment repeats a vertex, and
/// the mesh has at least one and at most `kMaxVertices` vertices. For a mesh with tetrahedra
/// also: no segments, every tetrahedron positively oriented with a volume above 1e-12 of
/// its longest edge cubed (the error names the element and its signed volume), no face
/// shared by more than two tetrahedra, and `triangles` equal to `boundary_faces`.
void validate(const Mesh& mesh, const std::string& source);

}  // namespace pce::sim
