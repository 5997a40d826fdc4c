// SPDX-License-Identifier: MIT
/// @file
/// Tetrahedral mesh files for `pce::sim` volumes (`docs/simulation.md` §2.2): Gmsh `.msh`
/// (ASCII, format versions 2.x, 4.0 and 4.1), TetGen `.node`/`.ele`, and a plain text form
/// `.tet`.
///
/// - `.msh`: `$MeshFormat` first, then `$Nodes` and `$Elements` (in that order), one node,
///   node tag or element per line as Gmsh writes them; other sections (`$PhysicalNames`,
///   `$Entities`, `$NodeData`, …) are skipped. Element type 4 (4-node tetrahedron) is read,
///   and every other element type (points, lines, triangles, …) is skipped. Node tags may be
///   any positive integers (sparse, unordered); vertices are numbered in the order of the
///   file's nodes, and nodes no tetrahedron uses are dropped. Binary files are an error.
/// - `.ele` (with the `.node` of the same stem beside it): `.node` lists `index x y z
///   [attributes] [boundary marker]`, `.ele` lists `index a b c d [attributes]`, with
///   indices from 0 or from 1 as the `.node` file's first index says (points numbered
///   consecutively); 10-node tetrahedra give their four corners; `#` starts a comment. Every
///   point is a vertex, in order.
/// - `.tet`: `v x y z` lines (vertices, numbered from 1 in order) and `t a b c d` lines
///   (tetrahedra, 1-based vertex numbers); `#` starts a comment, blank lines are skipped.
///
/// Every tetrahedron is turned positive: one whose signed volume is negative has two
/// vertices swapped (c, d), as Gmsh and TetGen meshes may use either orientation. One that
/// repeats a vertex or is flat (by `validate`'s measure) is an error at its line, naming it
/// `tetrahedron k` (its column in `tetrahedra`). Counts a file declares beyond `kMaxVertices`
/// nodes (8 · `kMaxVertices` elements) are refused before anything is allocated. The
/// boundary surface is extracted once (`boundary_faces`). Every malformed line is an
/// `InputError` naming the file and the line; the result is checked by `validate`.
#pragma once

#include <pce/sim/mesh.hpp>

#include <filesystem>

namespace pce::sim {

/// True for the extensions `read_tet_mesh` reads: `.msh`, `.ele`, `.node`, `.tet`.
bool is_tet_mesh_file(const std::filesystem::path& path);

/// Reads a tetrahedral mesh by its extension (`.msh`, `.ele` or `.node` for TetGen's pair,
/// `.tet`; any case), orients every tetrahedron positively, sets `triangles` to the boundary
/// faces, `segments` to none, and validates the mesh (TetGen's as its `.ele` file). Throws
/// `InputError` naming the file (and line) on a missing file, a file without tetrahedra or
/// anything malformed.
Mesh read_tet_mesh(const std::filesystem::path& path);

/// Writes `mesh`'s positions and tetrahedra as `.tet` (17 significant digits: a read gives
/// back the same doubles and tetrahedra). Throws `InputError` if the file cannot be written.
void write_tet(const std::filesystem::path& path, const Mesh& mesh);

}  // namespace pce::sim
