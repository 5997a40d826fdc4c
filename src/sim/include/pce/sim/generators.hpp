// SPDX-License-Identifier: MIT
/// @file
/// Meshes made by `pce::sim` itself: the ones a scene's `generator` names (`grid`, `strands`,
/// `tet_box`, `tet_ball`; `docs/simulation.md` §2.2) and the crumpled cloths the broad-phase tests and benchmark
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

/// A box of tetrahedra centred at the origin, of size `size` (x, y, z in (0, kMaxCoordinate]),
/// with `n` = (nx, ny, nz) cubes per side (each in [1, 256], (nx + 1)(ny + 1)(nz + 1) ≤
/// kMaxVertices), each cube split into six positively oriented tetrahedra around its
/// diagonal from its lowest corner (Kuhn's subdivision, the same in every cube, so conforming
/// between neighbouring cubes). Vertex (i, j, k) has index i + (nx + 1)(j + (ny + 1) k) and
/// position ((i/nx − ½) x, (j/ny − ½) y, (k/nz − ½) z); cube (i, j, k)'s six tetrahedra are
/// 6 (i + nx (j + ny k)) onwards; the triangles are the boundary faces. Invalid arguments are
/// an `InputError`.
Mesh tet_box(const Eigen::Vector3d& size, const Eigen::Vector3i& n);

/// A ball of tetrahedra of radius `radius` (in (0, kMaxCoordinate]) centred at the origin:
/// the lattice of a `tet_box` of 2·`n` cubes per side over [−1, 1]³ (n in [1, 127]), every
/// vertex p moved to radius·p·‖p‖∞/‖p‖₂ (the cube's concentric shells onto spheres), so the
/// boundary vertices lie on the sphere. Unlike `tet_box`, each cube's diagonal runs from its
/// corner nearest the centre to the opposite one (Kuhn's subdivision mirrored across the
/// coordinate planes, still conforming): with one direction for all cubes, the octants whose
/// cubes' diagonals point at the centre get flat tetrahedra (volume / longest edge³ falling
/// as 1/n²); mirrored, it stays above 0.024 (n ≤ 24, a regular tetrahedron: 0.118). Every
/// tetrahedron is positively oriented; the triangles are the boundary faces.
Mesh tet_ball(double radius, int n);

/// A 1 × 1 `grid` of n × n quads (spacing s = 1/n), crumpled: vertex (x, y, 0) moves by
/// (jitter·s·u₁, jitter·s·u₂, 2·jitter·s·u₃ + fold·sin(6πx)·cos(4πy)), u₁, u₂, u₃ drawn in
/// that order from U(−1, 1) by a `std::mt19937_64` seeded with `seed`. Reproducible for a
/// given standard library; many close and crossing triangles, so broad phases see dense
/// and sparse regions at once. `fold`, `jitter` finite and ≥ 0.
Mesh crumpled_grid(int n, unsigned seed, double fold = 0.05, double jitter = 0.4);

}  // namespace pce::sim
