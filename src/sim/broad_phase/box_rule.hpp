// SPDX-License-Identifier: MIT
/// @file
/// The rule every tree-based broad phase (`fcl.cpp`, `bullet.cpp`) follows to return
/// exactly `brute_force_candidates`'s pairs in its order, written once (internal header,
/// not installed).
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
inline bool padding(const Eigen::Matrix3Xd& x, double distance, double& pad) {
  if (!(distance >= 0 && distance <= kTreeLimit)) return false;  // NaN, negative, huge
  double m = 0;
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    if (!std::isfinite(x.data()[k])) return false;
    m = std::max(m, std::abs(x.data()[k]));
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
template <class Matrix> bool begin_query(const Eigen::Matrix3Xd& x, double distance, const Matrix& topology,
                                         Matrix& built_for, double& h, bool& new_topology);

/// The box a tree stores for vertex v: [x_v − h, x_v + h].
inline void vertex_box(const Eigen::Matrix3Xd& x, int v, double h, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo = x.col(v).array() - h;
  hi = x.col(v).array() + h;
}

/// The box a tree stores for triangle t: [min(a, b, c) − h, max(a, b, c) + h], the corners
/// taken in the brute force's order.
inline void triangle_box(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles, int t, double h,
                         Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  const Eigen::Vector3d a = x.col(triangles(0, t)), b = x.col(triangles(1, t)), c = x.col(triangles(2, t));
  lo = a.cwiseMin(b).cwiseMin(c).array() - h;
  hi = a.cwiseMax(b).cwiseMax(c).array() + h;
}

/// The box a tree stores for edge e: [min(a, b) − h, max(a, b) + h].
inline void edge_box(const Eigen::Matrix3Xd& x, const Eigen::Matrix2Xi& edges, int e, double h, Eigen::Vector3d& lo,
                     Eigen::Vector3d& hi) {
  const Eigen::Vector3d a = x.col(edges(0, e)), b = x.col(edges(1, e));
  lo = a.cwiseMin(b).array() - h;
  hi = a.cwiseMax(b).array() + h;
}

/// The brute force's vertex-face rule for a pair a tree reported: v is not a corner of t
/// and x_v ∈ [min − d, max + d] of t's corners, with `brute_force_candidates`' operations.
inline bool accept_vertex_face(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles, int v, int t,
                               double distance) {
  const Eigen::Vector3i tri = triangles.col(t);
  if (tri[0] == v || tri[1] == v || tri[2] == v) return false;
  const Eigen::Vector3d lo = x.col(tri[0]).cwiseMin(x.col(tri[1])).cwiseMin(x.col(tri[2])).array() - distance;
  const Eigen::Vector3d hi = x.col(tri[0]).cwiseMax(x.col(tri[1])).cwiseMax(x.col(tri[2])).array() + distance;
  return (x.col(v).array() >= lo.array()).all() && (x.col(v).array() <= hi.array()).all();
}

/// The brute force's edge-edge rule for a pair a tree reported (i < j): the edges share no
/// vertex and blo − ahi ≤ d, alo − bhi ≤ d on every axis, with the brute force's operations.
inline bool accept_edge_edge(const Eigen::Matrix3Xd& x, const Eigen::Matrix2Xi& edges, int i, int j, double distance) {
  const int a0 = edges(0, i), a1 = edges(1, i), b0 = edges(0, j), b1 = edges(1, j);
  if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) return false;
  const Eigen::Vector3d alo = x.col(a0).cwiseMin(x.col(a1)), ahi = x.col(a0).cwiseMax(x.col(a1));
  const Eigen::Vector3d blo = x.col(b0).cwiseMin(x.col(b1)), bhi = x.col(b0).cwiseMax(x.col(b1));
  return ((blo - ahi).array() <= distance).all() && ((alo - bhi).array() <= distance).all();
}

/// Sorts pairs lexicographically (first index in [0, n)): a counting sort on the first
/// index, then each bucket — a few dozen pairs — by the second. Linear in the pair count
/// where `std::sort` of a million pairs costs tens of milliseconds. `scratch` and `start`
/// are buffers the caller keeps between queries.
inline void sort_pairs(std::vector<std::array<int, 2>>& pairs, int n, std::vector<std::array<int, 2>>& scratch,
                       std::vector<int>& start) {
  start.assign(static_cast<std::size_t>(n) + 1, 0);
  for (const auto& p : pairs) ++start[static_cast<std::size_t>(p[0]) + 1];
  for (int i = 0; i < n; ++i) start[static_cast<std::size_t>(i) + 1] += start[static_cast<std::size_t>(i)];
  scratch.resize(pairs.size());
  for (const auto& p : pairs) scratch[static_cast<std::size_t>(start[static_cast<std::size_t>(p[0])]++)] = p;
  // start[i] is now the end of bucket i (the beginning of bucket i + 1).
  auto first = scratch.begin();
  for (int i = 0; i < n; ++i) {
    const auto last = scratch.begin() + start[static_cast<std::size_t>(i)];
    if (last - first > 1) std::sort(first, last);
    first = last;
  }
  pairs.swap(scratch);
}

/// True when two index matrices are equal (same column count and entries): the topology
/// test that decides between refitting a tree and rebuilding it.
template <class Matrix> bool same_topology(const Matrix& a, const Matrix& b) {
  return a.cols() == b.cols() && (a.array() == b.array()).all();
}

template <class Matrix> bool begin_query(const Eigen::Matrix3Xd& x, double distance, const Matrix& topology,
                                         Matrix& built_for, double& h, bool& new_topology) {
  double pad = 0;
  if (!padding(x, distance, pad)) return false;
  new_topology = !same_topology(topology, built_for);
  if (new_topology) built_for = topology;
  h = distance / 2 + pad;
  return true;
}

}  // namespace pce::sim::box_rule
