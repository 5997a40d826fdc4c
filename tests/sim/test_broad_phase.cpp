// SPDX-License-Identifier: MIT
// pce::sim broad phase (src/sim/broad_phase/fcl.cpp): the FCL dynamic-AABB-tree broad phase
// returns exactly the brute-force reference's vectors (same pairs, same order) for
// vertex-face and edge-edge on crumpled cloths, overlapping sheets, strands, flat grids
// whose pairs sit exactly on the box boundary, after the vertices move (refit) and after
// the topology changes (rebuild).
//
// DISABLED_Timing (run with --gtest_also_run_disabled_tests --gtest_filter=*Timing*) prints
// the query times of both on a crumpled 100×100 cloth; it asserts nothing about speed.
#include <pce/sim/broad_phase.hpp>
#include <pce/sim/candidates.hpp>
#include <pce/sim/generators.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>

namespace {

using Pairs = std::vector<std::array<int, 2>>;

/// A w×w cloth of n×n quads, crumpled: a fold wave of amplitude `fold` along z plus random
/// displacements of up to `jitter` times the spacing in x, y and twice that in z.
pce::sim::Mesh crumpled(int n, unsigned seed, double fold = 0.05, double jitter = 0.4) {
  pce::sim::Mesh m = pce::sim::grid(1.0, 1.0, n, n);
  const double h = 1.0 / n, pi = std::acos(-1.0);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    const double x = m.positions(0, v), y = m.positions(1, v);
    m.positions.col(v) += Eigen::Vector3d(jitter * h * u(rng), jitter * h * u(rng),
                                          2 * jitter * h * u(rng) + fold * std::sin(6 * pi * x) * std::cos(4 * pi * y));
  }
  return m;
}

Pairs brute_vf(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& t, double d) {
  return pce::sim::brute_force_candidates(x, t, Eigen::Matrix2Xi(2, 0), d).vertex_face;
}
Pairs brute_ee(const Eigen::Matrix3Xd& x, const Eigen::Matrix2Xi& e, double d) {
  return pce::sim::brute_force_candidates(x, Eigen::Matrix3Xi(3, 0), e, d).edge_edge;
}

/// Runs both queries on `fcl` and compares the vectors exactly; returns the pair counts.
std::array<std::size_t, 2> expect_same(pce::sim::BroadPhase& fcl, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& t,
                                       const Eigen::Matrix2Xi& e, double d, const std::string& what) {
  Pairs vf, ee;
  fcl.vertex_face(x, t, d, vf);
  fcl.edge_edge(x, e, d, ee);
  const Pairs bvf = brute_vf(x, t, d), bee = brute_ee(x, e, d);
  EXPECT_EQ(vf.size(), bvf.size()) << what << ", vertex-face, distance " << d;
  EXPECT_TRUE(vf == bvf) << what << ", vertex-face, distance " << d;
  EXPECT_EQ(ee.size(), bee.size()) << what << ", edge-edge, distance " << d;
  EXPECT_TRUE(ee == bee) << what << ", edge-edge, distance " << d;
  return {bvf.size(), bee.size()};
}

TEST(FclBroadPhase, CrumpledClothEqualsBruteForce) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const pce::sim::Mesh m = crumpled(20, seed);
    const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
    auto fcl = pce::sim::make_broad_phase(pce::sim::BroadPhaseKind::fcl);
    for (double d : {0.0, 0.005, 0.02, 0.08}) {
      const auto counts = expect_same(*fcl, m.positions, m.triangles, edges, d, "crumpled seed " + std::to_string(seed));
      EXPECT_GT(counts[0], 0u);
      EXPECT_GT(counts[1], 0u);
    }
  }
}

TEST(FclBroadPhase, TwoOverlappingSheets) {
  // A second sheet 0.004 above the first, rotated by 30° and shifted, both crumpled a little.
  const pce::sim::Mesh a = crumpled(15, 7, 0.0, 0.1), b0 = crumpled(12, 8, 0.0, 0.1);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.5236, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pce::sim::Mesh both;
  const Eigen::Index na = a.vertex_count(), nb = b0.vertex_count();
  both.positions.resize(3, na + nb);
  both.positions.leftCols(na) = a.positions;
  for (Eigen::Index v = 0; v < nb; ++v)
    both.positions.col(na + v) = R * b0.positions.col(v) + Eigen::Vector3d(0.2, 0.1, 0.004);
  both.triangles.resize(3, a.triangles.cols() + b0.triangles.cols());
  both.triangles << a.triangles, (b0.triangles.array() + static_cast<int>(na)).matrix();
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(both.triangles);
  auto fcl = pce::sim::make_broad_phase(pce::sim::BroadPhaseKind::fcl);
  for (double d : {0.0, 0.002, 0.01}) {
    const auto counts = expect_same(*fcl, both.positions, both.triangles, edges, d, "two sheets");
    EXPECT_GT(counts[0], 0u);
  }
}

TEST(FclBroadPhase, StrandsEdgeEdge) {
  const pce::sim::Mesh m = pce::sim::strands(25, 30, 1.0, 0.02, 0.012);
  auto fcl = pce::sim::make_broad_phase(pce::sim::BroadPhaseKind::fcl);
  for (double d : {0.0, 0.003, 0.01, 0.03}) {
    Pairs ee;
    fcl->edge_edge(m.positions, m.segments, d, ee);
    const Pairs bee = brute_ee(m.positions, m.segments, d);
    EXPECT_TRUE(ee == bee) << "strands, distance " << d << ": " << ee.size() << " vs " << bee.size();
    EXPECT_GT(bee.size(), 0u);
  }
}

TEST(FclBroadPhase, FlatGridPairsExactlyOnTheBoundary) {
  // Grid coordinates (i/n − ½)·w are not exact binary fractions, and the distances equal
  // the spacing: many pairs sit on the brute force's `<=` boundary up to one rounding.
  for (int n : {7, 10, 13}) {
    const pce::sim::Mesh m = pce::sim::grid(1.3, 0.7, n, n + 2);
    const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
    auto fcl = pce::sim::make_broad_phase(pce::sim::BroadPhaseKind::fcl);
    for (double d : {0.0, 1.3 / n, 0.7 / (n + 2), 2 * 1.3 / n, 0.1})
      expect_same(*fcl, m.positions, m.triangles, edges, d, "flat grid " + std::to_string(n));
  }
}

TEST(FclBroadPhase, RefitAfterTheVerticesMove) {
  pce::sim::Mesh m = crumpled(16, 11);
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  auto fcl = pce::sim::make_broad_phase(pce::sim::BroadPhaseKind::fcl);
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int step = 0; step < 5; ++step) {
    expect_same(*fcl, m.positions, m.triangles, edges, 0.015, "refit step " + std::to_string(step));
    // Large moves, so the old tree's boxes are far from right: a missing refit would show.
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
      m.positions.col(v) += Eigen::Vector3d(0.03 * u(rng), 0.03 * u(rng), 0.1 * u(rng));
  }
}

TEST(FclBroadPhase, RebuildAfterTheTopologyChanges) {
  auto fcl = pce::sim::make_broad_phase(pce::sim::BroadPhaseKind::fcl);
  // Different sizes: 12×12, then 9×14, then back.
  for (int k = 0; k < 3; ++k) {
    const pce::sim::Mesh m = k == 1 ? crumpled(9, 20 + k) : crumpled(12, 20 + k);
    expect_same(*fcl, m.positions, m.triangles, pce::sim::unique_edges(m.triangles), 0.02, "size change " + std::to_string(k));
  }
  // Same counts, different indices: the triangles and edges of one cloth reversed in
  // order and the vertex numbering mirrored.
  pce::sim::Mesh m = crumpled(12, 30);
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  expect_same(*fcl, m.positions, m.triangles, edges, 0.02, "before renumbering");
  const int n = static_cast<int>(m.vertex_count());
  Eigen::Matrix3Xd mirrored = m.positions.rowwise().reverse();
  Eigen::Matrix3Xi tris = (n - 1 - m.triangles.rowwise().reverse().array()).matrix();
  Eigen::Matrix2Xi redges = (n - 1 - edges.rowwise().reverse().array()).matrix();
  expect_same(*fcl, mirrored, tris, redges, 0.02, "after renumbering");
  // And a strand set through the same object (edges only, no triangles).
  const pce::sim::Mesh s = pce::sim::strands(9, 12, 0.5, 0.03, 0.02);
  expect_same(*fcl, s.positions, Eigen::Matrix3Xi(3, 0), s.segments, 0.01, "strands after cloth");
}

TEST(FclBroadPhase, DegenerateInputs) {
  auto fcl = pce::sim::make_broad_phase(pce::sim::BroadPhaseKind::fcl);
  const pce::sim::Mesh m = pce::sim::grid(1, 1, 1, 1);  // 4 vertices, 2 triangles sharing an edge
  expect_same(*fcl, m.positions, m.triangles, pce::sim::unique_edges(m.triangles), 0.1, "one quad");
  Pairs out{{1, 2}};
  fcl->vertex_face(m.positions, Eigen::Matrix3Xi(3, 0), 1.0, out);
  EXPECT_TRUE(out.empty());
  out = {{1, 2}};
  fcl->edge_edge(m.positions, Eigen::Matrix2Xi(2, 0), 1.0, out);
  EXPECT_TRUE(out.empty());
}

double milliseconds(const std::function<void()>& f, int repeat) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < repeat; ++r) f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / repeat;
}

TEST(FclBroadPhase, DISABLED_Timing) {
  const pce::sim::Mesh m = crumpled(100, 5);
  const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
  const double d = 0.02;  // 2% of the 1 m sheet
  auto fcl = pce::sim::make_broad_phase(pce::sim::BroadPhaseKind::fcl);
  Pairs vf, ee;
  const double first_vf = milliseconds([&] { fcl->vertex_face(m.positions, m.triangles, d, vf); }, 1);
  const double first_ee = milliseconds([&] { fcl->edge_edge(m.positions, edges, d, ee); }, 1);
  // Refit path: move every vertex a little between queries, as a time step would.
  Eigen::Matrix3Xd x = m.positions;
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  const double refit_vf = milliseconds([&] {
    x = x.unaryExpr([&](double c) { return c + u(rng); });
    fcl->vertex_face(x, m.triangles, d, vf);
  }, 5);
  const double refit_ee = milliseconds([&] { fcl->edge_edge(x, edges, d, ee); }, 5);
  Pairs bvf, bee;
  const double brute_vf_ms = milliseconds([&] { bvf = brute_vf(x, m.triangles, d); }, 1);
  const double brute_ee_ms = milliseconds([&] { bee = brute_ee(x, edges, d); }, 1);
  EXPECT_TRUE(vf == bvf);
  EXPECT_TRUE(ee == bee);
  std::printf("crumpled 100x100 cloth: %td vertices, %td triangles, %td edges, distance %g\n", m.vertex_count(),
              m.triangles.cols(), edges.cols(), d);
  std::printf("vertex-face: %zu pairs; fcl first (build) %.1f ms, fcl refit %.1f ms, brute force %.1f ms\n", bvf.size(),
              first_vf, refit_vf, brute_vf_ms);
  std::printf("edge-edge:   %zu pairs; fcl first (build) %.1f ms, fcl refit %.1f ms, brute force %.1f ms\n", bee.size(),
              first_ee, refit_ee, brute_ee_ms);
}

}  // namespace
