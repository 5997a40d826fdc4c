// SPDX-License-Identifier: MIT
/// @file
/// Accuracy of the PSD strategies against the true nearest-PSD projection, shared by
/// `pce-accuracy` (benchmarks/accuracy.cpp) and `tests/test_accuracy_reference.cpp`.
///
/// For one sample (a pair kind, a length, a penalty and a double input x) and a scalar S:
///  * the input S sees is x rounded to S (`rounded<S>`);
///  * the reference P* is `pce::project_psd` of the exact Hessian, both computed in 50 digits
///    (`HighPrecision`) at exactly that rounded input (`reference_at`, compiled once per pair
///    kind in accuracy_reference_*.cpp): V max(Λ, 0) Vᵀ, the Frobenius-nearest PSD matrix;
///  * each strategy's P is computed in S (`measure_at<S>`) and compared (`compare`):
///    rel_dist = ‖P − P*‖_F / ‖P*‖_F, in long double (P* rounded to long double, 64-bit
///    mantissa, far below any error measured here). When ‖P*‖_F = 0 (the exact Hessian is
///    negative semidefinite, e.g. zero) the denominator is ‖H*‖_F instead; when that is 0 too,
///    rel_dist is 0 if P = 0 and +inf otherwise;
///  * a PSD violation is λ_min(P) < −τ·max|λ(P)|, λ computed in long double, τ = n·ε_S
///    (`psd_tolerance`; n = 12, 9, 6 coordinates): rounding a PSD matrix of rank ≤ 5 to S
///    moves its eigenvalues by at most ~√5·u·‖P‖₂ = 1.1·ε·‖P‖₂, so τ leaves a margin of ~10.
///  * unsigned length with |l| within rounding of 0 (|l*| ≤ 64 u_S max|x|): the length is not
///    differentiable there and the scalar's rounding decides which one-sided Hessian it
///    returns; the distance is taken to the nearer of the two references (as
///    docs/stability.md does for the Hessian).
///
/// Samples: `random` (well-shaped pairs, L spread over the penalty's active range),
/// `near_contact` (L / range log-uniform in 1e-6 … 1e-2), and the hard-case families of
/// hard_cases.hpp (`hard_samples`).
#pragma once

#include "conformance.hpp"
#include "hard_cases.hpp"
// Only for draw_point_edge / draw_point_point (header-only use; nothing of gtest is linked).
#include "kind_conformance.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace pce_test {

/// All four pair kinds (conformance.hpp's `PairKind` has the two plane kinds only).
enum class AnyPair { vertex_face, edge_edge, point_edge, point_point };
inline const char* name(AnyPair p) {
  switch (p) {
    case AnyPair::vertex_face:
      return "vertex_face";
    case AnyPair::edge_edge:
      return "edge_edge";
    case AnyPair::point_edge:
      return "point_edge";
    case AnyPair::point_point:
      return "point_point";
  }
  return "?";
}
inline int dofs(AnyPair p) { return p == AnyPair::point_edge ? 9 : p == AnyPair::point_point ? 6 : 12; }
inline bool is_plane(AnyPair p) { return p == AnyPair::vertex_face || p == AnyPair::edge_edge; }

/// The five strategies measured, in report order.
inline constexpr std::array<pce::Projection, 5> kStrategies = {pce::Projection::analytic, pce::Projection::abs,
                                                               pce::Projection::exact, pce::Projection::gauss_newton,
                                                               pce::Projection::numerical};

/// One input: coordinates in the first dofs(pair) entries of x.
struct Sample {
  AnyPair pair = AnyPair::vertex_face;
  LengthKind length = LengthKind::unsigned_;
  PenaltySpec penalty{};
  pce::Vec12<double> x = pce::Vec12<double>::Zero();
  std::string family;       ///< "random", "near_contact" or a hard family
  std::string severity;     ///< hard cases only
  bool degenerate = false;  ///< hard case without a frame (`degenerate` expected)
};

/// The three built-in penalties (with_penalty would also instantiate the tests' custom one).
template <class F> decltype(auto) with_builtin_penalty(const PenaltySpec& p, F&& f) {
  if (p.kind == PenaltyKind::quadratic) return f(pce::QuadraticPenalty{p.stiffness, p.eps});
  if (p.kind == PenaltyKind::cubic) return f(pce::CubicPenalty{p.stiffness, p.eps, p.delta});
  return f(pce::LogBarrierPenalty{p.stiffness, p.dhat});
}

/// A penalty of the given kind whose active range is L < R: quadratic and cubic ε = R
/// (cubic δ = (R/10)²), log barrier d̂ = R; stiffness 1 (every distance is relative).
inline PenaltySpec penalty_with_range(PenaltyKind kind, double R) {
  if (kind == PenaltyKind::quadratic) return {PenaltyKind::quadratic, 1.0, R, 0, 0, 0};
  if (kind == PenaltyKind::cubic) return {PenaltyKind::cubic, 1.0, R, 0.01 * R * R, 0, 0};
  return {PenaltyKind::log_barrier, 1.0, 0, 0, R, 0};
}
/// The active range of a penalty spec (ε, or d̂ for the barrier).
inline double active_range(const PenaltySpec& p) { return p.kind == PenaltyKind::log_barrier ? p.dhat : p.eps; }

/// x rounded to S, held exactly in long double.
template <class S> pce::Vec12<long double> rounded(const pce::Vec12<double>& x) {
  pce::Vec12<long double> y;
  for (int i = 0; i < 12; ++i) y[i] = static_cast<long double>(static_cast<S>(x[i]));
  return y;
}

/// The 50-digit reference at one input (long double copies of the 50-digit results).
struct Reference {
  pce::Status status = pce::Status::invalid_input;
  int n = 12;
  long double l = 0;       ///< signed length l (plane kinds), L (point kinds)
  long double length = 0;  ///< L
  pce::Mat12<long double> hessian = pce::Mat12<long double>::Zero();     ///< H*, top-left n×n
  pce::Mat12<long double> projection = pce::Mat12<long double>::Zero();  ///< P* = project_psd(H*)
  long double hessian_norm = 0, projection_norm = 0;                     ///< Frobenius, computed in 50 digits
};

/// The reference of `s` at input `x` (exactly representable in long double), in 50 digits.
/// One translation unit per pair kind (accuracy_reference_*.cpp): the 50-digit
/// instantiations are the slow part of the build.
Reference reference_vertex_face(const Sample& s, const pce::Vec12<long double>& x);
Reference reference_edge_edge(const Sample& s, const pce::Vec12<long double>& x);
Reference reference_point(const Sample& s, const pce::Vec12<long double>& x);  ///< point_edge, point_point
inline Reference reference_at(const Sample& s, const pce::Vec12<long double>& x) {
  if (s.pair == AnyPair::vertex_face) return reference_vertex_face(s, x);
  if (s.pair == AnyPair::edge_edge) return reference_edge_edge(s, x);
  return reference_point(s, x);
}

/// Fills a Reference from a 50-digit energy (used by accuracy_reference_*.cpp).
template <class Energy> void fill_reference(const Energy& e, Reference& r) {
  const auto H = pce::energy_hessian(e);
  const auto P = pce::project_psd(H);
  constexpr int N = decltype(H)::RowsAtCompileTime;
  r.n = N;
  HighPrecision hn = 0, pn = 0;
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) {
      r.hessian(i, j) = static_cast<long double>(H(i, j));
      r.projection(i, j) = static_cast<long double>(P(i, j));
      hn += H(i, j) * H(i, j);
      pn += P(i, j) * P(i, j);
    }
  r.hessian_norm = static_cast<long double>(sqrt(hn));
  r.projection_norm = static_cast<long double>(sqrt(pn));
  r.length = static_cast<long double>(e.length);
}

/// The 50-digit reference of a plane kind (`pce::VertexFace`, `pce::EdgeEdge`), signed or
/// unsigned: the body of `reference_vertex_face` and `reference_edge_edge`, each
/// instantiated in its own translation unit.
template <class Pair> Reference plane_reference(const Sample& s, const pce::Vec12<long double>& x) {
  Reference r;
  const pce::Vec12<HighPrecision> y = cast12<HighPrecision>(x);
  with_builtin_penalty(s.penalty, [&](const auto& pen) {
    with_length(s.length, [&](const auto& len) {
      pce::PairEnergy<HighPrecision> e;
      r.status = pce::pair_energy<Pair>(y, len, pen, e);
      if (r.status != pce::Status::ok) return 0;
      fill_reference(e, r);
      r.l = static_cast<long double>(e.frame.l);
      return 0;
    });
    return 0;
  });
  return r;
}

/// What the scalar S computes at its rounding of the input.
struct Measured {
  pce::Status status = pce::Status::invalid_input;
  int n = 12;
  std::array<pce::Mat12<long double>, kStrategies.size()> projection{};  ///< top-left n×n
};

template <class S, class Energy> void fill_measured(const Energy& e, Measured& m) {
  for (std::size_t k = 0; k < kStrategies.size(); ++k) {
    const auto P = pce::projected_hessian(e, kStrategies[k]);
    constexpr int N = decltype(P)::RowsAtCompileTime;
    m.n = N;
    m.projection[k].setZero();
    m.projection[k].template topLeftCorner<N, N>() = P.template cast<long double>();
  }
}

/// Evaluates every strategy of `s` in S at `rounded<S>(s.x)`.
template <class S> Measured measure_at(const Sample& s) {
  Measured m;
  const pce::Vec12<S> x = cast12<S>(s.x);
  with_builtin_penalty(s.penalty, [&](const auto& pen) {
    if (is_plane(s.pair)) {
      with_pair(s.pair == AnyPair::vertex_face ? PairKind::vertex_face : PairKind::edge_edge, [&](auto pair) {
        with_length(s.length, [&](const auto& len) {
          pce::PairEnergy<S> e;
          m.status = pce::pair_energy<decltype(pair)>(x, len, pen, e);
          if (m.status == pce::Status::ok) fill_measured<S>(e, m);
          return 0;
        });
        return 0;
      });
    } else if (s.pair == AnyPair::point_edge) {
      pce::PointEdgeEnergy<S> e;
      m.status = pce::pair_energy<pce::PointEdge>(pce::Vec9<S>(x.template head<9>()), pce::UnsignedLength{}, pen, e);
      if (m.status == pce::Status::ok) fill_measured<S>(e, m);
    } else {
      pce::PointPointEnergy<S> e;
      m.status = pce::pair_energy<pce::PointPoint>(pce::Vec6<S>(x.template head<6>()), pce::UnsignedLength{}, pen, e);
      if (m.status == pce::Status::ok) fill_measured<S>(e, m);
    }
    return 0;
  });
  return m;
}

/// ‖A‖_F of the top-left n×n block, in long double.
inline long double frobenius(const pce::Mat12<long double>& A, int n) {
  return std::sqrt(A.topLeftCorner(n, n).squaredNorm());
}

/// rel_dist of P to the reference, with the ‖P*‖ = 0 rule of the file comment.
inline double rel_dist(const pce::Mat12<long double>& P, const Reference& r) {
  const long double num = frobenius((P - r.projection).eval(), r.n);
  long double den = r.projection_norm > 0 ? r.projection_norm : r.hessian_norm;
  if (den > 0) return static_cast<double>(num / den);
  return num == 0 ? 0.0 : std::numeric_limits<double>::infinity();
}

/// λ_min / max|λ| of the top-left n×n block (long double eigensolver of pce_test_support);
/// 0 for the zero matrix.
inline double psd_ratio(const pce::Mat12<long double>& P, int n) {
  double lmin = 0, big = 0;
  const auto take = [&](const auto& values) {
    lmin = static_cast<double>(values.minCoeff());
    big = static_cast<double>(values.cwiseAbs().maxCoeff());
  };
  if (n == 12) take(symmetric_eigen<long double, 12>(P).values);
  if (n == 9) take(symmetric_eigen<long double, 9>(pce::Mat9<long double>(P.topLeftCorner<9, 9>())).values);
  if (n == 6) take(symmetric_eigen<long double, 6>(pce::Mat6<long double>(P.topLeftCorner<6, 6>())).values);
  return big > 0 ? lmin / big : 0.0;
}

/// τ of the PSD-violation test: n·ε of the scalar.
template <class S> double psd_tolerance(int n) { return n * static_cast<double>(std::numeric_limits<S>::epsilon()); }

inline bool all_finite(const pce::Mat12<long double>& P, int n) {
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (!std::isfinite(P(i, j))) return false;
  return true;
}

/// One strategy's outcome on one sample.
struct StrategyOutcome {
  bool finite = false;
  double rel_dist = 0;   ///< meaningful when finite
  double psd_ratio = 0;  ///< λ_min/max|λ|
  bool psd_violation = false;
};

/// Everything measured for one sample in one scalar.
struct SampleOutcome {
  pce::Status status = pce::Status::invalid_input;            ///< of S
  pce::Status reference_status = pce::Status::invalid_input;  ///< of 50 digits at the same input
  bool sign_ambiguous = false;                                ///< the nearer of two one-sided references was used
  bool zero_reference = false;                                ///< ‖P*‖ = 0
  std::array<StrategyOutcome, kStrategies.size()> strategies{};
};

/// Measures `s` in S: status, and for every strategy finiteness, rel_dist and PSD-ness.
template <class S> SampleOutcome measure_sample(const Sample& s) {
  SampleOutcome o;
  const pce::Vec12<long double> y = rounded<S>(s.x);
  const Reference ref = reference_at(s, y);
  o.reference_status = ref.status;
  const Measured m = measure_at<S>(s);
  o.status = m.status;
  if (m.status != pce::Status::ok) return o;
  // Unsigned length within rounding of 0: the other one-sided reference too.
  Reference alt;
  if (is_plane(s.pair) && s.length == LengthKind::unsigned_ && ref.status == pce::Status::ok) {
    const long double u = std::numeric_limits<S>::epsilon() / 2;
    if (std::fabs(ref.l) <= 64 * u * y.head(dofs(s.pair)).cwiseAbs().maxCoeff()) {
      Sample flipped = s;
      flipped.length = ref.l < 0 ? LengthKind::signed_positive : LengthKind::signed_negative;
      alt = reference_at(flipped, y);
      o.sign_ambiguous = alt.status == pce::Status::ok;
    }
  }
  o.zero_reference = ref.status == pce::Status::ok && ref.projection_norm == 0;
  for (std::size_t k = 0; k < kStrategies.size(); ++k) {
    StrategyOutcome& so = o.strategies[k];
    so.finite = all_finite(m.projection[k], m.n);
    if (!so.finite) continue;
    so.psd_ratio = psd_ratio(m.projection[k], m.n);
    so.psd_violation = so.psd_ratio < -psd_tolerance<S>(m.n);
    if (ref.status != pce::Status::ok) {
      so.rel_dist = std::numeric_limits<double>::quiet_NaN();  // no reference: not counted
      continue;
    }
    so.rel_dist = rel_dist(m.projection[k], ref);
    if (o.sign_ambiguous) so.rel_dist = std::min(so.rel_dist, rel_dist(m.projection[k], alt));
  }
  return o;
}

// ---------------------------------------------------------------------------------------
// Samples

/// Length draws of the two generated families, relative to the penalty's range R.
enum class LengthDraw { spread, near_contact };

/// `count` seeded samples of one pair × length × penalty: well-shaped pairs of size
/// `scale` (log-uniform in 1e-2 … 1e2) at an offset up to `scale` from the origin; the
/// penalty's range is R = scale/2 and L is R·U(0.02, 0.98) (`spread`) or R·10^U(−6, −2)
/// (`near_contact`); an unsigned length gets l of either sign.
inline std::vector<Sample> generated_samples(AnyPair pair, LengthKind length, PenaltyKind penalty, LengthDraw draw,
                                             int count, std::uint64_t seed) {
  std::vector<Sample> out;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  for (int i = 0; i < count; ++i) {
    const double scale = std::pow(10.0, -2 + 4 * U(rng));
    const double offset = scale * U(rng);
    const double R = 0.5 * scale;
    const double L = draw == LengthDraw::spread ? R * (0.02 + 0.96 * U(rng)) : R * std::pow(10.0, -6 + 4 * U(rng));
    Sample s;
    s.pair = pair;
    s.length = length;
    s.penalty = penalty_with_range(penalty, R);
    s.family = draw == LengthDraw::spread ? "random" : "near_contact";
    if (is_plane(pair)) {
      const double l = (length == LengthKind::unsigned_ && U(rng) < 0.5) ? -L : L;
      s.x = random_configuration(pair == AnyPair::vertex_face ? PairKind::vertex_face : PairKind::edge_edge, l, scale,
                                 offset, rng)
                .x;
    } else if (pair == AnyPair::point_edge) {
      double d = 0;
      pce::Vec9<double> x = draw_point_edge(rng, scale, offset, d);
      // Move the point along its perpendicular to the line, to distance L.
      const Eigen::Vector3d p = x.head<3>(), e0 = x.segment<3>(3), e1 = x.segment<3>(6);
      const Eigen::Vector3d foot = e0 + (p - e0).dot(e1 - e0) / (e1 - e0).squaredNorm() * (e1 - e0);
      x.head<3>() = foot + (p - foot) * (L / (p - foot).norm());
      s.x.head<9>() = x;
    } else {
      double d = 0;
      pce::Vec6<double> x = draw_point_point(rng, scale, offset, d);
      const Eigen::Vector3d p = x.head<3>(), q = x.tail<3>();
      x.head<3>() = q + (p - q) * (L / (p - q).norm());
      s.x.head<6>() = x;
    }
    out.push_back(s);
  }
  return out;
}

/// The hard cases of hard_cases.hpp, each with every built-in penalty: its own penalty for
/// its own kind; for the other kinds, `penalty_with_range` of the own penalty's active range
/// (quadratic/cubic ε, barrier d̂), which holds the case's length inside the active range
/// wherever L > 0 (the log barrier is out of its domain at L ≤ 0: signed negative severities
/// and exact zeros report `out_of_domain`, as they should).
inline std::vector<Sample> hard_samples(PenaltyKind penalty) {
  std::vector<Sample> out;
  for (const HardCase& hc : hard_cases()) {
    Sample s;
    s.pair = hc.pair == PairKind::vertex_face ? AnyPair::vertex_face : AnyPair::edge_edge;
    s.length = hc.length;
    s.penalty = hc.penalty.kind == penalty ? hc.penalty : penalty_with_range(penalty, active_range(hc.penalty));
    s.x = hc.x;
    s.family = hc.family;
    s.severity = hc.severity;
    s.degenerate = hc.degenerate;
    out.push_back(s);
  }
  return out;
}

}  // namespace pce_test
