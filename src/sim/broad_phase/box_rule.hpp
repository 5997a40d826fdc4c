// SPDX-License-Identifier: MIT
/// @file
/// The rule every tree-based broad phase (`fcl.cpp`, `bullet.cpp`) follows to return
/// exactly `brute_force_candidates`'s pairs in its order, written once (internal header,
/// not installed).
///
/// A query is over a sweep from positions x0 to x1 (x1 = x0 for a query at one state): a
/// primitive's box is the box of its vertices at both, min and max taken over the six
/// (vertex-face: two for the vertex) or four points. With x1 = x0 every min and max is of
/// equal numbers, so the boxes, and the pairs, are bit for bit those of the one state.
///
/// The brute force accepts (v, t) when x_v lies in t's box grown by d, and (a, b) when the
/// edges' boxes are at most d apart along every axis, each with its own floating-point
/// expressions (`accept_vertex_face`, `accept_edge_edge` below, which
/// `broad_phase/brute_force.cpp` calls). Two boxes each grown by d/2 overlap under the
/// same *exact* comparison, but not after rounding. So a tree sees boxes grown by
/// h = d/2 + pad, pad = 4 ε (M + d) (M the largest finite |coordinate|, `padding`): the
/// brute force's fl(lo − d) and the tree's fl(x − h), fl(hi + h) each err by at most
/// ½ ulp(M + d) ≤ ε (M + d)/2, so the margin 2·pad = 8 ε (M + d) on the exact comparison
/// covers all three roundings and every brute-force pair overlaps in the tree (a superset).
/// Each pair the tree reports is then re-tested by `accept_vertex_face` /
/// `accept_edge_edge` — the brute force's own expressions, same operations in the same
/// order — which removes the extra pairs, and `sort_pairs` gives the brute force's order.
/// Trees report each leaf pair once (FCL's and Bullet's self-collision visit unordered
/// pairs once), so no deduplication is needed.
#pragma once

#include "util/counting_sort.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace pce::sim::box_rule {

/// The largest M + d (M = max |x_ik|, d the query distance) whose boxes a tree may see:
/// every grown box then lies inside [−2·1e100, 2·1e100]³, so the quantities the trees
/// derive from boxes — FCL's volumes (extent³ ≤ 6.4e301) and centres, Bullet's extent
/// sums — are finite. Beyond it (a distance of 1e308 grew boxes to ±∞, whose NaN volumes
/// sent FCL's bottom-up build out of its array: a segmentation fault) the caller answers
/// with the brute force.
inline constexpr double kTreeLimit = 1e100;

/// pad = 4 ε (M + d), M = max |x_ik|: the margin h − d/2 that makes a tree's overlap test
/// of boxes grown by h = d/2 + pad accept every brute-force pair. Returns false (and leaves
/// `pad` unset) when a coordinate is not finite, or when d is not a number in
/// [0, ∞) with M + d ≤ `kTreeLimit`: neither tree library survives a NaN or infinite box
/// (FCL crashes, Bullet corrupts its heap), so the caller then answers with
/// `brute_force_candidates` itself, whose comparisons reject non-finite pairs and accept
/// every pair within a huge distance.
inline bool padding(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, double distance, double& pad) {
  if (!(distance >= 0 && distance <= kTreeLimit)) return false;  // NaN, negative, huge
  if (x1.cols() != x0.cols()) return false;                      // not a sweep: the brute force refuses it too
  double m = 0;
  for (const Eigen::Matrix3Xd* x : {&x0, &x1})
    for (Eigen::Index k = 0; k < x->size(); ++k) {
      if (!std::isfinite(x->data()[k])) return false;
      m = std::max(m, std::abs(x->data()[k]));
    }
  if (!(m + distance <= kTreeLimit)) return false;
  pad = 4 * std::numeric_limits<double>::epsilon() * (m + distance);
  return true;
}

/// What every tree query starts with: h = d/2 + pad, and whether `topology` differs from
/// the one the trees were built for (then `built_for` takes it). Returns false, and sets
/// nothing, when `padding` does (a coordinate not finite, a distance not in [0, ∞) or
/// coordinates plus distance beyond `kTreeLimit`): the caller answers with
/// `brute_force_candidates` itself.
template <class Matrix> bool begin_query(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, double distance,
                                         const Matrix& topology, Matrix& built_for, double& h, bool& new_topology);

/// The box of vertex v over the sweep: [min(x0_v, x1_v), max(x0_v, x1_v)].
inline void swept_vertex(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, int v, Eigen::Vector3d& lo,
                         Eigen::Vector3d& hi) {
  lo = x0.col(v).cwiseMin(x1.col(v));
  hi = x0.col(v).cwiseMax(x1.col(v));
}

/// The box of triangle t over the sweep: min and max of its corners at x0 and at x1.
inline void swept_triangle(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix3Xi& triangles,
                           int t, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  const Eigen::Vector3i tri = triangles.col(t);
  lo = x0.col(tri[0]).cwiseMin(x0.col(tri[1])).cwiseMin(x0.col(tri[2]));
  hi = x0.col(tri[0]).cwiseMax(x0.col(tri[1])).cwiseMax(x0.col(tri[2]));
  lo = lo.cwiseMin(x1.col(tri[0]).cwiseMin(x1.col(tri[1])).cwiseMin(x1.col(tri[2])));
  hi = hi.cwiseMax(x1.col(tri[0]).cwiseMax(x1.col(tri[1])).cwiseMax(x1.col(tri[2])));
}

/// The box of edge e over the sweep: min and max of its ends at x0 and at x1.
inline void swept_edge(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix2Xi& edges, int e,
                       Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  const int a = edges(0, e), b = edges(1, e);
  lo = x0.col(a).cwiseMin(x0.col(b)).cwiseMin(x1.col(a).cwiseMin(x1.col(b)));
  hi = x0.col(a).cwiseMax(x0.col(b)).cwiseMax(x1.col(a).cwiseMax(x1.col(b)));
}

/// The box a tree stores for vertex v: its swept box grown by h.
inline void vertex_box(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, int v, double h, Eigen::Vector3d& lo,
                       Eigen::Vector3d& hi) {
  swept_vertex(x0, x1, v, lo, hi);
  lo.array() -= h;
  hi.array() += h;
}

/// The box a tree stores for triangle t: its swept box grown by h.
inline void triangle_box(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix3Xi& triangles,
                         int t, double h, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  swept_triangle(x0, x1, triangles, t, lo, hi);
  lo.array() -= h;
  hi.array() += h;
}

/// The box a tree stores for edge e: its swept box grown by h.
inline void edge_box(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix2Xi& edges, int e,
                     double h, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  swept_edge(x0, x1, edges, e, lo, hi);
  lo.array() -= h;
  hi.array() += h;
}

/// The brute force's vertex-face rule for a pair a tree reported: v is not a corner of t
/// and v's swept box meets [min − d, max + d] of t's (at one state: x_v lies in it), with
/// `brute_force_candidates`' operations.
inline bool accept_vertex_face(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1,
                               const Eigen::Matrix3Xi& triangles, int v, int t, double distance) {
  const Eigen::Vector3i tri = triangles.col(t);
  if (tri[0] == v || tri[1] == v || tri[2] == v) return false;
  Eigen::Vector3d lo, hi, vlo, vhi;
  swept_triangle(x0, x1, triangles, t, lo, hi);
  swept_vertex(x0, x1, v, vlo, vhi);
  lo.array() -= distance;
  hi.array() += distance;
  return (vhi.array() >= lo.array()).all() && (vlo.array() <= hi.array()).all();
}

/// The brute force's edge-edge rule for a pair a tree reported (i < j): the edges share no
/// vertex and their swept boxes have blo − ahi ≤ d, alo − bhi ≤ d on every axis, with the
/// brute force's operations.
inline bool accept_edge_edge(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix2Xi& edges,
                             int i, int j, double distance) {
  const int a0 = edges(0, i), a1 = edges(1, i), b0 = edges(0, j), b1 = edges(1, j);
  if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) return false;
  Eigen::Vector3d alo, ahi, blo, bhi;
  swept_edge(x0, x1, edges, i, alo, ahi);
  swept_edge(x0, x1, edges, j, blo, bhi);
  return ((blo - ahi).array() <= distance).all() && ((alo - bhi).array() <= distance).all();
}

/// Sorts pairs lexicographically (first index in [0, n), second ≥ 0): a counting sort on
/// the second index, then a stable counting sort on the first (least significant digit
/// first). Linear in the pair count where `std::sort` of a million pairs costs tens of
/// milliseconds (and sorting each first index's bucket of a few dozen pairs cost 4 % of a
/// single-solve hammock frame). `scratch` and `start` are buffers the caller keeps between
/// queries.
inline void sort_pairs(std::vector<std::array<int, 2>>& pairs, int n, std::vector<std::array<int, 2>>& scratch,
                       std::vector<int>& start) {
  int m = 0;
  for (const auto& p : pairs) m = std::max(m, p[1] + 1);
  scratch.resize(pairs.size());
  // By the second index into scratch, then stably by the first back into pairs.
  counting_pass(
      pairs, scratch, static_cast<std::size_t>(m), [](const std::array<int, 2>& p) { return p[1]; }, start);
  counting_pass(
      scratch, pairs, static_cast<std::size_t>(n), [](const std::array<int, 2>& p) { return p[0]; }, start);
}

/// True when two index matrices are equal (same column count and entries): the topology
/// test that decides between refitting a tree and rebuilding it.
template <class Matrix> bool same_topology(const Matrix& a, const Matrix& b) {
  return a.cols() == b.cols() && (a.array() == b.array()).all();
}

template <class Matrix> bool begin_query(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, double distance,
                                         const Matrix& topology, Matrix& built_for, double& h, bool& new_topology) {
  double pad = 0;
  if (!padding(x0, x1, distance, pad)) return false;
  new_topology = !same_topology(topology, built_for);
  if (new_topology) built_for = topology;
  h = distance / 2 + pad;
  return true;
}

}  // namespace pce::sim::box_rule
