// SPDX-License-Identifier: MIT
// Conformance suite for energy/pair_energy.hpp: one set of checks run on every
// pair × length × penalty × scalar combination, at random well-shaped configurations over
// several scales and offsets. For each configuration:
//   - central finite differences (several step sizes) of value -> gradient -> Hessian
//     (double and long double; float is checked against the high-precision reference);
//   - agreement with the same templated code instantiated in 50-digit binary floating point;
//   - closed-form eigenpairs: residual ‖Hq − λq‖, orthonormality, reconstruction QΛQᵀ,
//     ascending order, agreement with a numerical eigensolver;
//   - every projection strategy: PSD, symmetric, and equal to an independent dense
//     construction of what docs/math.md says it is;
//   - invariance under rigid motions (double).
#include "support/conformance.hpp"
#include "support/high_precision.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <sstream>
#include <tuple>
#include <type_traits>

// This file is compiled twice (tests/CMakeLists.txt), once per pair kind, so that the two
// halves of the suite build in parallel: PCE_CONFORMANCE_PAIR 0 = vertex-face, 1 = edge-edge.
#ifndef PCE_CONFORMANCE_PAIR
#define PCE_CONFORMANCE_PAIR 0
#endif

namespace {

using namespace pce_test;
using HP = HighPrecision;
using SuitePair = std::conditional_t<PCE_CONFORMANCE_PAIR == 0, pce::VertexFace, pce::EdgeEdge>;
constexpr PairKind kSuitePair = PCE_CONFORMANCE_PAIR == 0 ? PairKind::vertex_face : PairKind::edge_edge;

enum class ScalarKind { float_, double_, long_double };
const char* name(ScalarKind s) {
  return s == ScalarKind::float_ ? "float" : s == ScalarKind::double_ ? "double" : "long_double";
}

struct Combo {
  PairKind pair;
  LengthKind length;
  PenaltyKind penalty;
  ScalarKind scalar;
};

std::string combo_name(const testing::TestParamInfo<Combo>& info) {
  std::ostringstream s;
  s << name(info.param.pair) << "_" << name(info.param.length) << "_" << name(info.param.penalty) << "_"
    << name(info.param.scalar);
  return s.str();
}

/// Tolerances per scalar: multiples of the unit roundoff, for well-shaped configurations.
template <class S> struct Tol {
  static double eps() { return static_cast<double>(std::numeric_limits<S>::epsilon()); }
  static double reference() { return 2e3 * eps(); }  // vs 50-digit evaluation of the same code
  static double algebra() { return 200 * eps(); }    // eigen residuals, reconstructions
};

/// Draws one active configuration and penalty for a combination.
struct Case {
  Configuration config;
  PenaltySpec penalty;
};

Case draw_case(const Combo& c, double scale, double offset, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> U(0, 1);
  const double mag = scale * (0.05 + 0.9 * U(rng));
  double sign = U(rng) < 0.5 ? -1.0 : 1.0;
  const double side = c.length == LengthKind::signed_negative ? -1.0 : 1.0;
  if (c.penalty == PenaltyKind::log_barrier && c.length != LengthKind::unsigned_) sign = side;  // keep L > 0
  const double l = sign * mag;
  const double L = c.length == LengthKind::unsigned_ ? mag : side * l;
  PenaltySpec p{c.penalty, 0.5 + 5 * U(rng), 0, 0, 0, 0};
  p.eps = L + scale * (0.2 + U(rng));  // active, with a margin for finite differences
  p.delta = U(rng) < 0.25 ? 0.0 : scale * scale * U(rng);
  p.dhat = L * (1.3 + 2 * U(rng));
  p.width = scale * (0.5 + U(rng));
  return {random_configuration(c.pair, l, scale, offset, rng), p};
}

/// Independent dense construction of a strategy from the numerical eigensystem of the
/// 9×9 frame Hessian: Jᵀ f(Hc) J.
template <class S, class F> pce::Mat12<S> dense_filtered(const pce::PairEnergy<S>& e, F f) {
  const pce::Mat9<S> Hc = pce::energy_frame_hessian(e).dense();
  const SymmetricEigen<S, 9> es = symmetric_eigen(Hc);
  pce::Vec9<S> lam = es.values;
  for (int i = 0; i < 9; ++i) lam[i] = f(lam[i]);
  const pce::Mat9<S> Hf = es.vectors * lam.asDiagonal() * es.vectors.transpose();
  const Eigen::Matrix<S, 9, 12> J = pce::frame_jacobian(e.frame);
  return J.transpose() * Hf * J;
}

class Conformance : public testing::TestWithParam<Combo> {};

// The checks below depend only on the evaluated energy, so they are templated on the
// scalar alone: compiled 3 times per executable instead of once per length × penalty ×
// scalar (24), which is most of this file's compile time.

/// How `exact` compared with `numerical` over the suite (printed by each test).
struct ExactTally {
  int compared = 0, numerical_inaccurate = 0;
  double worst = 0;
};
ExactTally& exact_tally() {
  static ExactTally t;
  return t;
}

/// `Projection::exact` is the nearest PSD matrix: it agrees with the 50-digit projection of
/// the 50-digit Hessian, and with `numerical` (relative Frobenius ≤ 1e-12 in double)
/// wherever `numerical` is itself accurate (within 1e3 roundoffs of that reference).
template <class S> void check_exact_against_numerical(const pce::PairEnergy<S>& e, const pce::PairEnergy<HP>& r) {
  const pce::Mat12<HP> ref = pce::project_psd(pce::energy_hessian(r));
  const auto frob = [&](const pce::Mat12<S>& a) {
    HP num = 0, den = 0;
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) {
        num += (HP(a(i, j)) - ref(i, j)) * (HP(a(i, j)) - ref(i, j));
        den += ref(i, j) * ref(i, j);
      }
    return static_cast<double>(sqrt(num / den));
  };
  const pce::Mat12<S> Px = pce::projected_hessian(e, pce::Projection::exact);
  const pce::Mat12<S> Pn = pce::projected_hessian(e, pce::Projection::numerical);
  const double eps = static_cast<double>(std::numeric_limits<S>::epsilon());
  EXPECT_LT(frob(Px), 1e3 * eps) << "exact vs the 50-digit projection";
  if (frob(Pn) < 1e3 * eps) {
    const double d = static_cast<double>((Px - Pn).norm() / Pn.norm());
    if (std::is_same_v<S, double>) {
      EXPECT_LE(d, 1e-12) << "exact vs numerical";
    }
    EXPECT_LE(d, 2e3 * eps) << "exact vs numerical";
    ++exact_tally().compared;
    exact_tally().worst = std::max(exact_tally().worst, d / eps);
  } else {
    ++exact_tally().numerical_inaccurate;
  }
}

/// 1. The same code in 50 digits (`r`, evaluated at exactly the input `e` saw).
template <class S> void check_against_reference(const pce::PairEnergy<S>& e, const pce::PairEnergy<HP>& r) {
  const double tol = Tol<S>::reference();
  EXPECT_LT(std::fabs(static_cast<double>(HP(e.length) - r.length)) / static_cast<double>(abs(r.length)), tol);
  EXPECT_LT(std::fabs(static_cast<double>(HP(e.psi.value) - r.psi.value)) /
                std::max(1e-300, std::fabs(static_cast<double>(r.psi.value))),
            tol);
  EXPECT_LT(rel_error(pce::energy_gradient(e), pce::energy_gradient(r)), tol) << "gradient vs high precision";
  EXPECT_LT(rel_error(pce::energy_hessian(e), pce::energy_hessian(r)), tol) << "Hessian vs high precision";
  EXPECT_LT(rel_error(pce::projected_hessian(e, pce::Projection::analytic),
                      pce::projected_hessian(r, pce::Projection::analytic)),
            tol)
      << "analytic projection vs high precision";
  EXPECT_LT(rel_error(pce::energy_eigensystem(e).values, pce::energy_eigensystem(r).values), tol)
      << "eigenvalues vs high precision";
  EXPECT_LT(
      rel_error(pce::projected_hessian(e, pce::Projection::exact), pce::projected_hessian(r, pce::Projection::exact)),
      tol)
      << "exact projection vs high precision";
  check_exact_against_numerical(e, r);
}

/// 3.–5. Pullback, closed-form eigensystem and projection strategies of one energy;
/// `gL` is the length gradient ∇L (for the Gauss–Newton check).
template <class S> void check_energy_algebra(const pce::PairEnergy<S>& e, const pce::Vec12<S>& gL) {
  const pce::Mat12<S> H = pce::energy_hessian(e);
  const double Hn = max_abs(H);

  // --- 3. The exact Hessian is Jᵀ Hc J with the frame Jacobian (dense check of `pullback`).
  const pce::Mat9<S> Hc = pce::energy_frame_hessian(e).dense();
  {
    const Eigen::Matrix<S, 9, 12> J = pce::frame_jacobian(e.frame);
    EXPECT_LT(rel_error(H, (J.transpose() * Hc * J).eval()), Tol<S>::algebra());
    EXPECT_LT(rel_error(H, H.transpose().eval()), Tol<S>::algebra()) << "exact Hessian symmetric";
  }

  // --- 4. Closed-form eigensystem of the frame Hessian.
  {
    const pce::FrameEigensystem<S> es = pce::energy_eigensystem(e);
    const double Hcn = std::max(max_abs(Hc), 1e-300);
    const double tol = Tol<S>::algebra();
    for (int i = 0; i < 9; ++i) {
      const pce::Vec9<S> res = Hc * es.vectors.col(i) - es.values[i] * es.vectors.col(i);
      EXPECT_LT(max_abs(res) / Hcn, tol) << "eigenpair residual " << i;
      if (i > 0) {
        EXPECT_LE(es.values[i - 1], es.values[i]) << "eigenvalues ascending";
      }
    }
    EXPECT_LT(max_abs((es.vectors.transpose() * es.vectors - pce::Mat9<S>::Identity()).eval()), tol)
        << "orthonormal eigenvectors";
    EXPECT_LT(max_abs((es.vectors * es.values.asDiagonal() * es.vectors.transpose() - Hc).eval()) / Hcn, tol)
        << "reconstruction QΛQᵀ";
    EXPECT_LT(max_abs((symmetric_eigen(Hc).values - es.values).eval()) / Hcn, tol)
        << "closed-form vs numerical eigenvalues";
  }

  // --- 5. Projection strategies.
  {
    const double tol = 50 * Tol<S>::eps();
    const auto clamp = [](S v) { return v > S(0) ? v : S(0); };
    const auto flip = [](S v) { return v < S(0) ? S(-v) : v; };
    const pce::Mat12<S> Pa = pce::projected_hessian(e, pce::Projection::analytic);
    const pce::Mat12<S> Pb = pce::projected_hessian(e, pce::Projection::abs);
    const pce::Mat12<S> Pg = pce::projected_hessian(e, pce::Projection::gauss_newton);
    const pce::Mat12<S> Pn = pce::projected_hessian(e, pce::Projection::numerical);
    const pce::Mat12<S> Px = pce::projected_hessian(e, pce::Projection::exact);
    EXPECT_EQ(pce::projected_hessian(e, pce::Projection::none), H);
    const pce::Mat12<S>* all[5] = {&Pa, &Pb, &Pg, &Pn, &Px};
    const char* names[5] = {"analytic", "abs", "gauss_newton", "numerical", "exact"};
    for (int i = 0; i < 5; ++i) {
      const double n = std::max(max_abs(*all[i]), Hn);
      EXPECT_GE(min_eigenvalue(*all[i]), -tol * n * 12) << names[i] << " is PSD";
      EXPECT_LT(max_abs((*all[i] - all[i]->transpose()).eval()), tol * n) << names[i] << " symmetric";
    }
    const double Hd = std::max(Hn, 1e-300);
    EXPECT_LT(rel_error(Pa, dense_filtered(e, clamp)), Tol<S>::reference()) << "analytic = Jᵀ clamp(Hc) J";
    EXPECT_LT(rel_error(Pb, dense_filtered(e, flip)), Tol<S>::reference()) << "abs = Jᵀ |Hc| J";
    const S c2 = e.psi.second > S(0) ? e.psi.second : S(0);
    EXPECT_LT(rel_error(Pg, (c2 * gL * gL.transpose()).eval(), Hd), Tol<S>::algebra()) << "GN = ψ″⁺ ∇L∇Lᵀ";
    // analytic ⪰ exact, abs ⪰ analytic, numerical ⪰ exact (each difference is Jᵀ(PSD)J).
    EXPECT_GE(min_eigenvalue((Pa - H).eval()), -tol * Hd * 12) << "analytic - exact is PSD";
    EXPECT_GE(min_eigenvalue((Pb - Pa).eval()), -tol * Hd * 12) << "abs - analytic is PSD";
    EXPECT_GE(min_eigenvalue((Pn - H).eval()), -tol * Hd * 12) << "numerical - exact is PSD";
    EXPECT_GE(min_eigenvalue((Px - H).eval()), -tol * Hd * 12) << "exact projection - exact Hessian is PSD";
    // analytic is never closer to the Hessian than the nearest PSD matrix.
    EXPECT_LE(static_cast<double>((Px - H).norm()),
              static_cast<double>((Pa - H).norm()) * (1 + 1e3 * Tol<S>::eps()) + tol * Hd)
        << "exact is at least as close to the Hessian as analytic";
    // The nearest PSD matrix is a fixed point of the projection.
    EXPECT_LT(rel_error(pce::project_psd(Pn), Pn, Hd), 100 * tol) << "numerical projection idempotent";
  }
}

/// 6. evaluate() returns what the separate calls return.
template <class S> void check_result_matches(const pce::PairResult<S>& out, const pce::PairEnergy<S>& e) {
  EXPECT_EQ(out.value, e.psi.value);
  EXPECT_EQ(out.length, e.length);
  EXPECT_EQ(out.gradient, pce::energy_gradient(e));
  EXPECT_EQ(out.hessian, pce::energy_hessian(e));
  EXPECT_EQ(out.projected_hessian, pce::projected_hessian(e, pce::Projection::analytic));
}

/// 7. Rigid motions: `ey` is `e` evaluated at (R x + t); `B` = diag(R, R, R, R).
inline void check_rotated(const pce::PairEnergy<double>& e, const pce::PairEnergy<double>& ey,
                          const Eigen::Matrix<double, 12, 12>& B) {
  const double tol = 1e-9;
  const pce::Mat12<double> H = pce::energy_hessian(e);
  EXPECT_NEAR(ey.psi.value, e.psi.value, tol * std::fabs(e.psi.value)) << "value invariant";
  EXPECT_LT(rel_error(pce::energy_gradient(ey), (B * pce::energy_gradient(e)).eval()), tol) << "gradient rotates";
  EXPECT_LT(rel_error(pce::energy_hessian(ey), (B * H * B.transpose()).eval()), tol) << "Hessian rotates";
  const pce::Mat12<double> Pa = pce::projected_hessian(e, pce::Projection::analytic);
  EXPECT_LT(rel_error(pce::projected_hessian(ey, pce::Projection::analytic), (B * Pa * B.transpose()).eval()), tol)
      << "analytic projection rotates";
}

/// Every check on one case; only the evaluations that need the length and penalty types
/// are in this function.
template <class Pair, class S, class Length, class Penalty>
void check_case(const Combo& combo, const Case& cs, const Length& len, const Penalty& pen) {
  SCOPED_TRACE(testing::Message() << "x = " << cs.config.x.transpose() << ", scale " << cs.config.scale);
  const pce::Vec12<S> x = cast12<S>(cs.config.x);
  pce::PairEnergy<S> e;
  ASSERT_EQ(pce::pair_energy<Pair>(x, len, pen, e), pce::Status::ok);

  // --- 1. High-precision reference: the same code in 50 digits, at the same (rounded) input.
  {
    pce::PairEnergy<HP> r;
    ASSERT_EQ(pce::pair_energy<Pair>(cast12<HP>(x), len, pen, r), pce::Status::ok);
    check_against_reference(e, r);
  }

  // --- 2. Finite differences at several step sizes (best step counts), double and long double.
  if constexpr (!std::is_same_v<S, float>) {
    const auto value = [&](const pce::Vec12<S>& y) {
      pce::PairEnergy<S> ey;
      EXPECT_EQ(pce::pair_energy<Pair>(y, len, pen, ey), pce::Status::ok);
      return ey.psi.value;
    };
    const auto gradient = [&](const pce::Vec12<S>& y) {
      pce::PairEnergy<S> ey;
      EXPECT_EQ(pce::pair_energy<Pair>(y, len, pen, ey), pce::Status::ok);
      return pce::energy_gradient(ey);
    };
    const pce::Vec12<S> g = pce::energy_gradient(e);
    const pce::Mat12<S> H = pce::energy_hessian(e);
    const bool ld = std::is_same_v<S, long double>;
    const double steps[3] = {ld ? 1e-4 : 1e-3, ld ? 1e-5 : 1e-4, ld ? 1e-6 : 1e-5};
    double eg = 1e300, eh = 1e300;
    for (double h : steps) {
      const S hs = S(h * cs.config.scale);
      eg = std::min(eg, rel_error(fd_gradient<S>(value, x, hs), g));
      eh = std::min(eh, rel_error(fd_jacobian<S>(gradient, x, hs), H));
    }
    const double tol = ld ? 1e-8 : 1e-6;
    EXPECT_LT(eg, tol) << "gradient vs finite differences";
    EXPECT_LT(eh, tol) << "Hessian vs finite differences";
  }

  // --- 3.–5.
  check_energy_algebra(e, pce::pullback(e.frame, pce::length_gradient(e.frame, len)));

  // --- 6.
  {
    pce::PairResult<S> out;
    ASSERT_EQ(pce::evaluate<Pair>(x, len, pen, pce::Projection::analytic, out), pce::Status::ok);
    check_result_matches(out, e);
  }

  // --- 7. Rigid motions: E(Rx + t) = E(x), ∇E and ∇²E rotate with R (double only).
  if constexpr (std::is_same_v<S, double>) {
    std::mt19937_64 rng(7);
    const Eigen::Matrix3d R = random_rotation(rng);
    const Eigen::Vector3d t = Eigen::Vector3d(0.3, -0.7, 0.2) * cs.config.scale * 3;
    pce::Vec12<double> y;
    Eigen::Matrix<double, 12, 12> B = Eigen::Matrix<double, 12, 12>::Zero();
    for (int j = 0; j < 4; ++j) {
      y.segment<3>(3 * j) = R * x.template segment<3>(3 * j) + t;
      B.block<3, 3>(3 * j, 3 * j) = R;
    }
    pce::PairEnergy<double> ey;
    ASSERT_EQ(pce::pair_energy<Pair>(y, len, pen, ey), pce::Status::ok);
    check_rotated(e, ey, B);
  }
  (void)combo;
}

TEST_P(Conformance, RandomConfigurations) {
  const Combo c = GetParam();
  std::mt19937_64 rng(1234 + 97 * static_cast<int>(c.pair) + 31 * static_cast<int>(c.length) +
                      7 * static_cast<int>(c.penalty));
  const double scales[3] = {1e-2, 1.0, 1e2};
  const double offsets[2] = {0.0, 20.0};  // in units of the scale
  const int per = 8;
  for (double scale : scales)
    for (double off : offsets)
      for (int k = 0; k < per; ++k) {
        const Case cs = draw_case(c, scale, off * scale, rng);
        with_length(c.length, [&](const auto& len) {
          with_penalty(cs.penalty, [&](const auto& pen) {
            switch (c.scalar) {
              case ScalarKind::float_:
                check_case<SuitePair, float>(c, cs, len, pen);
                break;
              case ScalarKind::double_:
                check_case<SuitePair, double>(c, cs, len, pen);
                break;
              case ScalarKind::long_double:
                check_case<SuitePair, long double>(c, cs, len, pen);
                break;
            }
            return 0;
          });
          return 0;
        });
        if (HasFatalFailure()) return;
      }
  std::printf("exact vs numerical: compared on %d configurations (worst %.1f roundoffs), numerical inaccurate on %d\n",
              exact_tally().compared, exact_tally().worst, exact_tally().numerical_inaccurate);
  exact_tally() = ExactTally{};
}

std::vector<Combo> all_combos() {
  std::vector<Combo> v;
  for (PairKind p : {kSuitePair})
    for (LengthKind l : {LengthKind::signed_positive, LengthKind::signed_negative, LengthKind::unsigned_})
      for (PenaltyKind q : {PenaltyKind::quadratic, PenaltyKind::cubic, PenaltyKind::log_barrier, PenaltyKind::custom})
        for (ScalarKind s : {ScalarKind::float_, ScalarKind::double_, ScalarKind::long_double})
          v.push_back({p, l, q, s});
  return v;
}

INSTANTIATE_TEST_SUITE_P(AllCombinations, Conformance, testing::ValuesIn(all_combos()), combo_name);

}  // namespace

#if PCE_CONFORMANCE_PAIR == 0
namespace {

// Statuses of energy/pair_energy.hpp: every non-ok outcome writes nothing.
template <class S> class PairEnergyStatus : public testing::Test {};
using StatusScalars = testing::Types<float, double, long double>;
TYPED_TEST_SUITE(PairEnergyStatus, StatusScalars);

template <class S> pce::Vec12<S> simple_vf(double z) {
  pce::Vec12<double> x;
  x << 0.2, 0.3, z, 0, 0, 0, 1, 0, 0, 0, 1, 0;
  return pce_test::cast12<S>(x);
}

/// A user penalty whose ψ″ is not representable.
struct Exploding {
  template <class S> pce::PenaltyDerivatives<S> evaluate(S) const {
    return {S(1), S(1), std::numeric_limits<S>::infinity()};
  }
};

template <class S, class Length, class Penalty>
pce::Status status_of(const pce::Vec12<S>& x, const Length& len, const Penalty& pen) {
  pce::PairResult<S> out;
  out.value = S(-7);
  out.gradient.setConstant(S(-7));
  const pce::Status s = pce::evaluate<pce::VertexFace>(x, len, pen, pce::Projection::analytic, out);
  if (s != pce::Status::ok) {
    EXPECT_EQ(out.value, S(-7)) << "written on " << pce::to_string(s);
    EXPECT_EQ(out.gradient, pce::Vec12<S>::Constant(S(-7))) << "written on " << pce::to_string(s);
  }
  return s;
}

TYPED_TEST(PairEnergyStatus, EveryFailureIsExplicitAndWritesNothing) {
  using S = TypeParam;
  const pce::LogBarrierPenalty bar{1.0, 0.5};
  const pce::QuadraticPenalty quad{1.0, 0.5};
  EXPECT_EQ(status_of(simple_vf<S>(0.1), pce::SignedLength{}, bar), pce::Status::ok);
  // The log barrier is undefined at L <= 0: below the face, on it, and for the other side.
  EXPECT_EQ(status_of(simple_vf<S>(-0.1), pce::SignedLength{}, bar), pce::Status::out_of_domain);
  EXPECT_EQ(status_of(simple_vf<S>(0.0), pce::SignedLength{}, bar), pce::Status::out_of_domain);
  EXPECT_EQ(status_of(simple_vf<S>(0.0), pce::UnsignedLength{}, bar), pce::Status::out_of_domain);
  EXPECT_EQ(status_of(simple_vf<S>(0.1), pce::SignedLength{pce::Side::negative}, bar), pce::Status::out_of_domain);
  EXPECT_EQ(status_of(simple_vf<S>(-0.1), pce::SignedLength{pce::Side::negative}, bar), pce::Status::ok);
  // Bad coordinates and parameters.
  pce::Vec12<S> x = simple_vf<S>(0.1);
  x[4] = std::numeric_limits<S>::quiet_NaN();
  EXPECT_EQ(status_of(x, pce::SignedLength{}, quad), pce::Status::invalid_input);
  EXPECT_EQ(status_of(simple_vf<S>(0.1), pce::SignedLength{}, pce::LogBarrierPenalty{1.0, -1.0}),
            pce::Status::invalid_input);
  EXPECT_EQ(status_of(simple_vf<S>(0.1), pce::SignedLength{}, pce::QuadraticPenalty{-1.0, 0.5}),
            pce::Status::invalid_input);
  // A degenerate triangle.
  pce::Vec12<double> d;
  d << 0.2, 0.3, 0.1, 0, 0, 0, 1, 0, 0, 2, 0, 0;
  EXPECT_EQ(status_of(pce_test::cast12<S>(d), pce::SignedLength{}, quad), pce::Status::degenerate);
  // A result beyond the scalar's range is `overflow`, never inf.
  if constexpr (!std::is_same_v<S, long double>) {
    EXPECT_EQ(status_of(simple_vf<S>(0.1), pce::SignedLength{}, pce::QuadraticPenalty{1e308, 1e300}),
              pce::Status::overflow);
  }
  EXPECT_EQ(status_of(simple_vf<S>(0.1), pce::SignedLength{}, Exploding{}), pce::Status::overflow);
}

TEST(PairEnergyNames, StatusAndProjectionNames) {
  EXPECT_STREQ(pce::to_string(pce::Status::ok), "ok");
  EXPECT_STREQ(pce::to_string(pce::Status::invalid_input), "invalid_input");
  EXPECT_STREQ(pce::to_string(pce::Status::degenerate), "degenerate");
  EXPECT_STREQ(pce::to_string(pce::Status::out_of_domain), "out_of_domain");
  EXPECT_STREQ(pce::to_string(pce::Status::overflow), "overflow");
  EXPECT_STREQ(pce::to_string(pce::Projection::analytic), "analytic");
  EXPECT_STREQ(pce::to_string(pce::Projection::gauss_newton), "gauss_newton");
  EXPECT_STREQ(pce::to_string(pce::Projection::exact), "exact");
}

}  // namespace
#endif  // PCE_CONFORMANCE_PAIR == 0
