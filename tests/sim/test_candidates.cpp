// SPDX-License-Identifier: MIT
// pce::sim broad phase (src/sim/broad_phase): the brute-force reference finds every pair
// within the contact distance (checked against pce's own closest-feature distance on a
// crumpled cloth), excludes pairs that share a vertex, is sorted, and is not everything.
#include <pce/energy/closest_feature.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/lengths/unsigned_length.hpp>
#include <pce/penalties/quadratic.hpp>
#include <pce/sim/candidates.hpp>
#include <pce/sim/generators.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <set>

namespace {

/// A 10×10 cloth, crumpled: every vertex moved by up to 0.04 in x, y and 0.08 in z.
pce::sim::Mesh crumpled_cloth(unsigned seed) {
  pce::sim::Mesh m = pce::sim::grid(1.0, 1.0, 10, 10);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
    m.positions.col(v) += Eigen::Vector3d(0.04 * u(rng), 0.04 * u(rng), 0.08 * u(rng));
  return m;
}

double distance(const pce::Vec12<double>& x, bool vertex_face) {
  pce::ClosestFeatureEnergy<double> e;
  const pce::QuadraticPenalty far{1.0, 10.0};  // active everywhere here; only the length is used
  const pce::Status s = vertex_face ? pce::closest_feature_energy<pce::VertexFace>(x, pce::UnsignedLength{}, far, e)
                                    : pce::closest_feature_energy<pce::EdgeEdge>(x, pce::UnsignedLength{}, far, e);
  EXPECT_EQ(s, pce::Status::ok);
  return e.length;
}

TEST(BruteForceCandidates, EveryPairWithinTheDistanceAndNothingAdjacent) {
  const double d = 0.03;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const pce::sim::Mesh m = crumpled_cloth(seed);
    const Eigen::Matrix2Xi edges = pce::sim::unique_edges(m.triangles);
    const pce::sim::Candidates c = pce::sim::brute_force_candidates(m.positions, m.triangles, edges, d);
    EXPECT_TRUE(std::is_sorted(c.vertex_face.begin(), c.vertex_face.end()));
    EXPECT_TRUE(std::is_sorted(c.edge_edge.begin(), c.edge_edge.end()));
    const std::set<std::array<int, 2>> vf(c.vertex_face.begin(), c.vertex_face.end()),
        ee(c.edge_edge.begin(), c.edge_edge.end());
    std::size_t vf_pairs = 0, ee_pairs = 0, vf_near = 0, ee_near = 0;
    for (int v = 0; v < m.vertex_count(); ++v)
      for (int t = 0; t < m.triangles.cols(); ++t) {
        const Eigen::Vector3i tri = m.triangles.col(t);
        const bool adjacent = tri[0] == v || tri[1] == v || tri[2] == v;
        if (adjacent) {
          EXPECT_EQ(vf.count({v, t}), 0u) << "vertex " << v << " of its own triangle " << t;
          continue;
        }
        ++vf_pairs;
        pce::Vec12<double> x;
        x << m.positions.col(v), m.positions.col(tri[0]), m.positions.col(tri[1]), m.positions.col(tri[2]);
        if (distance(x, true) <= d) {
          ++vf_near;
          EXPECT_EQ(vf.count({v, t}), 1u) << "vertex " << v << " within " << d << " of triangle " << t << " missed";
        }
      }
    for (int a = 0; a < edges.cols(); ++a)
      for (int b = a + 1; b < edges.cols(); ++b) {
        const bool adjacent = edges(0, a) == edges(0, b) || edges(0, a) == edges(1, b) || edges(1, a) == edges(0, b) ||
                              edges(1, a) == edges(1, b);
        if (adjacent) {
          EXPECT_EQ(ee.count({a, b}), 0u) << "adjacent edges " << a << ", " << b;
          continue;
        }
        ++ee_pairs;
        pce::Vec12<double> x;
        x << m.positions.col(edges(0, a)), m.positions.col(edges(1, a)), m.positions.col(edges(0, b)),
            m.positions.col(edges(1, b));
        if (distance(x, false) <= d) {
          ++ee_near;
          EXPECT_EQ(ee.count({a, b}), 1u) << "edges " << a << ", " << b << " within " << d << " missed";
        }
      }
    // not vacuous, and not everything
    EXPECT_GT(vf_near, 0u);
    EXPECT_GT(ee_near, 0u);
    EXPECT_LT(vf.size(), vf_pairs / 4);
    EXPECT_LT(ee.size(), ee_pairs / 4);
  }
}

TEST(BruteForceCandidates, TheBoxIsGrownByExactlyTheDistance) {
  Eigen::Matrix3Xd x(3, 5);
  x.col(0) << 0, 0, 0;
  x.col(1) << 1, 0, 0;
  x.col(2) << 0, 1, 0;
  x.col(3) << 0.25, 0.25, 0.0999;  // inside the box grown by 0.1
  x.col(4) << 0.25, 0.25, 0.1001;  // outside
  Eigen::Matrix3Xi t(3, 1);
  t.col(0) << 0, 1, 2;
  const pce::sim::Candidates c = pce::sim::brute_force_candidates(x, t, Eigen::Matrix2Xi(2, 0), 0.1);
  ASSERT_EQ(c.vertex_face.size(), 1u);
  EXPECT_EQ(c.vertex_face[0], (std::array<int, 2>{3, 0}));
  EXPECT_TRUE(pce::sim::brute_force_candidates(x, t, Eigen::Matrix2Xi(2, 0), 0.0).vertex_face.empty());
}

TEST(BruteForceCandidates, StrandsGiveOnlyEdgeEdgePairs) {
  const pce::sim::Mesh s = pce::sim::strands(4, 10, 1.0, 0.05);
  const pce::sim::Candidates c = pce::sim::brute_force_candidates(s.positions, s.triangles, s.segments, 0.06);
  EXPECT_TRUE(c.vertex_face.empty());
  EXPECT_FALSE(c.edge_edge.empty());
  // segments of one strand are 0.1 apart along it (beyond 0.06) unless adjacent: every
  // candidate joins two strands
  for (const auto& p : c.edge_edge) EXPECT_NE(p[0] / 10, p[1] / 10) << p[0] << ", " << p[1];
}

}  // namespace
