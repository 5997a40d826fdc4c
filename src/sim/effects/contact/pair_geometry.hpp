// SPDX-License-Identifier: MIT
/// @file
/// Cheap geometry of one self-contact pair (internal): its vertices and coordinates, lower
/// bounds on the distance between its two primitives, and the plane-mode tests. Vertex-face
/// pairs are (vertex, triangle), edge-edge pairs (edge a, edge b); the 12 coordinates are
/// p, t0, t1, t2 resp. ea0, ea1, eb0, eb1 (docs/conventions.md).
#pragma once

#include <pce/core/types.hpp>
#include <pce/frames/frame.hpp>
#include <pce/sim/model.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>

namespace pce::sim::contact {

/// Edges nearer parallel than asin(0.05) ≈ 2.9° have no plane-mode energy: their line
/// distance and its closest points are ill-conditioned and the frame's normal flips without
/// any crossing.
inline constexpr double kParallelSin2 = 0.05 * 0.05;

template <bool VF> struct PairGeometry {
  /// Vertices of the first primitive (1: the vertex; 2: edge a) among the pair's four.
  static constexpr int first_side_count() { return VF ? 1 : 2; }

  /// The pair's four vertex indices in the order of its 12 coordinates.
  static std::array<int, 4> vertices(const Model& model, const std::array<int, 2>& c) {
    if constexpr (VF) {
      const auto t = model.triangles.col(c[1]);
      return {c[0], t[0], t[1], t[2]};
    } else {
      const auto a = model.edges.col(c[0]), b = model.edges.col(c[1]);
      return {a[0], a[1], b[0], b[1]};
    }
  }

  /// The pair's 12 coordinates at positions `x`.
  static Vec12<double> gather(const Eigen::Matrix3Xd& x, const std::array<int, 4>& v) {
    Vec12<double> xp;
    for (int j = 0; j < 4; ++j) xp.segment<3>(3 * j) = x.col(v[static_cast<std::size_t>(j)]);
    return xp;
  }

  /// A lower bound on the distance between the pair's two primitives: the distance between
  /// their axis-aligned boxes (each primitive lies in its box). A few comparisons, against
  /// a frame or a closest-feature evaluation.
  static double box_gap(const Vec12<double>& xp) {
    constexpr int na = first_side_count();
    Eigen::Vector3d alo = xp.segment<3>(0), ahi = alo, blo = xp.segment<3>(3 * na), bhi = blo;
    for (int j = 1; j < na; ++j) {
      alo = alo.cwiseMin(xp.segment<3>(3 * j));
      ahi = ahi.cwiseMax(xp.segment<3>(3 * j));
    }
    for (int j = na + 1; j < 4; ++j) {
      blo = blo.cwiseMin(xp.segment<3>(3 * j));
      bhi = bhi.cwiseMax(xp.segment<3>(3 * j));
    }
    return (blo - ahi).cwiseMax(alo - bhi).cwiseMax(0.0).norm();
  }

  /// A lower bound on the distance between the pair's primitives: the larger of the box gap
  /// and the gap between their bounding spheres (centred at the mean of the primitive's
  /// vertices, radius the farthest of them). The spheres are the sharper bound for
  /// neighbours of one sheet, whose boxes overlap.
  static double distance_lower_bound(const Vec12<double>& xp) {
    constexpr int na = first_side_count();
    Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
    for (int j = 0; j < 4; ++j) (j < na ? ca : cb) += xp.segment<3>(3 * j);
    ca /= na;
    cb /= 4 - na;
    double ra = 0, rb = 0;
    for (int j = 0; j < 4; ++j) {
      double& r = j < na ? ra : rb;
      r = std::max(r, (xp.segment<3>(3 * j) - (j < na ? ca : cb)).norm());
    }
    // (1 − 1e-12): the rounding of the norms must not lift the bound above the distance.
    return std::max(box_gap(xp), ((ca - cb).norm() - ra - rb) * (1 - 1e-12));
  }

  /// Plane mode: the closest points of the plane (line) distance lie inside the triangle
  /// (both segments).
  static bool inside(const Frame<double>& f) {
    if constexpr (VF)
      return f.beta >= 0 && f.gamma >= 0 && f.beta + f.gamma <= 1;
    else
      return f.beta >= 0 && f.beta <= 1 && f.gamma <= 0 && f.gamma >= -1;
  }

  /// A necessary condition for plane-mode activity within `reach`, in a few dozen flops
  /// instead of a frame: the plane (line) distance |l| is at most `reach`, the foot of the
  /// vertex lies in the triangle (the closest points of the lines in both segments) and, for
  /// edges, they are not nearer parallel than kParallelSin2 allows — each with a relative
  /// slack of 1e-6 (parameters) or 1 % (the parallel test), far beyond the rounding of either
  /// computation, so it never rejects a pair the frame would accept.
  static bool may_be_plane_active(const Vec12<double>& xp, double reach) {
    constexpr double slack = 1e-6;
    if constexpr (VF) {
      const Eigen::Vector3d p = xp.segment<3>(0), a = xp.segment<3>(3), b = xp.segment<3>(6), c = xp.segment<3>(9);
      const Eigen::Vector3d n = (b - a).cross(c - a);
      const double nn = n.squaredNorm(), s = (p - a).dot(n);
      if (!(s * s <= reach * reach * nn * (1 + slack))) return false;
      // Unnormalised barycentric coordinates of the foot of p (each nn at its own corner).
      const double tol = -slack * nn;
      return (c - b).cross(p - b).dot(n) >= tol && (a - c).cross(p - c).dot(n) >= tol &&
             (b - a).cross(p - a).dot(n) >= tol;
    } else {
      const Eigen::Vector3d a0 = xp.segment<3>(0), e0 = xp.segment<3>(3) - a0, b0 = xp.segment<3>(6),
                            e1 = xp.segment<3>(9) - b0, w = b0 - a0;
      const Eigen::Vector3d m = e0.cross(e1);
      const double mm = m.squaredNorm();
      if (!(mm >= 0.99 * kParallelSin2 * e0.squaredNorm() * e1.squaredNorm()) || !(mm > 0)) return false;
      const double s = w.dot(m);
      if (!(s * s <= reach * reach * mm * (1 + slack))) return false;
      // Closest points of the lines: a0 + u e0 and b0 + v e1, u = ((w × e1)·m)/|m|²,
      // v = ((w × e0)·m)/|m|².
      const double u = w.cross(e1).dot(m), v = w.cross(e0).dot(m), tol = slack * mm;
      return u >= -tol && u <= mm + tol && v >= -tol && v <= mm + tol;
    }
  }

  /// Edge-edge plane mode only: the edges are at least ~2.9° from parallel (kParallelSin2).
  static bool well_conditioned(const Vec12<double>& xp) {
    if constexpr (VF) {
      return true;
    } else {
      const Eigen::Vector3d e0 = xp.segment<3>(3) - xp.segment<3>(0), e1 = xp.segment<3>(9) - xp.segment<3>(6);
      return !(e0.cross(e1).squaredNorm() < kParallelSin2 * e0.squaredNorm() * e1.squaredNorm());
    }
  }
};

}  // namespace pce::sim::contact
