// SPDX-License-Identifier: MIT
// energy/closest_feature.hpp: classification against a brute-force distance, the
// conformance suite (tests/support/kind_conformance.hpp) on all 12 coordinates away from
// region boundaries, sweeps across every region boundary (distance and gradient
// continuous, Hessian jump finite), parallel and crossing edges, statuses, hard cases.
#include "support/kind_conformance.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <set>

namespace {
using namespace pce_test;
using V = Eigen::Vector3d;

pce::Vec12<double> four(const V& a, const V& b, const V& c, const V& d) {
  pce::Vec12<double> x;
  x << a, b, c, d;
  return x;
}

template <class Pair> pce::ClosestFeatureEnergy<double> eval(const pce::Vec12<double>& x, double eps = 10.0) {
  pce::ClosestFeatureEnergy<double> e;
  EXPECT_EQ(pce::closest_feature_energy<Pair>(x, pce::UnsignedLength{}, pce::QuadraticPenalty{1.0, eps}, e),
            pce::Status::ok);
  return e;
}

/// Distance between the primitives by dense sampling (upper bound) and its resolution.
double sampled_distance(bool vf, const pce::Vec12<double>& x, int n = 80) {
  const V a = x.segment<3>(0), b = x.segment<3>(3), c = x.segment<3>(6), d = x.segment<3>(9);
  double best = 1e300;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double u = double(i) / n, v = double(j) / n;
      if (vf) {
        if (i + j > n) continue;
        best = std::min(best, (a - (b + u * (c - b) + v * (d - b))).norm());
      } else {
        best = std::min(best, ((a + u * (b - a)) - (c + v * (d - c))).norm());
      }
    }
  return best;
}

TEST(ClosestFeature, DistanceMatchesBruteForceAndEveryFeatureOccurs) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int vf = 0; vf < 2; ++vf) {
    std::set<pce::Feature> seen;
    for (int it = 0; it < 600; ++it) {
      pce::Vec12<double> x;
      for (int i = 0; i < 12; ++i) x[i] = U(rng);
      const pce::ClosestFeatureEnergy<double> e = vf ? eval<pce::VertexFace>(x) : eval<pce::EdgeEdge>(x);
      seen.insert(e.feature);
      const double s = sampled_distance(vf, x);
      // The closest-feature distance is the minimum: never above a sample, and below the
      // best sample by at most the grid's resolution (≤ 2·4/80 for coordinates in [−1, 1]).
      EXPECT_LE(e.length, s * (1 + 1e-12) + 1e-15) << x.transpose();
      EXPECT_GE(e.length, s - 0.1) << x.transpose();
    }
    if (vf) {
      EXPECT_EQ(seen, (std::set<pce::Feature>{pce::Feature::point_plane, pce::Feature::point_edge,
                                              pce::Feature::point_point}));
    } else {
      EXPECT_EQ(seen,
                (std::set<pce::Feature>{pce::Feature::line_line, pce::Feature::point_edge, pce::Feature::point_point}));
    }
  }
}

TEST(ClosestFeature, FaceInteriorIsThePlainUnsignedPlaneEnergy) {
  const pce::Vec12<double> x = four({0.2, 0.3, -0.05}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  pce::PairEnergy<double> plain;
  ASSERT_EQ(pce::pair_energy<pce::VertexFace>(x, pce::UnsignedLength{}, pce::QuadraticPenalty{1.0, 10.0}, plain),
            pce::Status::ok);
  const pce::ClosestFeatureEnergy<double> e = eval<pce::VertexFace>(x);
  EXPECT_EQ(e.feature, pce::Feature::point_plane);
  EXPECT_EQ(pce::energy_gradient(e), pce::energy_gradient(plain));
  EXPECT_EQ(pce::energy_hessian(e), pce::energy_hessian(plain));
  EXPECT_EQ(pce::projected_hessian(e, pce::Projection::exact), pce::projected_hessian(plain, pce::Projection::exact));
}

TEST(ClosestFeature, StatusesAndWhatASignedRequestGets) {
  const pce::QuadraticPenalty quad{1.0, 1.0};
  pce::ClosestFeatureEnergy<double> e;
  e.length = -7;
  const pce::Vec12<double> vf = four({2, 2, 0.1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
  EXPECT_EQ(pce::closest_feature_energy<pce::VertexFace>(vf, pce::SignedLength{}, quad, e), pce::Status::invalid_input)
      << "closest-feature distances are unsigned";
  pce::Vec12<double> bad = vf;
  bad[7] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(pce::closest_feature_energy<pce::VertexFace>(bad, pce::UnsignedLength{}, quad, e),
            pce::Status::invalid_input);
  // p exactly on an edge of a proper triangle: inside the face's closed region, the plane
  // kind at l = 0 (σ = +1), ok.
  EXPECT_EQ(pce::closest_feature_energy<pce::VertexFace>(four({0.5, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}),
                                                         pce::UnsignedLength{}, quad, e),
            pce::Status::ok);
  EXPECT_EQ(e.feature, pce::Feature::point_plane);
  // p on a collinear (zero-area) triangle: distance 0 on a point kind, no direction.
  e.length = -7;
  EXPECT_EQ(pce::closest_feature_energy<pce::VertexFace>(four({0.5, 0, 0}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}),
                                                         pce::UnsignedLength{}, quad, e),
            pce::Status::degenerate);
  EXPECT_EQ(e.length, -7) << "nothing written on failure";
  EXPECT_EQ(pce::closest_feature_energy<pce::VertexFace>(four({1.5, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}),
                                                         pce::UnsignedLength{}, quad, e),
            pce::Status::ok)
      << "beyond the corner t1 in the plane: point-point at distance 0.5";
  EXPECT_EQ(e.feature, pce::Feature::point_point);
  EXPECT_DOUBLE_EQ(e.length, 0.5);
  e.length = -7;
  EXPECT_EQ(pce::closest_feature_energy<pce::EdgeEdge>(four({-1, 0, 0}, {1, 0, 0}, {-0.5, 0, 0}, {2, 0, 0}),
                                                       pce::UnsignedLength{}, quad, e),
            pce::Status::degenerate)
      << "overlapping collinear edges: distance 0";
  EXPECT_EQ(e.length, -7) << "nothing written on failure";
  // Degenerate triangles and parallel edges are not degenerate here.
  EXPECT_EQ(pce::closest_feature_energy<pce::VertexFace>(four({0.3, 0.5, 0.2}, {0, 0, 0}, {1, 0, 0}, {2, 0, 0}),
                                                         pce::UnsignedLength{}, quad, e),
            pce::Status::ok);
  EXPECT_EQ(e.feature, pce::Feature::point_edge);
  EXPECT_DOUBLE_EQ(e.length, std::sqrt(0.25 + 0.04));
  EXPECT_EQ(pce::closest_feature_energy<pce::VertexFace>(four({0.3, 0.5, 0.2}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}),
                                                         pce::UnsignedLength{}, quad, e),
            pce::Status::ok);
  EXPECT_EQ(e.feature, pce::Feature::point_point);
}

// The plane kind is chosen only when its |l| is not above the nearest point-segment
// distance: a frame whose normal is rounding noise (a triangle or edge pair at an angle
// below the scalar's ε) can put the foot "inside" with a meaningless l. classify() is
// given such a frame's verdict directly here.
TEST(ClosestFeature, ANoisyPlaneFrameCannotWinOverTheSegments) {
  pce::Vec12<double> x;
  x << 0.25, 0.25, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0;  // p above the face interior, l = 1
  pce::Feature feature;
  std::array<int, 3> points;
  pce::detail::classify<pce::VertexFace>(x, true, 1.0, feature, points);
  EXPECT_EQ(feature, pce::Feature::point_plane) << "an accurate frame: the plane";
  pce::detail::classify<pce::VertexFace>(x, true, 50.0, feature, points);  // |l| beyond every edge distance
  EXPECT_EQ(feature, pce::Feature::point_edge);
  EXPECT_EQ(points[0], 0);
  pce::detail::classify<pce::VertexFace>(x, false, 1.0, feature, points);
  EXPECT_EQ(feature, pce::Feature::point_edge) << "foot outside: a segment";
  pce::Vec12<double> y;
  y << 0, 0, 0, 1, 0, 0, 0.5, -1, 1, 0.5, 1, 1;  // edges crossing at height 1
  pce::detail::classify<pce::EdgeEdge>(y, true, 1.0, feature, points);
  EXPECT_EQ(feature, pce::Feature::line_line);
  pce::detail::classify<pce::EdgeEdge>(y, true, -7.0, feature, points);
  EXPECT_NE(feature, pce::Feature::line_line);
}

TEST(ClosestFeature, ParallelAndCrossingEdges) {
  // Exactly parallel and overlapping: an endpoint and the other edge's inside.
  pce::ClosestFeatureEnergy<double> e =
      eval<pce::EdgeEdge>(four({-1, 0, 0}, {1, 0, 0}, {-0.5, 0.3, 0.1}, {1.5, 0.3, 0.1}));
  EXPECT_EQ(e.feature, pce::Feature::point_edge);
  EXPECT_NEAR(e.length, std::sqrt(0.1), 1e-15);
  // Exactly parallel, not overlapping: two endpoints.
  e = eval<pce::EdgeEdge>(four({-1, 0, 0}, {1, 0, 0}, {2, 0.3, 0.1}, {3, 0.3, 0.1}));
  EXPECT_EQ(e.feature, pce::Feature::point_point);
  EXPECT_EQ(e.points[0], 1);
  EXPECT_EQ(e.points[1], 2);
  EXPECT_NEAR(e.length, std::sqrt(1 + 0.1), 1e-15);
  // Nearly parallel: the same distances, no status change, bounded Hessians.
  for (int k = 2; k <= 14; k += 2) {
    const double th = std::pow(10.0, -k);
    e = eval<pce::EdgeEdge>(four({-1, 0, 0}, {1, 0, 0}, {-0.5, 0.3, 0.1}, {1.5, 0.3 + 2 * th, 0.1}));
    EXPECT_EQ(e.feature, pce::Feature::point_edge) << th;
    EXPECT_LT(pce::projected_hessian(e, pce::Projection::exact).norm(), 100.0) << th;
  }
  // Crossing edges: line-line at distance 0 is evaluated (l = 0, σ = +1).
  e = eval<pce::EdgeEdge>(four({-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}));
  EXPECT_EQ(e.feature, pce::Feature::line_line);
  EXPECT_EQ(e.length, 0.0);
}

/// Sweeps `make(δ)` across a region boundary at δ = 0: the features on the two sides are
/// `below` and `above`; the distance and the gradient are continuous (differences O(δ));
/// the Hessian stays finite and its jump is reported.
template <class Pair, class Make>
void sweep_boundary(const char* what, Make make, pce::Feature below, pce::Feature above) {
  SCOPED_TRACE(what);
  const pce::ClosestFeatureEnergy<double> e0 = eval<Pair>(make(0.0));
  const pce::Vec12<double> g0 = pce::energy_gradient(e0);
  double jump = 0;
  for (int k = 2; k <= 12; k += 2) {
    const double d = std::pow(10.0, -k);
    const pce::ClosestFeatureEnergy<double> em = eval<Pair>(make(-d)), ep = eval<Pair>(make(d));
    // Within ~1e-8 of a point-edge | point-point boundary the two distances differ by
    // O(δ²), below rounding: either feature is a correct answer there (same distance, same
    // gradient), so the features are checked only where they are decided.
    if (d >= 1e-6) {
      EXPECT_EQ(em.feature, below) << d;
      EXPECT_EQ(ep.feature, above) << d;
    }
    EXPECT_LE(std::fabs(em.length - e0.length), 2 * d + 1e-15) << "distance continuous";
    EXPECT_LE(std::fabs(ep.length - e0.length), 2 * d + 1e-15) << "distance continuous";
    const pce::Mat12<double> Hm = pce::energy_hessian(em), Hp = pce::energy_hessian(ep);
    // C¹: the gradient moves by at most ‖∇²E‖·|δx| (here |δx| ≤ δ) on either side; a jump in
    // the gradient would be O(1), independent of δ.
    const double eg = std::max((pce::energy_gradient(em) - g0).norm(), (pce::energy_gradient(ep) - g0).norm());
    EXPECT_LE(eg, 1.01 * std::max(Hm.norm(), Hp.norm()) * d + 1e-12) << "gradient continuous (C1) at " << d;
    EXPECT_TRUE(pce::detail::all_finite(Hm) && pce::detail::all_finite(Hp));
    jump = std::max(jump, (Hm - Hp).norm() / std::max(Hm.norm(), Hp.norm()));
    for (pce::Projection p : {pce::Projection::analytic, pce::Projection::exact})
      for (const auto* e : {&em, &ep}) EXPECT_GE(min_eigenvalue(pce::projected_hessian(*e, p)), -1e-12 * Hm.norm());
  }
  std::printf("%-40s relative Hessian jump across the boundary: %.3f\n", what, jump);
}

TEST(ClosestFeature, SweepsAcrossEveryRegionBoundary) {
  const V t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  const double h = 0.2;
  using PF = pce::Feature;
  sweep_boundary<pce::VertexFace>(
      "vertex-face: face | edge t0t1",
      [&](double d) {
        return four({0.4, d, h}, t0, t1, t2);
      },
      PF::point_edge, PF::point_plane);
  sweep_boundary<pce::VertexFace>(
      "vertex-face: face | edge t1t2 (hypotenuse)",
      [&](double d) { return four(V(0.5, 0.5, h) - d * V(1, 1, 0) / std::sqrt(2.0), t0, t1, t2); }, PF::point_edge,
      PF::point_plane);
  sweep_boundary<pce::VertexFace>(
      "vertex-face: corner t0 | edge t0t1",
      [&](double d) {
        return four({d, -0.3, h}, t0, t1, t2);
      },
      PF::point_point, PF::point_edge);
  sweep_boundary<pce::VertexFace>(
      "vertex-face: edge t1t2 | corner t1",
      [&](double d) { return four(V(1.2, 0.2, h) + d * V(-1, 1, 0) / std::sqrt(2.0), t0, t1, t2); }, PF::point_point,
      PF::point_edge);
  // Edge-edge: edge b crosses above edge a at x = x0; line-line while x0 < 1.
  sweep_boundary<pce::EdgeEdge>(
      "edge-edge: line-line | point-edge",
      [&](double d) {
        return four({-1, 0, 0}, {1, 0, 0}, {1 + d, -1, h}, {1 + d, 1, h});
      },
      PF::line_line, PF::point_edge);
  sweep_boundary<pce::EdgeEdge>(
      "edge-edge: point-edge | point-point",
      [&](double d) {
        return four({-1, 0, 0}, {1, 0, 0}, {1.5, -d, h}, {1.5, 2, h});
      },
      PF::point_point, PF::point_edge);
}

/// A random candidate whose closest features do not change within ±2e-3·scale of any
/// coordinate (so finite differences stay in one region), with distance ≥ 0.05·scale.
template <class Pair> pce::Vec12<double> draw_interior(std::mt19937_64& rng, double scale, double offset, double& L) {
  std::uniform_real_distribution<double> U(-1, 1);
  for (;;) {
    pce::Vec12<double> x;
    for (int i = 0; i < 12; ++i) x[i] = scale * U(rng);
    const pce::ClosestFeatureEnergy<double> e = eval<Pair>(x, 1e9);
    if (e.length < 0.05 * scale || e.length > scale) continue;
    bool stable = true;
    for (int i = 0; i < 12 && stable; ++i)
      for (double s : {-2e-3, 2e-3}) {
        pce::Vec12<double> y = x;
        y[i] += s * scale;
        const pce::ClosestFeatureEnergy<double> f = eval<Pair>(y, 1e9);
        stable = stable && f.feature == e.feature && f.points == e.points;
      }
    if (!stable) continue;
    L = e.length;
    for (int j = 0; j < 4; ++j) x.segment<3>(3 * j) += offset * V(0.6, -0.48, 0.64);
    return x;
  }
}

TEST(ClosestFeature, ConformanceVertexFace) {
  const ExactStats st = run_kind_suite<ClosestKind<pce::VertexFace>>(
      [](std::mt19937_64& rng, double s, double o, double& L) { return draw_interior<pce::VertexFace>(rng, s, o, L); },
      47);
  std::printf("closest vertex-face: exact vs numerical compared on %d (worst %.2e), numerical inaccurate on %d\n",
              st.compared, st.worst_vs_numerical, st.numerical_inaccurate);
  EXPECT_GT(st.compared, 100);
}

TEST(ClosestFeature, ConformanceEdgeEdge) {
  const ExactStats st = run_kind_suite<ClosestKind<pce::EdgeEdge>>(
      [](std::mt19937_64& rng, double s, double o, double& L) { return draw_interior<pce::EdgeEdge>(rng, s, o, L); },
      53);
  std::printf("closest edge-edge: exact vs numerical compared on %d (worst %.2e), numerical inaccurate on %d\n",
              st.compared, st.worst_vs_numerical, st.numerical_inaccurate);
  EXPECT_GT(st.compared, 100);
}

TEST(ClosestFeatureHardCases, FarPointsParallelEdgesNearBoundaries) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, V(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  const auto place = [&](const V& a, const V& b, const V& c, const V& d) { return four(R * a, R * b, R * c, R * d); };
  using KVF = ClosestKind<pce::VertexFace>;
  using KEE = ClosestKind<pce::EdgeEdge>;
  const V t0(0, 0, 0), t1(1, 0, 0), t2(0.3, 0.9, 0);
  for (double far : {1e2, 1e4, 1e6}) {
    SCOPED_TRACE(testing::Message() << "vertex " << far << " away");
    expect_stable_all_scalars<KVF>(place({far, 0.7 * far, 0.1}, t0, t1, t2), pce::QuadraticPenalty{1.0, 2 * far});
    expect_stable_all_scalars<KVF>(place({0.3, 0.3, far}, t0, t1, t2), pce::QuadraticPenalty{1.0, 2 * far});
  }
  for (int k = 2; k <= 12; k += 2) {
    const double d = std::pow(10.0, -k);
    SCOPED_TRACE(testing::Message() << "severity " << d);
    // Vertex close to the plane beside an edge, and close to a corner.
    expect_stable_all_scalars<KVF>(place({0.5, -0.2, d}, t0, t1, t2), pce::QuadraticPenalty{1.0, 1.0});
    expect_stable_all_scalars<KVF>(place({-d, -d, d}, t0, t1, t2), pce::QuadraticPenalty{1.0, 1.0});
    // Nearly parallel overlapping edges; nearly touching crossing edges.
    expect_stable_all_scalars<KEE>(place({-1, 0, 0}, {1, 0, 0}, {-0.5, 0.3, 0.1}, {1.5, 0.3 + d, 0.1}),
                                   pce::QuadraticPenalty{1.0, 1.0});
    expect_stable_all_scalars<KEE>(place({-1, 0, 0}, {1, 0, 0}, {0.2, -1, d}, {0.3, 1, d}),
                                   pce::QuadraticPenalty{1.0, 1.0});
  }
}

}  // namespace

TEST(ClosestFeature, CollinearDisjointEdgesAreTheirEndpointsApart) {
  // Two edges on one line with a gap (a grid's anti-diagonal edges two cells apart, as in a
  // tilted sheet): the line distance is ~0 and the frame's normal and closest points are
  // rounding noise that can claim "inside"; the distance must still be the gap.
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> u(-1, 1);
  int noisy_frames = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    V dir(u(rng), u(rng), u(rng));
    dir.normalize();
    const V o(u(rng), u(rng), u(rng));
    const double h = 0.032;
    const pce::Vec12<double> x = four(o, o + h * dir, o + 2 * h * dir, o + 3 * h * dir);
    pce::Frame<double> f;
    if (pce::EdgeEdge::frame(x, f) == pce::Status::ok) ++noisy_frames;
    const auto e = eval<pce::EdgeEdge>(x);
    ASSERT_NEAR(e.length, (x.segment<3>(6) - x.segment<3>(3)).norm(), 1e-12) << "trial " << trial;
    EXPECT_EQ(e.feature, pce::Feature::point_point);
  }
  EXPECT_GT(noisy_frames, 0) << "no trial reached the noisy frame: the test would not exercise the refusal";
}

TEST(ClosestFeature, FootConsistencyRefusesNoisyInsideClaims) {
  // The claim a noisy frame made in a simulated hammock (edges on one anti-diagonal of a
  // tilted grid, two cells apart): β = 1, γ = 0, l = 3.5e-4, while the claimed closest
  // points are the gap (0.032) apart. Refused; accurate frames are accepted.
  const V dir = V(-1, 1, 0.2).normalized();
  const V o(0.1, -0.2, 0.05);
  const double h = 0.032;
  const pce::Vec12<double> x = four(o, o + h * dir, o + 2 * h * dir, o + 3 * h * dir);
  pce::Frame<double> f;
  f.beta = 1;
  f.gamma = 0;
  f.l = 3.5e-4;
  EXPECT_FALSE(pce::foot_consistent<pce::EdgeEdge>(x, f));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  int accepted_vf = 0, accepted_ee = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const pce::Vec12<double> y = four(V(u(rng), u(rng), u(rng)), V(u(rng), u(rng), u(rng)), V(u(rng), u(rng), u(rng)),
                                      V(u(rng), u(rng), u(rng)));
    if (pce::VertexFace::frame(y, f) == pce::Status::ok) accepted_vf += pce::foot_consistent<pce::VertexFace>(y, f);
    if (pce::EdgeEdge::frame(y, f) == pce::Status::ok) accepted_ee += pce::foot_consistent<pce::EdgeEdge>(y, f);
  }
  EXPECT_EQ(accepted_vf, 500);
  EXPECT_EQ(accepted_ee, 500);
}
