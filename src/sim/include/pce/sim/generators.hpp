// SPDX-License-Identifier: MIT
/// @file
/// Meshes made by `pce::sim` itself, for scenes that do not load OBJ files (contract §2:
/// "a rectangular cloth grid of given resolution, a bundle of straight or curly strands").
#pragma once

#include <pce/sim/mesh.hpp>

namespace pce::sim {

/// A `width` × `height` rectangle in the z = 0 plane, centred at the origin, with
/// `nx` × `ny` quads (nx, ny ≥ 1) each split into two triangles along alternating
/// diagonals (no preferred shear direction); normals along +z. Vertex (i, j) has index
/// `j (nx + 1) + i` and position ((i/nx − ½) width, (j/ny − ½) height, 0).
Mesh grid(double width, double height, int nx, int ny);

/// `count` strands of `segments` segments each, hanging along −z from the points of a
/// square lattice of spacing `spacing` in the z = 0 plane, each of length `length`.
/// `curl` > 0 winds each strand into a helix of that radius (one turn per `length / 2`),
/// with a phase that differs from strand to strand. Strand k's vertices are consecutive,
/// starting at index k (segments + 1).
Mesh strands(int count, int segments, double length, double spacing, double curl = 0.0);

}  // namespace pce::sim
