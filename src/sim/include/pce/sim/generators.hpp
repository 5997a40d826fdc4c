// SPDX-License-Identifier: MIT
/// @file
/// Meshes made by `pce::sim` itself: the two a scene's `generator` names (`grid`, `strands`;
/// `docs/simulation.md` §2.2) and the crumpled cloths the broad-phase tests and benchmark
/// share (`crumpled_grid`, C++ only).
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

/// A 1 × 1 `grid` of n × n quads (spacing s = 1/n), crumpled: vertex (x, y, 0) moves by
/// (jitter·s·u₁, jitter·s·u₂, 2·jitter·s·u₃ + fold·sin(6πx)·cos(4πy)), u₁, u₂, u₃ drawn in
/// that order from U(−1, 1) by a `std::mt19937_64` seeded with `seed`. Reproducible for a
/// given standard library; many close and crossing triangles, so broad phases see dense
/// and sparse regions at once. `fold`, `jitter` finite and ≥ 0.
Mesh crumpled_grid(int n, unsigned seed, double fold = 0.05, double jitter = 0.4);

}  // namespace pce::sim
