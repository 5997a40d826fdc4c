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

/// Throws `InputError(source, "", …)` unless every position is finite, every index is in
/// range, no triangle or segment repeats a vertex, and the mesh has at least one vertex.
void validate(const Mesh& mesh, const std::string& source);

}  // namespace pce::sim
