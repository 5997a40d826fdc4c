// SPDX-License-Identifier: MIT
/// @file
/// Broad phase: the vertex-face and edge-edge pairs a contact effect must look at. A pair is
/// a candidate when its axis-aligned boxes, grown by the contact distance, overlap — a
/// conservative test: every pair whose true distance is ≤ the contact distance is a
/// candidate (the narrow phase, pce's pair energies, decides the rest). Pairs that share a
/// vertex (a vertex and its own triangle, adjacent edges) are excluded.
///
/// A query may also be over a sweep from positions x0 to x1: each primitive's box is then the
/// box of its vertices at both states, so the candidates cover every pair that comes within
/// the distance anywhere the primitives' vertices stay inside their swept boxes (a contact
/// effect sweeps from the start of a time step to its inertial prediction).
///
/// `brute_force_candidates` tests every pair: O(n²), the reference the accelerated broad
/// phases must reproduce exactly (same sets, same order).
#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

namespace pce::sim {

/// The candidate pairs of one query.
struct Candidates {
  std::vector<std::array<int, 2>> vertex_face;  ///< (vertex, triangle), sorted
  std::vector<std::array<int, 2>> edge_edge;    ///< (edge a, edge b) with a < b, sorted
};

/// Candidates among vertices `x`, `triangles` and `edges` (columns of vertex indices) for a
/// contact distance `distance` ≥ 0: (v, t) when v is not a vertex of t and lies in t's box
/// grown by `distance`; (a, b) when the edges share no vertex and their boxes are at most
/// `distance` apart along every axis.
Candidates brute_force_candidates(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles,
                                  const Eigen::Matrix2Xi& edges, double distance);

/// The same over the sweep from `x0` to `x1` (see the file comment): (v, t) when v's box
/// over both states meets t's grown by `distance`; (a, b) when the edges' boxes over both
/// states are at most `distance` apart along every axis. `x0` and `x1` equal give exactly the
/// pairs of one state. Throws std::invalid_argument when their column counts differ.
Candidates brute_force_candidates(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1,
                                  const Eigen::Matrix3Xi& triangles, const Eigen::Matrix2Xi& edges, double distance);

}  // namespace pce::sim
