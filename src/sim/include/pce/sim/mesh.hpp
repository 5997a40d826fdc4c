// SPDX-License-Identifier: MIT
/// @file
/// A simulated mesh: vertex positions, triangles (cloth) and segments (strands), plus the
/// unique edges of the triangles (edge-edge contact, bending). Meshes come from OBJ files
/// (`pce/sim/obj.hpp`) or generators (`pce/sim/generators.hpp`) and are checked once, by
/// `validate`, before anything uses them.
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

/// A triangle mesh (cloth, obstacle surface) and/or a set of segments (strands).
struct Mesh {
  Eigen::Matrix3Xd positions;  ///< one column per vertex
  Eigen::Matrix3Xi triangles;  ///< vertex indices, counter-clockwise seen from the normal's side
  Eigen::Matrix2Xi segments;   ///< strand segments (OBJ `l` elements)

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

/// Throws `InputError(source, "", …)` unless every position is finite with |xᵢ| ≤
/// `kMaxCoordinate`, every index is in range, no triangle or segment repeats a vertex, and
/// the mesh has at least one and at most `kMaxVertices` vertices.
void validate(const Mesh& mesh, const std::string& source);

}  // namespace pce::sim
