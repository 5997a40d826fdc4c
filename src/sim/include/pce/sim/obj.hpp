// SPDX-License-Identifier: MIT
/// @file
/// Wavefront OBJ reading and writing for `pce::sim`: triangles from `f` elements, strands
/// from `l` polyline elements (`docs/simulation.md` §2.2).
///
/// Read: `v x y z [w]` (w ignored), `f` with any of the `i`, `i/t`, `i//n`, `i/t/n` forms
/// and negative (relative) indices; polygons with more than three vertices are split into a
/// fan from their first vertex (exact for the convex planar polygons OBJ exporters write);
/// `l i j k …` becomes segments (i, j), (j, k), …. Other elements (`vt`, `vn`, `o`, `g`,
/// `s`, `usemtl`, `mtllib`, comments) are skipped. Every malformed line is an `InputError`
/// naming the file and the line.
#pragma once

#include <pce/sim/mesh.hpp>

#include <filesystem>

namespace pce::sim {

/// Reads and validates a mesh; throws `InputError` on a missing file or any malformed line.
Mesh read_obj(const std::filesystem::path& path);

/// Writes positions, triangles and segments (17 significant digits: a read gives back the
/// same doubles). Throws `InputError` if the file cannot be written.
void write_obj(const std::filesystem::path& path, const Mesh& mesh);

}  // namespace pce::sim
