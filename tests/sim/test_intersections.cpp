// SPDX-License-Identifier: MIT
// pce::sim exact intersection counts (src/sim/geometry/intersections_cgal.cpp): every case of
// the header's rules (disjoint, crossing, touching, coplanar overlap, degenerate, non-finite),
// the neighbour rule for shared edges and shared vertices in every vertex order, and the
// box-filtered counts against the brute-force count over all pairs with the same predicate.
#include <pce/sim/generators.hpp>
#include <pce/sim/intersections.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace {
using pce::sim::intersecting_triangle_pairs;
using pce::sim::triangles_intersect;

Eigen::Matrix3Xd points(const std::vector<Eigen::Vector3d>& p) {
  Eigen::Matrix3Xd x(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i) x.col(static_cast<Eigen::Index>(i)) = p[i];
  return x;
}

Eigen::Matrix3Xi triangles(const std::vector<Eigen::Vector3i>& t) {
  Eigen::Matrix3Xi m(3, static_cast<Eigen::Index>(t.size()));
  for (std::size_t i = 0; i < t.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = t[i];
  return m;
}

/// Every unordered pair tested with the exact predicate, no filter.
long brute_force(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& t) {
  long count = 0;
  for (Eigen::Index i = 0; i < t.cols(); ++i)
    for (Eigen::Index j = i + 1; j < t.cols(); ++j) count += triangles_intersect(x, t.col(i), t.col(j));
  return count;
}

Eigen::Vector3i rotated(const Eigen::Vector3i& t, int r) {
  return Eigen::Vector3i(t[r % 3], t[(r + 1) % 3], t[(r + 2) % 3]);
}

/// The verdict on the pair (a, b) of vertices `x`, checked to be the same in both orders,
/// for every rotation and both orientations of each triangle, and for the counting function.
bool pair_verdict(const Eigen::Matrix3Xd& x, const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
  const bool verdict = triangles_intersect(x, a, b);
  for (int flip_a = 0; flip_a < 2; ++flip_a)
    for (int flip_b = 0; flip_b < 2; ++flip_b)
      for (int ra = 0; ra < 3; ++ra)
        for (int rb = 0; rb < 3; ++rb) {
          Eigen::Vector3i pa = rotated(a, ra), pb = rotated(b, rb);
          if (flip_a) std::swap(pa[0], pa[1]);
          if (flip_b) std::swap(pb[0], pb[1]);
          EXPECT_EQ(triangles_intersect(x, pa, pb), verdict) << "order " << flip_a << flip_b << ra << rb;
          EXPECT_EQ(triangles_intersect(x, pb, pa), verdict) << "order " << flip_a << flip_b << ra << rb;
          EXPECT_EQ(intersecting_triangle_pairs(x, triangles({pa, pb})), verdict ? 1 : 0);
        }
  return verdict;
}

const Eigen::Vector3i first(0, 1, 2), second(3, 4, 5);

/// Triangle (0,1,2) = {(0,0,0), (1,0,0), (0,1,0)} and a second one given by its points.
Eigen::Matrix3Xd with_second(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  return points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, p, q, r});
}

TEST(TrianglePair, Disjoint) {
  EXPECT_FALSE(pair_verdict(with_second({0, 0, 1}, {1, 0, 1}, {0, 1, 1}), first, second));           // parallel
  EXPECT_FALSE(pair_verdict(with_second({0.6, 0.6, -1}, {0.6, 0.6, 1}, {2, 2, 0}), first, second));  // beyond the edge
}

TEST(TrianglePair, Crossing) {
  EXPECT_TRUE(pair_verdict(with_second({0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}), first, second));
  EXPECT_TRUE(
      pair_verdict(with_second({-1, 0.2, -1}, {2, 0.2, -1}, {0.5, 0.2, 1}), first, second));  // edge through edge
}

TEST(TrianglePair, TouchingCounts) {
  // A vertex on the face, a vertex on an edge, an edge lying on an edge, vertex on vertex.
  EXPECT_TRUE(pair_verdict(with_second({0.2, 0.2, 0}, {0.2, 0.2, 1}, {0.3, 0.2, 1}), first, second));
  EXPECT_TRUE(pair_verdict(with_second({0.5, 0, 0}, {0.5, -1, 1}, {0.5, -1, -1}), first, second));
  EXPECT_TRUE(pair_verdict(with_second({0.2, 0, 0}, {0.7, 0, 0}, {0.5, -1, 1}), first, second));
  EXPECT_TRUE(pair_verdict(with_second({1, 0, 0}, {2, 0, 1}, {2, 1, 1}), first, second));
  // The same vertex position under two indices touches: it is not shared.
  EXPECT_TRUE(pair_verdict(with_second({0, 0, 0}, {-1, -1, 1}, {-1, -1, -1}), first, second));
  // Just off: a gap of one ulp-sized step is a gap.
  EXPECT_FALSE(pair_verdict(with_second({0.2, 0.2, 1e-300}, {0.2, 0.2, 1}, {0.3, 0.2, 1}), first, second));
}

TEST(TrianglePair, CoplanarOverlap) {
  EXPECT_TRUE(pair_verdict(with_second({0.2, 0.2, 0}, {2, 0.2, 0}, {0.2, 2, 0}), first, second));
  EXPECT_TRUE(pair_verdict(with_second({0.1, 0.1, 0}, {0.3, 0.1, 0}, {0.1, 0.3, 0}), first, second));  // inside
  EXPECT_FALSE(pair_verdict(with_second({0.6, 0.6, 0}, {2, 0.6, 0}, {0.6, 2, 0}), first, second));
}

// Shared edge (0,1) along x; T1 = (0,1,2) with 2 at (0,1,0); T2 = (1,0,3).
Eigen::Matrix3Xd shared_edge(const Eigen::Vector3d& d) { return points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, d}); }
const Eigen::Vector3i edge_a(0, 1, 2), edge_b(1, 0, 3);

TEST(SharedEdge, FlatAndFoldedDoNotCount) {
  EXPECT_FALSE(pair_verdict(shared_edge({0.5, -1, 0}), edge_a, edge_b));    // flat continuation
  EXPECT_FALSE(pair_verdict(shared_edge({0.5, 0, 1}), edge_a, edge_b));     // folded 90°
  EXPECT_FALSE(pair_verdict(shared_edge({0.5, 1, 1e-9}), edge_a, edge_b));  // folded almost flat
  EXPECT_FALSE(pair_verdict(shared_edge({0.5, 1, -1e-9}), edge_a, edge_b));
  EXPECT_FALSE(pair_verdict(shared_edge({3, 0, 0}), edge_a, edge_b));  // d on the line: degenerate
}

TEST(SharedEdge, FoldedThroughCounts) {
  EXPECT_TRUE(pair_verdict(shared_edge({0.5, 1, 0}), edge_a, edge_b));    // folded flat onto T1
  EXPECT_TRUE(pair_verdict(shared_edge({0.2, 0.1, 0}), edge_a, edge_b));  // inside T1
  EXPECT_TRUE(pair_verdict(shared_edge({5, 0.1, 0}), edge_a, edge_b));    // sliver overlapping near the edge
}

// Shared vertex 0 at the origin; T1 = (0,1,2) in z = 0; T2 = (0,3,4).
Eigen::Matrix3Xd shared_vertex(const Eigen::Vector3d& e, const Eigen::Vector3d& f) {
  return points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, e, f});
}
const Eigen::Vector3i vertex_a(0, 1, 2), vertex_b(0, 3, 4);

TEST(SharedVertex, MeetingOnlyAtTheVertexDoesNotCount) {
  EXPECT_FALSE(pair_verdict(shared_vertex({1, 1, -1}, {-1, 2, -1}), vertex_a, vertex_b));  // below
  EXPECT_FALSE(pair_verdict(shared_vertex({-1, 0, 0}, {0, -1, 0}), vertex_a, vertex_b));   // coplanar, opposite
  EXPECT_FALSE(pair_verdict(shared_vertex({-1, 0, 0}, {-1, -1, 1}), vertex_a, vertex_b));
  // Through the vertex into the opposite side of the plane: a cone meeting T1 only at 0.
  EXPECT_FALSE(pair_verdict(shared_vertex({-1, -1, 1}, {-1, -2, -1}), vertex_a, vertex_b));
}

TEST(SharedVertex, CrossingCounts) {
  // T2 cuts T1 along x = y; T2's opposite edge misses T1, T1's opposite edge hits T2.
  EXPECT_TRUE(pair_verdict(shared_vertex({1, 1, 1}, {1, 1, -1}), vertex_a, vertex_b));
  // T2's opposite edge pierces T1.
  EXPECT_TRUE(pair_verdict(shared_vertex({0.2, 0.2, 1}, {0.3, 0.2, -1}), vertex_a, vertex_b));
  // Coplanar wedges that overlap, and that share a ray (touching along a segment).
  EXPECT_TRUE(pair_verdict(shared_vertex({1, 1, 0}, {-1, 2, 0}), vertex_a, vertex_b));
  EXPECT_TRUE(pair_verdict(shared_vertex({2, 0, 0}, {0, -1, 0}), vertex_a, vertex_b));
  // T2 leaning on T1's edge (0,1) from above: touching along it.
  EXPECT_TRUE(pair_verdict(shared_vertex({0.5, 0, 0}, {0.5, -1, 1}), vertex_a, vertex_b));
}

TEST(TrianglePair, RepeatedTriangleDoesNotCount) {
  const Eigen::Matrix3Xd x = points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  EXPECT_FALSE(triangles_intersect(x, Eigen::Vector3i(0, 1, 2), Eigen::Vector3i(2, 0, 1)));
  EXPECT_EQ(intersecting_triangle_pairs(x, triangles({{0, 1, 2}, {1, 2, 0}})), 0);
}

TEST(TrianglePair, DegenerateTriangles) {
  // Collinear (a segment) piercing T1, and one lying beside it; all three points equal.
  EXPECT_TRUE(pair_verdict(with_second({0.2, 0.2, -1}, {0.2, 0.2, 1}, {0.2, 0.2, 0.5}), first, second));
  EXPECT_FALSE(pair_verdict(with_second({2, 2, -1}, {2, 2, 1}, {2, 2, 0.5}), first, second));
  EXPECT_TRUE(pair_verdict(with_second({0.2, 0.2, 0}, {0.2, 0.2, 0}, {0.2, 0.2, 0}), first, second));
  EXPECT_FALSE(pair_verdict(with_second({0.2, 0.2, 1}, {0.2, 0.2, 1}, {0.2, 0.2, 1}), first, second));
  // A degenerate neighbour never counts.
  EXPECT_FALSE(pair_verdict(shared_edge({0.5, 0, 0}), edge_a, edge_b));
}

TEST(TrianglePair, NonFiniteSkippedAndIndicesChecked) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Matrix3Xd x = with_second({0.2, 0.2, -1}, {0.3, 0.2, 1}, {nan, 0.3, 1});
  EXPECT_FALSE(triangles_intersect(x, first, second));
  EXPECT_EQ(intersecting_triangle_pairs(x, triangles({first, second})), 0);
  EXPECT_THROW(intersecting_triangle_pairs(x, triangles({first, {3, 4, 6}})), std::invalid_argument);
  EXPECT_THROW(intersecting_triangle_pairs(x, triangles({first, {3, -1, 5}})), std::invalid_argument);
  EXPECT_EQ(intersecting_triangle_pairs(Eigen::Matrix3Xd(3, 0), Eigen::Matrix3Xi(3, 0)), 0);
}

TEST(Grid, FlatGridHasNoIntersection) {
  const pce::sim::Mesh g = pce::sim::grid(1.0, 1.0, 12, 9);
  EXPECT_EQ(intersecting_triangle_pairs(g.positions, g.triangles), 0);
  EXPECT_EQ(brute_force(g.positions, g.triangles), 0);
}

/// Two 8 × 8 grids, one 0.1 above the other, as one mesh.
pce::sim::Mesh two_layers() {
  const pce::sim::Mesh g = pce::sim::grid(1.0, 1.0, 8, 8);
  pce::sim::Mesh m;
  const Eigen::Index n = g.positions.cols();
  m.positions.resize(3, 2 * n);
  m.positions << g.positions, g.positions.colwise() + Eigen::Vector3d(0, 0, 0.1);
  m.triangles.resize(3, 2 * g.triangles.cols());
  m.triangles << g.triangles, g.triangles.array() + static_cast<int>(n);
  return m;
}

TEST(Grid, VertexPushedThroughAnotherLayer) {
  pce::sim::Mesh m = two_layers();
  EXPECT_EQ(intersecting_triangle_pairs(m.positions, m.triangles), 0);
  const Eigen::Index n = m.positions.cols() / 2;
  m.positions(2, n + 4 * 9 + 4) = -0.1;  // an interior vertex of the top layer, pushed through
  const long count = intersecting_triangle_pairs(m.positions, m.triangles);
  EXPECT_GT(count, 0);
  EXPECT_EQ(count, brute_force(m.positions, m.triangles));
}

/// A 16 × 16 grid crumpled into a small box by a smooth map plus noise: many crossings of
/// every kind, neighbours included.
pce::sim::Mesh crumpled(int n, unsigned seed, double noise) {
  pce::sim::Mesh m = pce::sim::grid(1.0, 1.0, n, n);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, noise);
  for (Eigen::Index i = 0; i < m.positions.cols(); ++i) {
    const double u = m.positions(0, i), v = m.positions(1, i);
    m.positions.col(i) << 0.3 * u + 0.08 * std::sin(11 * v + 3 * u), 0.3 * v + 0.08 * std::sin(13 * u - 2 * v),
        0.1 * std::sin(9 * u + 7 * v) + 0.05 * std::cos(17 * u * v);
    m.positions.col(i) += Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
  }
  return m;
}

TEST(Grid, CrumpledMatchesBruteForce) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const pce::sim::Mesh m = crumpled(16, seed, 0.01);
    const long count = intersecting_triangle_pairs(m.positions, m.triangles);
    EXPECT_GT(count, 0);
    EXPECT_EQ(count, brute_force(m.positions, m.triangles)) << "seed " << seed;
  }
}

TEST(Grid, FoldsOntoItselfMatchBruteForce) {
  // Every vertex snapped to a coarse lattice in z = 0 and z = 0.05: many coplanar neighbours,
  // shared edges folded flat, vertices on edges.
  pce::sim::Mesh m = crumpled(12, 7, 0.02);
  m.positions = (m.positions * 20).array().round() / 20;
  const long count = intersecting_triangle_pairs(m.positions, m.triangles);
  EXPECT_GT(count, 0);
  EXPECT_EQ(count, brute_force(m.positions, m.triangles));
}

TEST(Obstacle, ClothAgainstObstacleMesh) {
  const pce::sim::Mesh cloth = pce::sim::grid(1.0, 1.0, 10, 10);
  pce::sim::Mesh obstacle = pce::sim::grid(0.5, 0.5, 3, 3);
  // Stand the obstacle grid up through the cloth.
  for (Eigen::Index i = 0; i < obstacle.positions.cols(); ++i)
    obstacle.positions.col(i) = Eigen::Vector3d(obstacle.positions(0, i) + 0.013, 0.017, obstacle.positions(1, i));
  long brute = 0;
  for (Eigen::Index i = 0; i < cloth.triangles.cols(); ++i)
    for (Eigen::Index j = 0; j < obstacle.triangles.cols(); ++j) {
      Eigen::Matrix3d a, b;
      for (int k = 0; k < 3; ++k) {
        a.col(k) = cloth.positions.col(cloth.triangles(k, i));
        b.col(k) = obstacle.positions.col(obstacle.triangles(k, j));
      }
      brute += triangles_intersect(a, b);
    }
  const long count =
      intersecting_triangle_pairs(cloth.positions, cloth.triangles, obstacle.positions, obstacle.triangles);
  EXPECT_GT(count, 0);
  EXPECT_EQ(count, brute);
  obstacle.positions.row(2).array() += 1.0;  // lifted clear
  EXPECT_EQ(intersecting_triangle_pairs(cloth.positions, cloth.triangles, obstacle.positions, obstacle.triangles), 0);
}

TEST(Grid, TimeOnCrumpled100x100) {
  const pce::sim::Mesh m = crumpled(100, 5, 0.002);
  // The best of five: the machine may be shared.
  long count = 0;
  double ms = 1e300;
  for (int run = 0; run < 5; ++run) {
    const auto start = std::chrono::steady_clock::now();
    count = intersecting_triangle_pairs(m.positions, m.triangles);
    ms = std::min(ms, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::cout << "crumpled 100 x 100 (" << m.triangles.cols() << " triangles): " << count << " intersecting pairs in "
            << ms << " ms\n";
  RecordProperty("milliseconds", std::to_string(ms));
  EXPECT_GT(count, 0);
  EXPECT_LT(ms, 2000.0);  // loose: shared CI machines and sanitizer builds; ~10 ms in Release
}

}  // namespace
