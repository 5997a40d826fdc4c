// SPDX-License-Identifier: MIT
// Tests of energy/evaluate_batch.hpp: every row of a batch equals the single-pair functions'
// outputs bit for bit (random, degenerate, out-of-domain and invalid rows, every kind,
// length, penalty and strategy, float and double); rows that are not ok are NaN; outputs
// left null are neither written nor needed.
#include <pce/energy/evaluate_batch.hpp>
#include <pce/penalties/cubic.hpp>
#include <pce/penalties/log_barrier.hpp>
#include <pce/penalties/quadratic.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

namespace {

constexpr pce::Projection kStrategies[] = {pce::Projection::none,      pce::Projection::analytic,
                                           pce::Projection::numerical, pce::Projection::gauss_newton,
                                           pce::Projection::abs,       pce::Projection::exact};

/// `n` pairs of `dofs` coordinates: random points in a small cube (most pairs are within the
/// penalties' reach), then a few hard rows: a repeated point (the second and third; the first
/// and second for point-point: degenerate but for edge-edge, where the edges then touch), a
/// NaN and a coordinate beyond the accepted magnitude.
template <class Scalar> std::vector<Scalar> pairs(int dofs, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::vector<Scalar> x(static_cast<std::size_t>(dofs * n));
  for (auto& v : x) v = static_cast<Scalar>(u(rng));
  const auto row = [&](int i) { return x.data() + static_cast<std::ptrdiff_t>(i) * dofs; };
  const int first = dofs == 6 ? 0 : 3;
  for (int j = 0; j < 3; ++j) row(0)[first + 3 + j] = row(0)[first + j];
  row(1)[4] = std::numeric_limits<Scalar>::quiet_NaN();
  row(2)[7] = std::numeric_limits<Scalar>::max();
  return x;
}

template <class Scalar> bool same_bits(const Scalar* a, const Scalar* b, int n) {
  return std::memcmp(a, b, sizeof(Scalar) * static_cast<std::size_t>(n)) == 0;
}

template <class Scalar> bool all_nan(const Scalar* a, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isnan(a[i])) return false;
  return true;
}

template <class Scalar> struct Buffers {
  std::vector<pce::Status> status;
  std::vector<Scalar> length, value, gradient, hessian, projected, eigenvalues;
  std::vector<pce::Feature> feature;
  Buffers(int n, int d, int f)
      : status(n),
        length(n),
        value(n),
        gradient(n * d),
        hessian(n * d * d),
        projected(n * d * d),
        eigenvalues(n * f),
        feature(n, pce::Feature::point_point) {}
  pce::BatchOutput<Scalar> all() {
    return {status.data(),  length.data(),    value.data(),       gradient.data(),
            hessian.data(), projected.data(), eigenvalues.data(), feature.data()};
  }
};

/// Row i of `b`'s length, value, gradient, Hessian and projected Hessian against `r`, bit for bit.
template <class Scalar, int D, int F>
void expect_row_equals(const Buffers<Scalar>& b, int i, const pce::PairResult<Scalar, D, F>& r) {
  const Eigen::Matrix<Scalar, D, D, Eigen::RowMajor> H = r.hessian, P = r.projected_hessian;
  EXPECT_TRUE(same_bits(&b.length[i], &r.length, 1));
  EXPECT_TRUE(same_bits(&b.value[i], &r.value, 1));
  EXPECT_TRUE(same_bits(&b.gradient[i * D], r.gradient.data(), D));
  EXPECT_TRUE(same_bits(&b.hessian[i * D * D], H.data(), D * D));
  EXPECT_TRUE(same_bits(&b.projected[i * D * D], P.data(), D * D));
}

/// Row i of `b` against `evaluate<Pair>` of the same pair.
template <class Pair, class Scalar, class Length, class Penalty>
void check_against_evaluate(const std::vector<Scalar>& x, int n, const Length& length, const Penalty& penalty,
                            pce::Projection strategy, int& ok_rows) {
  constexpr int D = Pair::dofs, F = Pair::frame_dofs;
  Buffers<Scalar> b(n, D, F);
  pce::evaluate_batch<Pair>(x.data(), static_cast<std::size_t>(n), length, penalty, strategy, b.all());
  for (int i = 0; i < n; ++i) {
    SCOPED_TRACE(::testing::Message() << Pair::name << " row " << i << " " << pce::to_string(strategy));
    const pce::VecN<Scalar, D> xi = Eigen::Map<const pce::VecN<Scalar, D>>(x.data() + i * D);
    pce::PairResult<Scalar, D, F> r;
    const pce::Status s = pce::evaluate<Pair>(xi, length, penalty, strategy, r);
    ASSERT_EQ(b.status[i], s);
    if (s != pce::Status::ok) {
      EXPECT_TRUE(std::isnan(b.length[i]) && std::isnan(b.value[i]));
      EXPECT_TRUE(all_nan(&b.gradient[i * D], D) && all_nan(&b.hessian[i * D * D], D * D) &&
                  all_nan(&b.projected[i * D * D], D * D) && all_nan(&b.eigenvalues[i * F], F));
      continue;
    }
    ++ok_rows;
    expect_row_equals(b, i, r);
    EXPECT_TRUE(same_bits(&b.eigenvalues[i * F], r.eigen.values.data(), F));
  }
}

template <class Pair, class Scalar> void check_kind(int& ok_rows) {
  const int n = 40;
  const std::vector<Scalar> x = pairs<Scalar>(Pair::dofs, n, 7);
  const pce::QuadraticPenalty quadratic{10.0, 0.2};
  const pce::CubicPenalty cubic{10.0, 0.2, 1e-3};
  const pce::LogBarrierPenalty barrier{10.0, 0.2};
  for (pce::Projection p : kStrategies) {
    check_against_evaluate<Pair>(x, n, pce::UnsignedLength{}, quadratic, p, ok_rows);
    check_against_evaluate<Pair>(x, n, pce::UnsignedLength{}, cubic, p, ok_rows);
    check_against_evaluate<Pair>(x, n, pce::UnsignedLength{}, barrier, p, ok_rows);
    if constexpr (Pair::dofs == 12) {
      check_against_evaluate<Pair>(x, n, pce::SignedLength{pce::Side::negative}, quadratic, p, ok_rows);
      check_against_evaluate<Pair>(x, n, pce::SignedLength{pce::Side::positive}, barrier, p, ok_rows);
    }
  }
}

template <class Scalar> void check_all_kinds() {
  int ok_rows = 0;
  check_kind<pce::VertexFace, Scalar>(ok_rows);
  check_kind<pce::EdgeEdge, Scalar>(ok_rows);
  check_kind<pce::PointEdge, Scalar>(ok_rows);
  check_kind<pce::PointPoint, Scalar>(ok_rows);
  EXPECT_GT(ok_rows, 1000);  // the comparison saw real values, not only NaN rows
}

TEST(EvaluateBatch, RowsEqualEvaluateBitForBitDouble) { check_all_kinds<double>(); }
TEST(EvaluateBatch, RowsEqualEvaluateBitForBitFloat) { check_all_kinds<float>(); }

/// The outputs `evaluate_lanes` computes (no eigenvalues; `none`, `analytic` or `abs`), so the
/// batch runs a packet at a time: every row against `evaluate`, bit for bit, on a batch whose
/// count is not a multiple of the packet width and whose hard rows (degenerate, NaN, huge,
/// tiny or huge but valid primitives that need rescaling, a vertex on the plane) fall in
/// different lanes, so that lanes of one packet take different paths.
template <class Pair, class Scalar> void check_vectorised(int& ok_rows) {
  constexpr int D = 12;
  const int n = 45;
  std::vector<Scalar> x = pairs<Scalar>(D, n, 17);
  const auto row = [&](int i) { return x.data() + static_cast<std::ptrdiff_t>(i) * D; };
  for (int c = 0; c < D; ++c) row(9)[c] *= Scalar(std::ldexp(1.0, -40));  // rescaled (float and double)
  for (int c = 0; c < D; ++c) row(14)[c] *= Scalar(std::ldexp(1.0, 40));
  for (int c = 0; c < D; ++c) row(20)[c] *= Scalar(std::ldexp(1.0, -135));  // rescaled in double only
  for (int j = 0; j < 3; ++j) row(27)[6 + j] = row(27)[3 + j];              // degenerate
  row(30)[11] = std::numeric_limits<Scalar>::infinity();
  for (int j = 0; j < 3; ++j) row(33)[j] = (row(33)[3 + j] + row(33)[6 + j]) / Scalar(2);  // on an edge: l = 0
  const pce::QuadraticPenalty quadratic{10.0, 0.2};
  const pce::LogBarrierPenalty barrier{10.0, 0.2};
  const pce::Projection strategies[] = {pce::Projection::none, pce::Projection::analytic, pce::Projection::abs};
  for (pce::Projection p : strategies) {
    const auto check = [&](const auto& length, const auto& penalty) {
      Buffers<Scalar> b(n, D, 9);
      pce::BatchOutput<Scalar> out = b.all();
      out.eigenvalues = nullptr;
      pce::evaluate_batch<Pair>(x.data(), static_cast<std::size_t>(n), length, penalty, p, out);
      for (int i = 0; i < n; ++i) {
        SCOPED_TRACE(::testing::Message() << Pair::name << " row " << i << " " << pce::to_string(p));
        pce::PairResult<Scalar, D, 9> r;
        const pce::Status s = pce::evaluate<Pair>(pce::Vec12<Scalar>(Eigen::Map<const pce::Vec12<Scalar>>(row(i))),
                                                  length, penalty, p, r);
        ASSERT_EQ(b.status[i], s);
        if (s != pce::Status::ok) {
          EXPECT_TRUE(std::isnan(b.value[i]) && all_nan(&b.projected[i * D * D], D * D));
          continue;
        }
        ++ok_rows;
        expect_row_equals(b, i, r);
      }
    };
    check(pce::UnsignedLength{}, quadratic);
    check(pce::UnsignedLength{}, barrier);
    check(pce::SignedLength{pce::Side::negative}, quadratic);
    check(pce::SignedLength{pce::Side::positive}, barrier);
  }
}

TEST(EvaluateBatch, VectorisedRowsEqualEvaluateBitForBit) {
  // x86-64 always has SSE2, so these run two doubles or four floats per packet
  EXPECT_GE(pce::lanes_width<double>, 2);
  EXPECT_GE(pce::lanes_width<float>, 4);
  int ok_rows = 0;
  check_vectorised<pce::VertexFace, double>(ok_rows);
  check_vectorised<pce::EdgeEdge, double>(ok_rows);
  check_vectorised<pce::VertexFace, float>(ok_rows);
  check_vectorised<pce::EdgeEdge, float>(ok_rows);
  EXPECT_GT(ok_rows, 1000);
}

/// Rows of wildly different sizes (coordinates ±10^[−40, 40], zeros, repeated points, a point
/// on the plane, ∞ and NaN), so that lanes of one packet take every path: each row bit for bit
/// `evaluate`'s, in float and double.
template <class Pair, class Scalar> void check_hard_mix(int& ok_rows) {
  constexpr int D = 12;
  const int n = 2003;
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0), ex(-40.0, 40.0), pick(0.0, 1.0);
  std::vector<Scalar> x(static_cast<std::size_t>(n * D));
  for (int i = 0; i < n; ++i) {
    Scalar* r = x.data() + static_cast<std::ptrdiff_t>(i) * D;
    const double scale = std::pow(10.0, pick(rng) < 0.5 ? 0.0 : ex(rng));
    for (int c = 0; c < D; ++c) r[c] = static_cast<Scalar>(u(rng) * scale);
    const double what = pick(rng);
    if (what < 0.03)
      r[5] = Scalar(0);
    else if (what < 0.06)
      for (int j = 0; j < 3; ++j) r[6 + j] = r[3 + j];
    else if (what < 0.08)
      r[9] = std::numeric_limits<Scalar>::infinity();
    else if (what < 0.10)
      r[2] = std::numeric_limits<Scalar>::quiet_NaN();
    else if (what < 0.13)
      for (int j = 0; j < 3; ++j) r[j] = r[3 + j] + (r[6 + j] - r[3 + j]) / Scalar(3);
    else if (what < 0.25) {  // a sliver or nearly parallel edges, within rounding of each other:
      // n̂ then needs a second Gram–Schmidt pass, or the frame does not exist
      const double tiny = scale * std::pow(10.0, -2.0 - 16.0 * pick(rng));
      const int from = std::is_same_v<Pair, pce::VertexFace> ? 3 : 6;  // t0 (VF) or eb0 (EE)
      const int dir0 = std::is_same_v<Pair, pce::VertexFace> ? 3 : 0, dir1 = dir0 + 3;
      for (int j = 0; j < 3; ++j)
        r[9 + j] = static_cast<Scalar>(r[from + j] + 0.37 * (r[dir1 + j] - r[dir0 + j]) + tiny * (j + 1));
    }
  }
  const pce::QuadraticPenalty quadratic{1.0, 0.5};
  for (pce::Projection p : {pce::Projection::analytic, pce::Projection::abs}) {
    Buffers<Scalar> b(n, D, 9);
    pce::BatchOutput<Scalar> out = b.all();
    out.eigenvalues = nullptr;
    pce::evaluate_batch<Pair>(x.data(), static_cast<std::size_t>(n), pce::UnsignedLength{}, quadratic, p, out);
    for (int i = 0; i < n; ++i) {
      pce::PairResult<Scalar, D, 9> r;
      const pce::Status s = pce::evaluate<Pair>(
          pce::Vec12<Scalar>(Eigen::Map<const pce::Vec12<Scalar>>(x.data() + static_cast<std::ptrdiff_t>(i) * D)),
          pce::UnsignedLength{}, quadratic, p, r);
      ASSERT_EQ(b.status[i], s) << Pair::name << " row " << i;
      if (s != pce::Status::ok) continue;
      ++ok_rows;
      SCOPED_TRACE(::testing::Message() << Pair::name << " row " << i << " " << pce::to_string(p));
      expect_row_equals(b, i, r);
    }
  }
}

TEST(EvaluateBatch, VectorisedHardMixEqualsEvaluateBitForBit) {
  int ok_rows = 0;
  check_hard_mix<pce::VertexFace, double>(ok_rows);
  check_hard_mix<pce::EdgeEdge, double>(ok_rows);
  check_hard_mix<pce::VertexFace, float>(ok_rows);
  check_hard_mix<pce::EdgeEdge, float>(ok_rows);
  EXPECT_GT(ok_rows, 8000);
}

TEST(EvaluateBatch, StatusesOfHardRows) {
  const std::vector<double> x = pairs<double>(12, 4, 3);
  std::vector<pce::Status> status(4);
  pce::BatchOutput<double> out;
  out.status = status.data();
  pce::evaluate_batch<pce::VertexFace>(x.data(), 4, pce::UnsignedLength{}, pce::LogBarrierPenalty{1.0, 10.0},
                                       pce::Projection::analytic, out);
  EXPECT_EQ(status[0], pce::Status::degenerate);
  EXPECT_EQ(status[1], pce::Status::invalid_input);
  EXPECT_EQ(status[2], pce::Status::invalid_input);
  EXPECT_EQ(status[3], pce::Status::ok);
  // The signed barrier on the negative side: half of random pairs are behind the face.
  std::vector<double> y = pairs<double>(12, 64, 5);
  std::vector<pce::Status> s2(64);
  out.status = s2.data();
  pce::evaluate_batch<pce::VertexFace>(y.data(), 64, pce::SignedLength{pce::Side::positive},
                                       pce::LogBarrierPenalty{1.0, 10.0}, pce::Projection::analytic, out);
  int out_of_domain = 0;
  for (pce::Status s : s2) out_of_domain += s == pce::Status::out_of_domain;
  EXPECT_GT(out_of_domain, 10);
}

TEST(EvaluateBatch, NullOutputsAreSkippedAndTheOthersUnchanged) {
  const int n = 16;
  const std::vector<double> x = pairs<double>(12, n, 11);
  const pce::QuadraticPenalty q{1.0, 0.5};
  Buffers<double> full(n, 12, 9);
  pce::evaluate_batch<pce::EdgeEdge>(x.data(), n, pce::UnsignedLength{}, q, pce::Projection::exact, full.all());
  std::vector<double> value(n), projected(n * 144, 7.0);
  pce::BatchOutput<double> some;
  some.value = value.data();
  some.projected = projected.data();
  pce::evaluate_batch<pce::EdgeEdge>(x.data(), n, pce::UnsignedLength{}, q, pce::Projection::exact, some);
  EXPECT_TRUE(same_bits(value.data(), full.value.data(), n) || n == 0);
  for (int i = 0; i < n; ++i) {
    if (full.status[i] != pce::Status::ok) continue;
    EXPECT_TRUE(same_bits(&value[i], &full.value[i], 1));
    EXPECT_TRUE(same_bits(&projected[i * 144], &full.projected[i * 144], 144));
  }
}

/// Closest features against `closest_feature_energy` and the ClosestFeatureEnergy overloads.
template <class Pair, class Scalar> void check_closest(int& seen_features) {
  const int n = 200;
  const std::vector<Scalar> x = pairs<Scalar>(12, n, 13);
  const pce::QuadraticPenalty q{3.0, 0.25};
  for (pce::Projection p : kStrategies) {
    Buffers<Scalar> b(n, 12, 9);
    pce::closest_feature_batch<Pair>(x.data(), n, q, p, b.all());
    for (int i = 0; i < n; ++i) {
      const pce::Vec12<Scalar> xi = Eigen::Map<const pce::Vec12<Scalar>>(x.data() + i * 12);
      pce::ClosestFeatureEnergy<Scalar> e;
      const pce::Status s = pce::closest_feature_energy<Pair>(xi, pce::UnsignedLength{}, q, e);
      ASSERT_EQ(b.status[i], s) << "row " << i;
      if (s != pce::Status::ok) {
        EXPECT_TRUE(std::isnan(b.value[i]) && all_nan(&b.projected[i * 144], 144));
        continue;
      }
      seen_features |= 1 << static_cast<int>(e.feature);
      EXPECT_EQ(b.feature[i], e.feature);
      const Eigen::Matrix<Scalar, 12, 12, Eigen::RowMajor> H = pce::energy_hessian(e);
      const Eigen::Matrix<Scalar, 12, 12, Eigen::RowMajor> P =
          p == pce::Projection::none ? pce::energy_hessian(e) : pce::projected_hessian(e, p);
      const pce::Vec12<Scalar> g = pce::energy_gradient(e);
      const pce::FeatureEigenvalues<Scalar> ev = pce::feature_eigenvalues(e);
      EXPECT_TRUE(same_bits(&b.value[i], &e.psi.value, 1));
      EXPECT_TRUE(same_bits(&b.length[i], &e.length, 1));
      EXPECT_TRUE(same_bits(&b.gradient[i * 12], g.data(), 12));
      EXPECT_TRUE(same_bits(&b.hessian[i * 144], H.data(), 144));
      EXPECT_TRUE(same_bits(&b.projected[i * 144], P.data(), 144));
      EXPECT_TRUE(same_bits(&b.eigenvalues[i * 9], ev.values.data(), ev.count));
      EXPECT_TRUE(all_nan(&b.eigenvalues[i * 9 + ev.count], 9 - ev.count));
    }
  }
}

TEST(EvaluateBatch, ClosestFeaturesEqualTheSinglePairFunctions) {
  int seen = 0;
  check_closest<pce::VertexFace, double>(seen);
  check_closest<pce::EdgeEdge, double>(seen);
  check_closest<pce::VertexFace, float>(seen);
  check_closest<pce::EdgeEdge, float>(seen);
  EXPECT_EQ(seen, 0xF);  // point_plane, line_line, point_edge and point_point all occurred
}

}  // namespace
