// SPDX-License-Identifier: MIT
// Tests for tests/support/naive_forms.hpp, the paper's direct forms that make the "before"
// column of docs/stability.md: on benign configurations they must be *right* (they are the
// paper's exact formulas, only evaluated the direct way), so that the before/after table
// compares formulations, not a strawman with the library.
//  * value, gradient and exact Hessian agree with the library to ~1e-12 in double, for both
//    pair kinds, all three lengths and all four penalty kinds;
//  * the gradient and Hessian (including the unsigned del term) agree with central
//    differences of the naive value and gradient in long double;
//  * Σλqqᵀ from the paper's eigenpairs reassembles the library's H_l blocks;
//  * where docs/stability.md says the direct forms break (e2⊥ = 0 exactly, exactly
//    parallel edges), they do report it.
#include "support/conformance.hpp"
#include "support/naive_forms.hpp"

#include <gtest/gtest.h>

namespace {
using namespace pce_test;

const LengthKind kLengths[] = {LengthKind::signed_positive, LengthKind::signed_negative, LengthKind::unsigned_};
const PairKind kPairs[] = {PairKind::vertex_face, PairKind::edge_edge};

/// Active penalties for |L| < 1; the barrier needs 0 < L < d̂ = 1.
std::vector<PenaltySpec> penalties() {
  return {{PenaltyKind::quadratic, 2.0, 1.0, 0, 0, 0},
          {PenaltyKind::cubic, 1.5, 1.0, 0.01, 0, 0},
          {PenaltyKind::log_barrier, 1.0, 0, 0, 1.0, 0},
          {PenaltyKind::custom, 1.0, 0, 0, 0, 0.7}};
}

/// Signed lengths l of benign configurations for which L lies in (0, 1) (barrier) or (−1, 1).
std::vector<double> lengths_for(LengthKind len, PenaltyKind pen) {
  if (pen != PenaltyKind::log_barrier) return {-0.6, -0.25, 0.3, 0.8};
  if (len == LengthKind::signed_positive) return {0.25, 0.6};
  if (len == LengthKind::signed_negative) return {-0.25, -0.6};
  return {-0.6, -0.25, 0.3, 0.8};
}

template <class S> struct Library {
  pce::Status status;
  S value;
  pce::Vec12<S> gradient;
  pce::Mat12<S> hessian;
  pce::Frame<S> frame;
};

template <class S>
Library<S> library(PairKind kind, LengthKind length, const PenaltySpec& spec, const pce::Vec12<S>& x) {
  Library<S> r{};
  with_pair(kind, [&](auto pair) {
    using Pair = decltype(pair);
    with_length(length, [&](const auto& len) {
      with_penalty(spec, [&](const auto& pen) {
        pce::PairEnergy<S> e;
        r.status = pce::pair_energy<Pair>(x, len, pen, e);
        if (r.status != pce::Status::ok) return 0;
        r.value = e.psi.value;
        r.gradient = pce::energy_gradient(e);
        r.hessian = pce::energy_hessian(e);
        r.frame = e.frame;
        return 0;
      });
      return 0;
    });
    return 0;
  });
  return r;
}

TEST(NaiveForms, AgreeWithTheLibraryOnBenignConfigurations) {
  std::mt19937_64 rng(71);
  int checked = 0;
  for (PairKind kind : kPairs)
    for (LengthKind len : kLengths)
      for (const PenaltySpec& pen : penalties())
        for (double l : lengths_for(len, pen.kind))
          for (double offset : {0.0, 3.0}) {
            const pce::Vec12<double> x = random_configuration(kind, l, 1, offset, rng).x;
            SCOPED_TRACE(testing::Message() << name(kind) << " " << name(len) << " " << name(pen.kind) << " l = " << l
                                            << " offset " << offset);
            const Library<double> lib = library(kind, len, pen, x);
            ASSERT_EQ(lib.status, pce::Status::ok);
            const NaiveOutputs<double> nv = naive_pair_energy(kind, len, pen, x);
            ASSERT_TRUE(nv.ok);
            EXPECT_NEAR(nv.value, lib.value, 1e-12 * std::max(1.0, std::fabs(lib.value)));
            EXPECT_LT(rel_error(nv.gradient, lib.gradient), 1e-12);
            EXPECT_LT(rel_error(nv.hessian, lib.hessian), 1e-11);
            ++checked;
          }
  EXPECT_GT(checked, 100);
}

/// The naive outputs are consistent derivatives of the naive value (long double, central
/// differences): checks the del term of the unsigned Hessian independently of the library.
TEST(NaiveForms, DerivativesMatchFiniteDifferences) {
  using LD = long double;
  std::mt19937_64 rng(72);
  for (PairKind kind : kPairs)
    for (LengthKind len : kLengths)
      for (const PenaltySpec& pen : penalties())
        for (double l : lengths_for(len, pen.kind)) {
          const pce::Vec12<LD> x = cast12<LD>(random_configuration(kind, l, 1, 0.5, rng).x);
          SCOPED_TRACE(testing::Message() << name(kind) << " " << name(len) << " " << name(pen.kind) << " l = " << l);
          const NaiveOutputs<LD> nv = naive_pair_energy(kind, len, pen, x);
          ASSERT_TRUE(nv.ok);
          const LD h = 1e-6L;
          const pce::Vec12<LD> gfd =
              fd_gradient([&](const pce::Vec12<LD>& y) { return naive_pair_energy(kind, len, pen, y).value; }, x, h);
          const pce::Mat12<LD> Hfd =
              fd_jacobian([&](const pce::Vec12<LD>& y) { return naive_pair_energy(kind, len, pen, y).gradient; }, x, h);
          EXPECT_LT(rel_error(nv.gradient, gfd), 1e-9);
          EXPECT_LT(rel_error(nv.hessian, Hfd), 1e-9);
        }
}

/// The unsigned del term is not negligible in benign cases: without it the norm form's
/// Hessian is wrong. (So the "before" unsigned Hessian really is frame term + del term.)
TEST(NaiveForms, UnsignedDelTermIsNeeded) {
  std::mt19937_64 rng(73);
  for (PairKind kind : kPairs) {
    const pce::Vec12<double> x = random_configuration(kind, 0.3, 1, 0, rng).x;
    const naive::Geometry<double> g = naive::geometry(kind, x);
    const double u = g.c2.norm();
    const pce::Mat12<double> del = naive::unsigned_del_term(g, g.c2, u);
    const Library<double> lib = library(kind, LengthKind::unsigned_, {PenaltyKind::quadratic, 0.5, 1.0, 0, 0, 0}, x);
    ASSERT_EQ(lib.status, pce::Status::ok);
    // ∇²E = ψ″∇u∇uᵀ + ψ′∇²u with k = 0.5: ψ″ = 1, ψ′ = u − 1.
    EXPECT_GT(max_abs(del), 0.1 * max_abs(lib.hessian));
  }
}

/// Rows 5–7: Σλqqᵀ over the paper's eigenpairs equals the library's block form of H_l.
TEST(NaiveForms, EigenpairsReassembleTheLengthHessian) {
  using LD = long double;
  std::mt19937_64 rng(74);
  for (PairKind kind : kPairs)
    for (double l : {-0.7, -0.05, 0.2, 1.5}) {
      const pce::Vec12<LD> x = cast12<LD>(random_configuration(kind, l, 1, 0, rng).x);
      const naive::Geometry<LD> g = naive::geometry(kind, x);
      bool ok = true;
      const pce::Mat9<LD> Hl = naive::length_hessian_from_eigenpairs(g, ok);
      ASSERT_TRUE(ok);
      pce::Frame<LD> f;
      ASSERT_EQ(with_pair(kind, [&](auto p) { return decltype(p)::frame(x, f); }), pce::Status::ok);
      const pce::Mat9<LD> ref = pce::detail::frame_hessian_blocks(f, LD(1), LD(0)).dense();
      EXPECT_LT(rel_error(Hl, ref), 1e-15) << "l = " << l;
      // The reassembled matrix is symmetric with the paper's spectrum: trace −l(1/a0² + 1/a1²).
      EXPECT_NEAR(double(Hl.trace()), double(-f.l * (1 / (f.a0 * f.a0) + 1 / (f.a1 * f.a1))), 1e-15);
    }
}

/// Plain log(L/d̂) vs log1p: equal where both are accurate.
TEST(NaiveForms, PlainBarrierMatchesTheLibraryAwayFromDhat) {
  const pce::LogBarrierPenalty p{2.0, 0.5};
  for (double L : {1e-6, 0.01, 0.2, 0.3, 0.45}) {
    const auto a = naive::penalty<double>(p, L), b = p.evaluate<double>(L);
    EXPECT_NEAR(a.value, b.value, 1e-13 * std::max(1.0, std::fabs(b.value)));
    EXPECT_NEAR(a.first, b.first, 1e-13 * std::max(1.0, std::fabs(b.first)));
    EXPECT_NEAR(a.second, b.second, 1e-13 * std::max(1.0, std::fabs(b.second)));
  }
  EXPECT_EQ(naive::penalty<double>(p, 0.5).value, 0.0);
  EXPECT_FALSE(std::isfinite(naive::penalty<double>(p, 0.0).value));
}

/// Row 9 in isolation: at an exactly known L with L/d̂ = 1 − 1e-12 (d̂ = 0.3, so L/d̂ rounds)
/// the plain logarithm loses ~12 digits of ψ and ψ″ and log1p does not. (Inside a pair
/// energy L carries the rounding of the coordinates, which costs as much:
/// docs/stability.md, "Measured: before and after".)
TEST(NaiveForms, PlainBarrierLosesDigitsNearDhatInIsolation) {
  const pce::LogBarrierPenalty p{1.0, 0.3};
  const double L = 0.3 * (1 - 1e-12);
  const auto ref = p.evaluate<long double>(static_cast<long double>(L));
  const auto plain = naive::penalty<double>(p, L), stable = p.evaluate<double>(L);
  const auto rel = [](double a, long double b) { return double(std::fabs((a - b) / b)); };
  EXPECT_GT(rel(plain.value, ref.value), 1e-7);
  EXPECT_LT(rel(stable.value, ref.value), 1e-14);
  EXPECT_GT(rel(plain.second, ref.second), 1e-7);
  EXPECT_LT(rel(stable.second, ref.second), 1e-14);
}

/// Row 10: without rescaling the Gram determinant (~x⁴) overflows above ~1e77 and
/// underflows below ~1e-78, at scales the library still handles.
TEST(NaiveForms, OverflowAndUnderflowWithoutRescaling) {
  using V = Eigen::Vector3d;
  for (double s : {1e78, 1e-80, 1e-85}) {
    pce::Vec12<double> x;
    x << s * V(0.3, 0.3, 0.1), s * V(0, 0, 0), s * V(1, 0, 0), s * V(0.3, 0.9, 0);
    const PenaltySpec pen{PenaltyKind::quadratic, 1.0, 0.5 * s, 0, 0, 0};
    const Library<double> lib = library(PairKind::vertex_face, LengthKind::signed_positive, pen, x);
    ASSERT_EQ(lib.status, pce::Status::ok) << s;
    EXPECT_TRUE(pce::detail::all_finite(lib.gradient) && pce::detail::all_finite(lib.hessian)) << s;
    const NaiveOutputs<double> nv = naive_pair_energy(PairKind::vertex_face, LengthKind::signed_positive, pen, x);
    if (s == 1e-80) {  // subnormal Gram determinant: finite, but only a few digits
      ASSERT_TRUE(nv.ok);
      EXPECT_GT(rel_error(nv.gradient, lib.gradient), 1e-5);
    } else {
      EXPECT_FALSE(nv.gradient_ok) << s;
    }
  }
}

/// Where docs/stability.md (rows 1, 3, 5) says the direct forms fail outright, they report it.
TEST(NaiveForms, ReportDivisionsByZeroOfTheDirectForms) {
  using V = Eigen::Vector3d;
  const PenaltySpec quad{PenaltyKind::quadratic, 1.0, 1.0, 0, 0, 0};
  // Vertex exactly on a corner: e2 = e2⊥ = 0, l = 0. The eigenvalues are 0·∞ (row 5), the
  // unsigned gradient direction 0/0 (row 3); the values themselves exist.
  pce::Vec12<double> corner;
  corner << V(0.2, 0.1, 0.3), V(0.2, 0.1, 0.3), V(1.2, 0.1, 0.3), V(0.5, 1.0, 0.3);
  const NaiveOutputs<double> s = naive_pair_energy(PairKind::vertex_face, LengthKind::signed_positive, quad, corner);
  EXPECT_TRUE(s.value_ok);
  EXPECT_FALSE(s.hessian_ok);
  EXPECT_FALSE(s.ok);
  const NaiveOutputs<double> u = naive_pair_energy(PairKind::vertex_face, LengthKind::unsigned_, quad, corner);
  EXPECT_TRUE(u.value_ok);
  EXPECT_EQ(u.value, 1.0);
  EXPECT_FALSE(u.gradient_ok);
  // The library is fine there (λ = ∓1/a at l = 0).
  const Library<double> lib = library(PairKind::vertex_face, LengthKind::signed_positive, quad, corner);
  EXPECT_EQ(lib.status, pce::Status::ok);
  EXPECT_TRUE(pce::detail::all_finite(lib.hessian));
  // Exactly parallel edges: Gram determinant 0 (row 1).
  pce::Vec12<double> par;
  par << V(-1, 0, 0), V(1, 0, 0), V(-1, 0.3, 0.1), V(1, 0.3, 0.1);
  EXPECT_FALSE(naive_pair_energy(PairKind::edge_edge, LengthKind::signed_positive, quad, par).ok);
  EXPECT_FALSE(naive_pair_energy(PairKind::edge_edge, LengthKind::unsigned_, quad, par).ok);
}

}  // namespace
