// SPDX-License-Identifier: MIT
// energy/projection.hpp: `with_projection` maps every strategy to its own compile-time
// constant, and for every energy type the run-time form `projected_hessian(e, strategy)` —
// here pce::precompiled's instantiation, which the tests link — gives the same bits as the
// header's compile-time form `projected_hessian<P>(e)`, for every strategy, in double (float
// and long double are the same source in the same library; instantiating every form in
// three scalars would cost this file ~100 s of compile time); the inputs reach every branch (each closest feature, a
// mollified pair inside and outside its threshold, an indefinite exact Hessian so that the strategies differ).
#include <pce/pce.hpp>

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace {
using S = double;
constexpr std::array<pce::Projection, 6> kAll{pce::Projection::none,      pce::Projection::analytic,
                                              pce::Projection::numerical, pce::Projection::gauss_newton,
                                              pce::Projection::abs,       pce::Projection::exact};

TEST(Projection, EveryStrategyDispatchesToItsOwnConstant) {
  for (pce::Projection p : kAll)
    EXPECT_EQ(pce::with_projection(p, [](auto c) { return decltype(c)::value; }), p) << pce::to_string(p);
  // A value outside the enumeration is `none`.
  EXPECT_EQ(pce::with_projection(static_cast<pce::Projection>(99), [](auto c) { return decltype(c)::value; }),
            pce::Projection::none);
}

/// Both forms for every strategy, bit for bit; returns how many distinct matrices the six
/// strategies gave (so a test can see that its input tells the strategies apart).
template <class Energy> int same_bits_both_forms(const Energy& e) {
  std::vector<decltype(pce::projected_hessian(e, pce::Projection::none))> seen;
  for (pce::Projection p : kAll) {
    SCOPED_TRACE(pce::to_string(p));
    const auto run_time = pce::projected_hessian(e, p);
    const auto compile_time =
        pce::with_projection(p, [&e](auto c) { return pce::projected_hessian<decltype(c)::value>(e); });
    EXPECT_TRUE(run_time.cwiseEqual(compile_time).all())
        << "largest difference " << (run_time - compile_time).cwiseAbs().maxCoeff();
    EXPECT_TRUE(run_time.allFinite());
    bool fresh = true;
    for (const auto& m : seen) fresh = fresh && !m.cwiseEqual(run_time).all();
    if (fresh) seen.push_back(run_time);
  }
  return static_cast<int>(seen.size());
}

pce::Vec12<S> vec12(std::initializer_list<double> v) {
  pce::Vec12<S> x;
  int i = 0;
  for (double c : v) x[i++] = S(c);
  return x;
}

// Inside the activation distance σψ′ < 0 and the length's Hessian has eigenvalues of both
// signs: the exact Hessian is indefinite, so the strategies give different matrices.
const pce::CubicPenalty kPenalty{10.0, 0.5, 0.4};

TEST(ProjectionForms, PlaneKinds) {
  pce::PairEnergy<S> vf, ee;
  ASSERT_EQ(pce::pair_energy<pce::VertexFace>(vec12({0.2, 0.3, 0.1, 0, 0, 0, 1, 0.1, 0, 0, 1, 0.05}),
                                              pce::SignedLength{}, kPenalty, vf),
            pce::Status::ok);
  ASSERT_EQ(pce::pair_energy<pce::EdgeEdge>(vec12({0, 0, 0, 1, 0.2, 0, 0.3, -0.5, 0.2, 0.4, 0.6, 0.15}),
                                            pce::UnsignedLength{}, kPenalty, ee),
            pce::Status::ok);
  EXPECT_GE(same_bits_both_forms(vf), 4);
  EXPECT_GE(same_bits_both_forms(ee), 4);
}

TEST(ProjectionForms, PointKinds) {
  pce::PointEdgeEnergy<S> pe;
  pce::PointPointEnergy<S> pp;
  pce::Vec9<S> xpe;
  xpe << S(0.5), S(0.2), S(0.1), S(0), S(0), S(0), S(2), S(0), S(0);
  pce::Vec6<S> xpp;
  xpp << S(0.1), S(0.2), S(0.15), S(0), S(0), S(0);
  ASSERT_EQ(pce::pair_energy<pce::PointEdge>(xpe, pce::UnsignedLength{}, kPenalty, pe), pce::Status::ok);
  ASSERT_EQ(pce::pair_energy<pce::PointPoint>(xpp, pce::UnsignedLength{}, kPenalty, pp), pce::Status::ok);
  EXPECT_GE(same_bits_both_forms(pe), 3);
  EXPECT_GE(same_bits_both_forms(pp), 3);
}

TEST(ProjectionForms, ClosestFeatures) {
  // A point above the plane's interior, beside an edge, and beside a vertex of the triangle.
  const std::array<pce::Vec12<S>, 3> xs{vec12({0.2, 0.2, 0.2, 0, 0, 0, 1, 0, 0, 0, 1, 0}),
                                        vec12({0.5, -0.2, 0.2, 0, 0, 0, 1, 0, 0, 0, 1, 0}),
                                        vec12({-0.2, -0.2, 0.2, 0, 0, 0, 1, 0, 0, 0, 1, 0})};
  const std::array<pce::Feature, 3> expected{pce::Feature::point_plane, pce::Feature::point_edge,
                                             pce::Feature::point_point};
  for (int k = 0; k < 3; ++k) {
    pce::ClosestFeatureEnergy<S> e;
    ASSERT_EQ(pce::closest_feature_energy<pce::VertexFace>(xs[k], pce::UnsignedLength{}, kPenalty, e), pce::Status::ok);
    ASSERT_EQ(e.feature, expected[k]);
    EXPECT_GE(same_bits_both_forms(e), 3);
  }
}

TEST(ProjectionForms, Mollified) {
  // Nearly parallel edges: |e0 × e1|² below the threshold (mollified), and a threshold below it.
  const pce::Vec12<S> x = vec12({0, 0, 0, 1, 0, 0, 0.1, 0.05, 0.2, 1.1, 0.1, 0.2});
  for (double threshold : {1.0, 1e-6}) {
    SCOPED_TRACE(threshold);
    pce::MollifiedEnergy<S> e;
    ASSERT_EQ(
        pce::mollified_pair_energy<pce::EdgeEdge>(x, pce::UnsignedLength{}, kPenalty, pce::Mollifier{threshold}, e),
        pce::Status::ok);
    EXPECT_GE(same_bits_both_forms(e), 3);
  }
}

}  // namespace
