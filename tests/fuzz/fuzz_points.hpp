// SPDX-License-Identifier: MIT
/// @file
/// The fuzz body of `docs/fuzzing.md`, the point kinds (`pce::PointEdge`, `pce::PointPoint`)
/// through `pce::evaluate` and the lower-level functions, and `run_new_kind<S>`, which
/// hands the point kinds and closest-feature evaluation to their checks. Decoding, the
/// helpers and the projection checks are shared with `fuzz_plane.hpp` and
/// `fuzz_closest.hpp` (`fuzz_common.hpp`); included, like them, only by the translation
/// unit of each scalar type (`fuzz_float.cpp`, ...), so its helpers stay in an unnamed
/// namespace.
///
/// As there, the library calls that depend on the penalty type are kept in a small function
/// (`run_point_penalty`: 3 scalars × 3 penalties × 2 kinds) that stores its results in a
/// case object; every check is in functions templated on the scalar and the kind only.
#pragma once

#include "fuzz_common.hpp"

#include <cstdio>

namespace pce_fuzz {
namespace {

using pce::Status;

// ---------------------------------------------------------------------------------------
// The point kinds.

template <class Pair> struct KindTraits;
template <> struct KindTraits<pce::PointEdge> {
  template <class S> using Frame = pce::PointEdgeFrame<S>;
  static constexpr int kind = pce_fuzz_point_edge;
  static constexpr Layout layout = Layout::point_edge;
};
template <> struct KindTraits<pce::PointPoint> {
  template <class S> using Frame = pce::PointPointFrame<S>;
  static constexpr int kind = pce_fuzz_point_point;
  static constexpr Layout layout = Layout::point_point;
};

/// One point-kind case: its inputs and what the penalty-typed calls returned.
template <class S, class Pair> struct PointCase {
  static constexpr int N = Pair::dofs, F = Pair::frame_dofs;
  using Frame = typename KindTraits<Pair>::template Frame<S>;
  using Energy = typename Pair::template Energy<S>;
  using Result = pce::PairResult<S, N, F>;

  pce::VecN<S, N> x;
  pce::Projection proj = pce::Projection::none;
  pce::Side side = pce::Side::positive;
  bool invalid_coords = false, nonfinite = false;
  bool barrier = false;
  double activation = 0;
  bool valid = true;  ///< penalty parameters

  Frame f;
  Status fs = Status::invalid_input;

  Energy e;
  Status ps = Status::invalid_input;
  bool psi_checked = false, psi_finite = false;  ///< ψ at L evaluated by the fuzzer (not for the barrier at L ≤ 0)

  Result r;
  Status es = Status::invalid_input;
};

template <class S, class Pair> struct PointLower {
  static constexpr int N = Pair::dofs, F = Pair::frame_dofs;
  pce::VecN<S, N> g;
  pce::MatN<S, N> H;
  pce::FrameEigensystem<S, F> eig;
  pce::MatN<S, N> P[kNumStrategies];
  bool core_finite = false;
};

/// `Pair::frame`: statuses, no write on failure, and on ok finite, consistent members and
/// a distance that matches a long double recomputation.
template <class S, class Pair> void check_point_frame(PointCase<S, Pair>& c) {
  using Frame = typename PointCase<S, Pair>::Frame;
  constexpr bool pe = std::is_same<Pair, pce::PointEdge>::value;
  const long double eps = eps_ld<S>();
  c.invalid_coords = coordinates_invalid<S, PointCase<S, Pair>::N>(c.x, c.nonfinite);
  fill(c.f);
  const Snapshot<Frame> fsnap(c.f);
  g_escape = &c.f;
  std::feclearexcept(FE_ALL_EXCEPT);
  c.fs = Pair::frame(c.x, c.f);
  const bool underflow = std::fetestexcept(FE_UNDERFLOW) != 0;
  const Status fs = c.fs;
  if (c.invalid_coords) {
    PCE_FUZZ_CHECK(fs == Status::invalid_input, "frame: coordinate %s but status %s",
                   c.nonfinite ? "NaN/Inf" : "beyond max_coordinate", pce::to_string(fs));
  } else if (pe) {
    PCE_FUZZ_CHECK(fs == Status::ok || fs == Status::degenerate || fs == Status::overflow,
                   "frame: valid coordinates but status %s", pce::to_string(fs));
  } else {
    PCE_FUZZ_CHECK(fs == Status::ok || fs == Status::degenerate, "frame: valid coordinates but status %s",
                   pce::to_string(fs));
  }
  if (fs != Status::ok)
    PCE_FUZZ_CHECK(fsnap.unchanged(c.f), "frame: status %s but the output was written", pce::to_string(fs));
  if (c.invalid_coords) return;

  if constexpr (pe) {
    const LdVec3 e_raw = point_ld<S>(c.x, 2) - point_ld<S>(c.x, 1), r_raw = point_ld<S>(c.x, 0) - point_ld<S>(c.x, 1);
    // Everything below in units of k = max(|e|∞, |r|∞) (a power of two; long double exact).
    const int k = unit_exponent((std::max)(e_raw.cwiseAbs().maxCoeff(), r_raw.cwiseAbs().maxCoeff()));
    const LdVec3 e = down(e_raw, k), r = down(r_raw, k);
    // stableNorm: in units of the larger vector the other can be far below sqrt(min) (an
    // edge 2^-8000 of the point's distance in long double), where a plain norm underflows.
    const long double en = e.stableNorm(), rn = r.stableNorm(), er = e.cross(r).stableNorm();
    // Exact coincidences are degenerate: a zero-length edge, or p on an endpoint (d = 0).
    if (same_point<S>(c.x, 1, 2) || same_point<S>(c.x, 0, 1) || same_point<S>(c.x, 0, 2))
      PCE_FUZZ_CHECK(fs == Status::degenerate, "point_edge frame: coincident points but status %s", pce::to_string(fs));
    // degenerate: e × r vanishes in the rescaled coordinates, so the points are collinear to
    // within the rounding of one cross product.
    if (fs == Status::degenerate && !underflow)
      PCE_FUZZ_CHECK(er <= 64 * eps * en * rn,
                     "point_edge frame: degenerate but |e x r| = %.6Le > 64 eps |e||r| = %.6Le (scaled)", er,
                     64 * eps * en * rn);
    // overflow: only for a point beyond the scalar's range relative to the edge, where |e × r|
    // in coordinates rescaled by the edge overflows (|r|/|e| beyond about sqrt(max)).
    if (fs == Status::overflow) {
      const long double ratio = r_raw.cwiseAbs().maxCoeff() / e_raw.cwiseAbs().maxCoeff();
      const long double lim = std::sqrt(static_cast<long double>((std::numeric_limits<S>::max)())) / 64;
      PCE_FUZZ_CHECK(ratio >= lim, "point_edge frame: overflow but |r|/|e| = %.6Le < %.6Le", ratio, lim);
    }
    if (fs == Status::ok) {
      const Frame& f = c.f;
      PCE_FUZZ_CHECK(
          finite(f.P) && finite(f.t) && finite(f.u) && finite(f.n) && finite(f.d) && finite(f.a) && finite(f.beta),
          "point_edge frame: status ok but a non-finite member");
      PCE_FUZZ_CHECK(f.d > S(0) && f.a > S(0), "point_edge frame: status ok but d = %.17Lg, a = %.17Lg",
                     (long double)f.d, (long double)f.a);
      PCE_FUZZ_CHECK(f.P(0, 0) == S(0) && f.P(0, 1) == S(-1) && f.P(0, 2) == S(1) && f.P(1, 0) == S(1) &&
                         f.P(1, 1) == S(S(-1) + f.beta) && f.P(1, 2) == -f.beta,
                     "point_edge frame: P is not (0, -1, 1; 1, -1 + beta, -beta)");
      const LdVec3 t = f.t.template cast<long double>(), u = f.u.template cast<long double>(),
                   n = f.n.template cast<long double>();
      // n̂ = (e × r)/|e × r| is accurate only to ε/sin∠(e, r) (its rounding error), but the
      // frame orthogonalises it against t̂, so (t̂, û, n̂) is orthonormal to rounding whatever
      // the angle — even for p on the line to within rounding, where n̂ is noise.
      // (An underflow in the rescaled cross product — |r| ≪ |e| by ~sqrt(min) — leaves n̂ not
      // unit: counted as excused, like every miss under underflow.)
      const long double defect = basis_defect(f.t, f.u, f.n);
      const long double cond = er > 0 ? en * rn / er : std::numeric_limits<long double>::infinity();
      const bool basis_ok = defect <= 64 * eps && (t.cross(u) - n).cwiseAbs().maxCoeff() <= 64 * eps;
      if (!basis_ok && underflow)
        ++pce_fuzz_stats().underflow_excused;
      else
        PCE_FUZZ_CHECK(
            basis_ok,
            "point_edge frame: (t, u, n) not a right-handed orthonormal basis: defect %.3Le > 64 eps (1/sin = %.3Le)",
            defect, cond);
      if (!underflow) {
        // d = |e × r|/|e| to within the rounding of the differences and of one cross
        // product (absolute ε|r|); û points from the line to p; a = |e|; β = r·e/|e|².
        const long double d = down(static_cast<long double>(f.d), k), a = down(static_cast<long double>(f.a), k);
        const long double dref = er / en;
        PCE_FUZZ_CHECK(std::fabs(d - dref) <= 64 * eps * rn,
                       "point_edge frame: d = %.17Lg but |e x r|/|e| = %.17Lg (scaled)", d, dref);
        PCE_FUZZ_CHECK(std::fabs(u.dot(r) - d) <= 64 * eps * rn,
                       "point_edge frame: u . r = %.17Lg differs from d = %.17Lg (scaled)", u.dot(r), d);
        PCE_FUZZ_CHECK(std::fabs(a - en) <= 16 * eps * en, "point_edge frame: a = %.17Lg but |e| = %.17Lg (scaled)", a,
                       en);
        const long double bref = r.dot(e) / en / en;
        PCE_FUZZ_CHECK(std::fabs(static_cast<long double>(f.beta) - bref) <= 64 * eps * (rn / en + 1),
                       "point_edge frame: beta = %.17Lg but r.e/|e|^2 = %.17Lg", (long double)f.beta, bref);
      }
    }
  } else {
    const LdVec3 e_raw = point_ld<S>(c.x, 0) - point_ld<S>(c.x, 1);
    const int k = unit_exponent(e_raw.cwiseAbs().maxCoeff());
    const LdVec3 e = down(e_raw, k);
    const long double en = e.norm();
    const bool coincident = same_point<S>(c.x, 0, 1);
    PCE_FUZZ_CHECK((fs == Status::degenerate) == coincident, "point_point frame: status %s but the points are %s",
                   pce::to_string(fs), coincident ? "coincident" : "distinct");
    if (fs == Status::ok) {
      const Frame& f = c.f;
      PCE_FUZZ_CHECK(finite(f.u) && finite(f.v) && finite(f.w) && finite(f.d),
                     "point_point frame: status ok but a non-finite member");
      PCE_FUZZ_CHECK(f.d > S(0), "point_point frame: status ok but d = %.17Lg", (long double)f.d);
      const LdVec3 u = f.u.template cast<long double>(), v = f.v.template cast<long double>(),
                   w = f.w.template cast<long double>();
      const long double defect = basis_defect(f.u, f.v, f.w);
      const bool basis_ok = defect <= 64 * eps && (u.cross(v) - w).cwiseAbs().maxCoeff() <= 64 * eps;
      if (!basis_ok && underflow)
        ++pce_fuzz_stats().underflow_excused;
      else
        PCE_FUZZ_CHECK(basis_ok, "point_point frame: (u, v, w) not a right-handed orthonormal basis (%.3Le)", defect);
      if (!underflow) {
        const long double d = down(static_cast<long double>(f.d), k);
        PCE_FUZZ_CHECK(std::fabs(d - en) <= 16 * eps * en,
                       "point_point frame: d = %.17Lg but |p - q| = %.17Lg (scaled)", d, en);
        PCE_FUZZ_CHECK((u - e / en).cwiseAbs().maxCoeff() <= 16 * eps, "point_point frame: u is not (p - q)/|p - q|");
      }
    }
  }
}

/// `pair_energy` (unsigned): statuses, no write, and on ok the lower-level outputs.
template <class S, class Pair> void check_point_energy(PointCase<S, Pair>& c,
                                                       const Snapshot<typename PointCase<S, Pair>::Energy>& esnap,
                                                       PointLower<S, Pair>& low) {
  PceFuzzStats& st = pce_fuzz_stats();
  constexpr bool pe = std::is_same<Pair, pce::PointEdge>::value;
  constexpr int F = Pair::frame_dofs;
  const Status ps = c.ps;
  if (!c.valid || c.invalid_coords) {
    PCE_FUZZ_CHECK(ps == Status::invalid_input, "pair_energy: %s but status %s",
                   !c.valid ? "invalid penalty parameters" : "invalid coordinates", pce::to_string(ps));
  } else if (c.fs != Status::ok) {
    PCE_FUZZ_CHECK(ps == c.fs, "pair_energy: frame status %s but pair_energy status %s", pce::to_string(c.fs),
                   pce::to_string(ps));
  } else if (!c.psi_checked) {
    PCE_FUZZ_CHECK(ps == Status::out_of_domain, "pair_energy: log barrier at L = %.17Lg <= 0 but status %s",
                   (long double)c.f.d, pce::to_string(ps));
  } else {
    PCE_FUZZ_CHECK(ps == (c.psi_finite ? Status::ok : Status::overflow), "pair_energy: status %s, psi %s finite",
                   pce::to_string(ps), c.psi_finite ? "is" : "is not");
  }
  if (ps == Status::out_of_domain)
    PCE_FUZZ_CHECK(c.barrier, "pair_energy: out_of_domain for a penalty defined everywhere");
  if (ps != Status::ok) {
    PCE_FUZZ_CHECK(esnap.unchanged(c.e), "pair_energy: status %s but the output was written", pce::to_string(ps));
    return;
  }
  const auto& e = c.e;
  PCE_FUZZ_CHECK(finite(e.length) && finite(e.psi.value) && finite(e.psi.first) && finite(e.psi.second),
                 "pair_energy: status ok but L = %.17Lg, psi = %.17Lg, psi' = %.17Lg, psi'' = %.17Lg",
                 (long double)e.length, (long double)e.psi.value, (long double)e.psi.first, (long double)e.psi.second);
  PCE_FUZZ_CHECK(e.length >= S(0), "unsigned length negative: %.17Lg", (long double)e.length);
  PCE_FUZZ_CHECK(e.length == c.f.d && e.frame.d == c.f.d && same_values(e.frame.u, c.f.u),
                 "pair_energy: length or frame differs from Pair::frame");
  check_psi(e.psi, e.length, c.activation, "pair_energy");

  // --- lower-level outputs ---
  if (e.psi.first != S(0) || e.psi.second != S(0)) ++st.active;
  low.g = pce::energy_gradient(e);
  low.H = pce::energy_hessian(e);
  low.eig = pce::energy_eigensystem(e);
  g_escape = &low.g;
  g_escape = &low.H;
  g_escape = &low.eig;
  const bool underflow = std::fetestexcept(FE_UNDERFLOW) != 0;
  ProjectionSet ps_set;
  compute_projections(e, low.H, underflow, low.P, ps_set);
  if constexpr (pe)
    ps_set.basis_defect = basis_defect(e.frame.t, e.frame.u, e.frame.n);
  else
    ps_set.basis_defect = basis_defect(e.frame.u, e.frame.v, e.frame.w);
  low.core_finite = finite(low.g) && finite(low.H) && finite(low.eig.values) && finite(e.length);

  const auto& eig = low.eig;
  PCE_FUZZ_CHECK(!finite(eig.values) || finite(eig.vectors),
                 "eigensystem: finite eigenvalues but a non-finite eigenvector");
  PCE_FUZZ_CHECK(same_values(low.P[0], low.H) || !finite(low.H), "projection none differs from energy_hessian");
  if (finite(eig.values)) {
    for (int i = 0; i + 1 < F; ++i)
      PCE_FUZZ_CHECK(eig.values[i] <= eig.values[i + 1], "eigenvalues not ascending at %d: %.17Lg > %.17Lg", i,
                     (long double)eig.values[i], (long double)eig.values[i + 1]);
    // The closed-form values, as the library computes them (same operations, so bit for bit).
    const S psi2 = e.psi.second, curv = S(e.psi.first / e.frame.d);
    bool used[F] = {};
    const auto take = [&](const S& v) {
      for (int i = 0; i < F; ++i)
        if (!used[i] && eig.values[i] == v) {
          used[i] = true;
          return true;
        }
      return false;
    };
    if constexpr (pe) {
      // {ψ″, ψ′/d, ψ′λ_big, ψ′λ_small, 0, 0} with λ_big·λ_small = −1/a².
      PCE_FUZZ_CHECK(take(psi2), "point_edge eigensystem: psi'' = %.17Lg is not an eigenvalue", (long double)psi2);
      PCE_FUZZ_CHECK(take(curv), "point_edge eigensystem: psi'/d = %.17Lg is not an eigenvalue", (long double)curv);
      const bool z0 = take(S(0)), z1 = take(S(0));
      PCE_FUZZ_CHECK(z0 && z1, "point_edge eigensystem: fewer than 2 exact zeros besides psi'' and psi'/d");
      long double rest[2] = {0, 0};
      int k = 0;
      for (int i = 0; i < F && k < 2; ++i)
        if (!used[i]) rest[k++] = static_cast<long double>(eig.values[i]);
      const long double target = static_cast<long double>(e.psi.first) / static_cast<long double>(e.frame.a);
      const long double want = -target * target, got = rest[0] * rest[1];
      if (!underflow && want != 0 && std::isfinite(want) && std::isfinite(got))
        PCE_FUZZ_CHECK(
            std::fabs(got - want) <= psd_tolerance<S>() * std::fabs(want),
            "point_edge eigensystem: psi' lambda_big * psi' lambda_small = %.17Lg, expected -(psi'/a)^2 = %.17Lg", got,
            want);
    } else {
      // {ψ″, ψ′/d, ψ′/d}
      PCE_FUZZ_CHECK(
          take(psi2) && take(curv) && take(curv),
          "point_point eigensystem: {%.17Lg, %.17Lg, %.17Lg} is not {psi'', psi'/d, psi'/d} = {%.17Lg, %.17Lg}",
          (long double)eig.values[0], (long double)eig.values[1], (long double)eig.values[2], (long double)psi2,
          (long double)curv);
    }
  }
  if constexpr (!pe) {
    // J = (1, −1) ⊗ I3 has orthogonal rows: the frame-space clamp is the nearest PSD matrix.
    PCE_FUZZ_CHECK(same_values(low.P[static_cast<int>(pce::Projection::analytic)],
                               low.P[static_cast<int>(pce::Projection::exact)]),
                   "point_point: analytic and exact differ");
  }
  check_projection_set<S>(ps_set);
}

/// `evaluate`: its status follows pair_energy's and the finiteness of the lower-level
/// outputs; no write on failure; on ok it equals them.
template <class S, class Pair> void check_point_evaluate(const PointCase<S, Pair>& c,
                                                         const Snapshot<typename PointCase<S, Pair>::Result>& rsnap,
                                                         const PointLower<S, Pair>& low) {
  PceFuzzStats& st = pce_fuzz_stats();
  const Status es = c.es;
  ++st.status[static_cast<int>(es)];
  ++st.kind_status[KindTraits<Pair>::kind][static_cast<int>(es)];
  const int pi = static_cast<int>(c.proj);
  if (c.ps != Status::ok) {
    PCE_FUZZ_CHECK(es == c.ps, "evaluate: status %s, pair_energy status %s", pce::to_string(es), pce::to_string(c.ps));
  } else {
    const bool all = low.core_finite && finite(low.P[pi]);
    PCE_FUZZ_CHECK(es == (all ? Status::ok : Status::overflow),
                   "evaluate: status %s but the lower-level outputs are %sfinite", pce::to_string(es),
                   all ? "" : "not ");
  }
  const auto& r = c.r;
  if (es != Status::ok) {
    PCE_FUZZ_CHECK(rsnap.unchanged(r), "evaluate: status %s but the output was written", pce::to_string(es));
    return;
  }
  PCE_FUZZ_CHECK(finite(r.length) && finite(r.value) && finite(r.gradient) && finite(r.hessian) &&
                     finite(r.projected_hessian) && finite(r.eigen.values) && finite(r.eigen.vectors),
                 "evaluate: status ok but a non-finite output");
  PCE_FUZZ_CHECK(r.length >= S(0), "evaluate: unsigned length negative");
  PCE_FUZZ_CHECK(r.length == c.e.length && r.value == c.e.psi.value && same_values(r.gradient, low.g) &&
                     same_values(r.hessian, low.H) && same_values(r.projected_hessian, low.P[pi]) &&
                     same_values(r.eigen.values, low.eig.values) && same_values(r.eigen.vectors, low.eig.vectors),
                 "evaluate: outputs differ from the lower-level functions");
}

template <class S, class Pair, class Penalty> void run_point_penalty(PointCase<S, Pair>& c, const Penalty& pen) {
  using Energy = typename PointCase<S, Pair>::Energy;
  using Result = typename PointCase<S, Pair>::Result;
  c.valid = pce::penalty_valid(pen);
  fill(c.e);
  const Snapshot<Energy> esnap(c.e);
  g_escape = &c.e;
  std::feclearexcept(FE_ALL_EXCEPT);
  c.ps = pce::pair_energy<Pair>(c.x, pce::UnsignedLength{}, pen, c.e);
  if (c.fs == Status::ok && c.valid && !(c.barrier && !(c.f.d > S(0)))) {
    const pce::PenaltyDerivatives<S> d = pen.template evaluate<S>(c.f.d);
    c.psi_checked = true;
    c.psi_finite = finite(d.value) && finite(d.first) && finite(d.second);
  }
  PointLower<S, Pair> low;
  check_point_energy<S, Pair>(c, esnap, low);

  fill(c.r);
  const Snapshot<Result> rsnap(c.r);
  c.es = pce::evaluate<Pair>(c.x, pce::UnsignedLength{}, pen, c.proj, c.r);
  check_point_evaluate<S, Pair>(c, rsnap, low);
}

/// A SignedLength request is invalid_input whatever else the input is: checked with the
/// decoded quadratic penalty only (one instantiation per scalar and kind, not three).
template <class S, class Pair> void run_point_signed(const PointCase<S, Pair>& c, const pce::QuadraticPenalty& pen) {
  using Energy = typename PointCase<S, Pair>::Energy;
  using Result = typename PointCase<S, Pair>::Result;
  Energy e2;
  fill(e2);
  const Snapshot<Energy> e2snap(e2);
  const Status s2 = pce::pair_energy<Pair>(c.x, pce::SignedLength{c.side}, pen, e2);
  check_signed_rejected<S>(s2, e2snap, e2, "pair_energy");
  Result r2;
  fill(r2);
  const Snapshot<Result> r2snap(r2);
  const Status s3 = pce::evaluate<Pair>(c.x, pce::SignedLength{c.side}, pen, c.proj, r2);
  check_signed_rejected<S>(s3, r2snap, r2, "evaluate");
}

template <class S, class Pair> void run_point_kind(Bytes& b, pce::Side side) {
  PointCase<S, Pair> c;
  c.side = side;
  c.x = decode_x<S, Pair::dofs>(b, KindTraits<Pair>::layout);
  const int penalty = b.u8() % 3;
  c.proj = kStrategies[b.u8() % kNumStrategies];
  g_case.projection = pce::to_string(c.proj);
  check_point_frame<S, Pair>(c);
  const double Lhint = c.fs == Status::ok ? double(c.f.d) : 1.0;
  const DecodedPenalty d = decode_penalty(b, penalty, Lhint);
  c.barrier = d.type == 2;
  c.activation = d.activation;
  with_penalty(d, [&](const auto& pen) { run_point_penalty<S, Pair>(c, pen); });
  run_point_signed<S, Pair>(c, d.quadratic);
}

}  // namespace

template <class S> void run_new_kind(Bytes& b, int kind) {
  const pce::Side side = (b.u8() & 1) ? pce::Side::negative : pce::Side::positive;
  g_case.length = side == pce::Side::positive ? "unsigned (and signed(positive): invalid_input)"
                                              : "unsigned (and signed(negative): invalid_input)";
  switch (kind) {
    case pce_fuzz_point_edge:
      g_case.pair = pce::PointEdge::name;
      run_point_kind<S, pce::PointEdge>(b, side);
      break;
    case pce_fuzz_point_point:
      g_case.pair = pce::PointPoint::name;
      run_point_kind<S, pce::PointPoint>(b, side);
      break;
    case pce_fuzz_closest_vf:
      g_case.pair = "closest_feature(vertex_face)";
      run_closest<S>(b, side, true);
      break;
    default:
      g_case.pair = "closest_feature(edge_edge)";
      run_closest<S>(b, side, false);
      break;
  }
}

}  // namespace pce_fuzz
