// SPDX-License-Identifier: MIT
// Exact intersecting-pair counts (pce/sim/intersections.hpp): CGAL's box intersection
// proposes the pairs whose closed bounding boxes meet, CGAL's exact predicates decide them.
// The only translation unit of pce::sim that includes CGAL.
#include <pce/sim/intersections.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace pce::sim {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;

/// The convex hull of a triangle's three points: a triangle (dimension 2), a segment between
/// the extreme points of three collinear ones (1), a point (0), or nothing (-1: a
/// non-finite coordinate).
struct Hull {
  int dimension = -1;
  Point p[3];
};

Hull hull(const Point& a, const Point& b, const Point& c) {
  Hull h;
  if (!CGAL::collinear(a, b, c)) {
    h.dimension = 2;
    h.p[0] = a, h.p[1] = b, h.p[2] = c;
    return h;
  }
  // On a line the lexicographic (x, y, z) order is the order along the line.
  h.p[0] = std::min({a, b, c});
  h.p[1] = std::max({a, b, c});
  h.dimension = h.p[0] == h.p[1] ? 0 : 1;
  return h;
}

Triangle triangle(const Hull& h) { return Triangle(h.p[0], h.p[1], h.p[2]); }
Segment segment(const Hull& h) { return Segment(h.p[0], h.p[1]); }

/// Closed hulls `s` and `t` share a point (both of dimension ≥ 0).
bool meet(const Hull& s, const Hull& t) {
  if (s.dimension < t.dimension) return meet(t, s);
  switch (s.dimension * 3 + t.dimension) {
    case 2 * 3 + 2:
      return CGAL::do_intersect(triangle(s), triangle(t));
    case 2 * 3 + 1:
      return CGAL::do_intersect(triangle(s), segment(t));
    case 2 * 3 + 0:
      return CGAL::do_intersect(triangle(s), t.p[0]);
    case 1 * 3 + 1:
      return CGAL::do_intersect(segment(s), segment(t));
    case 1 * 3 + 0:
      return CGAL::do_intersect(segment(s), t.p[0]);
    default:
      return s.p[0] == t.p[0];
  }
}

/// The neighbour rule of the header for triangles with vertex indices `a`, `b`, their points
/// `pa`, `pb` (in index order) and hulls `ha`, `hb` (both of dimension ≥ 0).
bool meet(const Eigen::Vector3i& a, const Eigen::Vector3i& b, const Point* pa, const Point* pb, const Hull& ha,
          const Hull& hb) {
  // in_b[k]: a's vertex k is one of b's; in_a likewise.
  bool in_b[3], in_a[3];
  int shared = 0;
  for (int k = 0; k < 3; ++k) {
    in_b[k] = a[k] == b[0] || a[k] == b[1] || a[k] == b[2];
    in_a[k] = b[k] == a[0] || b[k] == a[1] || b[k] == a[2];
    shared += in_b[k];
  }
  if (shared == 0) return meet(ha, hb);
  if (ha.dimension < 2 || hb.dimension < 2 || shared >= 3) return false;
  // Positions in a of its vertices not in b (first), then of the shared ones; b likewise.
  int ka[3], kb[3];
  for (int k = 0, front = 0, back = 2; k < 3; ++k) (in_b[k] ? ka[back--] : ka[front++]) = k;
  for (int k = 0, front = 0, back = 2; k < 3; ++k) (in_a[k] ? kb[back--] : kb[front++]) = k;
  if (shared == 2) {
    // Shared edge pq, opposite vertices c and d.
    const Point &c = pa[ka[0]], &d = pb[kb[0]], &p = pa[ka[1]], &q = pa[ka[2]];
    return CGAL::orientation(p, q, c, d) == CGAL::COPLANAR && CGAL::coplanar_orientation(p, q, c, d) == CGAL::POSITIVE;
  }
  // Shared vertex v. If one triangle's other two vertices lie strictly on one side of the
  // other's plane, it meets that plane only at v (two orientations decide most pairs).
  const Point &v = pa[ka[2]], &b1 = pa[ka[0]], &c1 = pa[ka[1]], &e2 = pb[kb[0]], &f2 = pb[kb[1]];
  const CGAL::Orientation e_side = CGAL::orientation(v, b1, c1, e2);
  if (e_side != CGAL::COPLANAR && CGAL::orientation(v, b1, c1, f2) == e_side) return false;
  const CGAL::Orientation b_side = CGAL::orientation(v, e2, f2, b1);
  if (b_side != CGAL::COPLANAR && CGAL::orientation(v, e2, f2, c1) == b_side) return false;
  // Otherwise: either opposite edge meets the other triangle.
  return CGAL::do_intersect(Segment(pa[ka[0]], pa[ka[1]]), triangle(hb)) ||
         CGAL::do_intersect(Segment(pb[kb[0]], pb[kb[1]]), triangle(ha));
}

Point point(const Eigen::Matrix3Xd& x, Eigen::Index i) { return Point(x(0, i), x(1, i), x(2, i)); }

std::vector<Point> points(const Eigen::Matrix3Xd& x) {
  std::vector<Point> p(static_cast<std::size_t>(x.cols()));
  for (Eigen::Index i = 0; i < x.cols(); ++i) p[static_cast<std::size_t>(i)] = point(x, i);
  return p;
}

void check_indices(const Eigen::Matrix3Xi& triangles, Eigen::Index vertex_count, const char* what) {
  if (triangles.size() > 0 && (triangles.minCoeff() < 0 || triangles.maxCoeff() >= vertex_count))
    throw std::invalid_argument(std::string("intersecting_triangle_pairs: ") + what + " index out of range [0, " +
                                std::to_string(vertex_count) + ")");
}

/// The points of triangle `t`, in index order.
struct Corners {
  Point p[3];
};

Corners corners(const std::vector<Point>& p, const Eigen::Matrix3Xi& triangles, Eigen::Index t) {
  Corners c;
  for (int k = 0; k < 3; ++k) c.p[k] = p[static_cast<std::size_t>(triangles(k, t))];
  return c;
}

bool finite(const Eigen::Matrix3Xd& x, const Eigen::Vector3i& t) {
  return x.col(t[0]).allFinite() && x.col(t[1]).allFinite() && x.col(t[2]).allFinite();
}

/// Hulls of every triangle (dimension -1 where a coordinate is not finite).
std::vector<Hull> hulls(const Eigen::Matrix3Xd& x, const std::vector<Point>& p, const Eigen::Matrix3Xi& triangles) {
  std::vector<Hull> h(static_cast<std::size_t>(triangles.cols()));
  for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
    if (!finite(x, triangles.col(t))) continue;
    const Corners c = corners(p, triangles, t);
    h[static_cast<std::size_t>(t)] = hull(c.p[0], c.p[1], c.p[2]);
  }
  return h;
}

/// Below this many boxes the box intersection scans instead of recursing (CGAL's default is
/// 10; 200 measured 25-30 % faster on a crumpled 100 x 100 grid).
constexpr std::ptrdiff_t box_cutoff = 200;

/// A closed box around one triangle; `id` must be unique among the boxes compared.
struct Box : CGAL::Box_intersection_d::Box_d<double, 3, CGAL::Box_intersection_d::ID_NONE> {
  using Base = CGAL::Box_intersection_d::Box_d<double, 3, CGAL::Box_intersection_d::ID_NONE>;
  Box(const CGAL::Bbox_3& b, int index, std::size_t id) : Base(b), index(index), id_(id) {}
  std::size_t id() const { return id_; }
  int index;
  std::size_t id_;
};

/// Boxes of the triangles with a hull, ids starting at `first_id`. Double coordinates are
/// stored exactly, so every box holds its triangle.
std::vector<Box> boxes(const std::vector<Hull>& h, std::size_t first_id) {
  std::vector<Box> b;
  b.reserve(h.size());
  for (std::size_t t = 0; t < h.size(); ++t) {
    if (h[t].dimension < 0) continue;
    CGAL::Bbox_3 box = h[t].p[0].bbox();
    for (int k = 1; k <= h[t].dimension; ++k) box += h[t].p[k].bbox();
    b.emplace_back(box, static_cast<int>(t), first_id + t);
  }
  return b;
}

}  // namespace

bool triangles_intersect(const Eigen::Matrix3Xd& x, const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
  if (!finite(x, a) || !finite(x, b)) return false;
  const Point pa[3] = {point(x, a[0]), point(x, a[1]), point(x, a[2])};
  const Point pb[3] = {point(x, b[0]), point(x, b[1]), point(x, b[2])};
  return meet(a, b, pa, pb, hull(pa[0], pa[1], pa[2]), hull(pb[0], pb[1], pb[2]));
}

bool triangles_intersect(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  if (!a.allFinite() || !b.allFinite()) return false;
  const Eigen::Matrix3Xd m = (Eigen::Matrix3Xd(3, 6) << a, b).finished();
  const std::vector<Point> p = points(m);
  return meet(hull(p[0], p[1], p[2]), hull(p[3], p[4], p[5]));
}

long intersecting_triangle_pairs(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles) {
  check_indices(triangles, x.cols(), "triangle");
  const std::vector<Point> p = points(x);
  const std::vector<Hull> h = hulls(x, p, triangles);
  std::vector<Box> b = boxes(h, 0);
  long count = 0;
  CGAL::box_self_intersection_d(
      b.begin(), b.end(),
      [&](const Box& s, const Box& t) {
        const Corners cs = corners(p, triangles, s.index), ct = corners(p, triangles, t.index);
        count += meet(triangles.col(s.index), triangles.col(t.index), cs.p, ct.p, h[static_cast<std::size_t>(s.index)],
                      h[static_cast<std::size_t>(t.index)]);
      },
      CGAL::Box_intersection_d::Box_traits_d<Box>(), box_cutoff, CGAL::Box_intersection_d::CLOSED);
  return count;
}

long intersecting_triangle_pairs(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles,
                                 const Eigen::Matrix3Xd& obstacle_vertices,
                                 const Eigen::Matrix3Xi& obstacle_triangles) {
  check_indices(triangles, x.cols(), "triangle");
  check_indices(obstacle_triangles, obstacle_vertices.cols(), "obstacle triangle");
  const std::vector<Point> p = points(x), q = points(obstacle_vertices);
  const std::vector<Hull> h = hulls(x, p, triangles), g = hulls(obstacle_vertices, q, obstacle_triangles);
  std::vector<Box> b = boxes(h, 0), c = boxes(g, h.size());
  long count = 0;
  CGAL::box_intersection_d(
      b.begin(), b.end(), c.begin(), c.end(),
      [&](const Box& s, const Box& t) {
        count += meet(h[static_cast<std::size_t>(s.index)], g[static_cast<std::size_t>(t.index)]);
      },
      CGAL::Box_intersection_d::Box_traits_d<Box>(), box_cutoff, CGAL::Box_intersection_d::CLOSED,
      CGAL::Box_intersection_d::BIPARTITE);
  return count;
}

}  // namespace pce::sim
