// SPDX-License-Identifier: MIT
/// @file
/// The fuzz body of `docs/fuzzing.md`, its templates shared by every kind and the two plane
/// kinds: decoding of the coordinates, the checks on a set of projections, the plane kinds
/// (vertex-face, edge-edge) through `pce::evaluate` and the lower-level per-pair functions,
/// and `run_scalar<S>`, the body for one scalar type. Included, with `fuzz_points.hpp` and
/// `fuzz_closest.hpp`, only by the translation unit of each scalar type (`fuzz_float.cpp`,
/// `fuzz_double.cpp`, `fuzz_long_double.cpp`; see `fuzz_common.hpp`), so its helpers stay
/// in unnamed namespaces. The rest of the body (reproducer, penalty decoding,
/// `pce_fuzz_one`) is in `fuzz_pair.cpp`.
///
/// Decoding is menu-driven, so that random bytes give interesting cases often: coordinates
/// come from geometric templates (a triangle and a vertex near its plane, two edges near
/// each other, a point near an edge's line, two nearly coincident points), small integers,
/// uniform values or special values (NaN, ±Inf, subnormals, the largest finite values,
/// `max_coordinate` and its neighbours, raw bit patterns), and are then edited by a few
/// operations (duplicate a point, make points collinear or coplanar, make edges nearly
/// parallel by a perturbation 10^-k, scale by 10^k or 2^k, offset by 10^k, rotate, nudge by
/// ulps, plant a special value).
#pragma once

#include "fuzz_common.hpp"

#include <cstdio>

namespace pce_fuzz {

// ---------------------------------------------------------------------------------------
// Coordinates.

template <class S> std::array<pce::Vec3<S>, 4> decode_points(Bytes& b, Layout layout) {
  using V = pce::Vec3<S>;
  std::array<V, 4> p;
  for (auto& q : p) q.setZero();
  const int npts = layout == Layout::point_edge ? 3 : layout == Layout::point_point ? 2 : 4;
  const int mode = b.u8() % 8;
  g_case.coord_mode = mode;
  switch (mode) {
    case 0:
    case 1:
    case 2: {  // template: a nice pair with one severity knob
      using std::cos;
      using std::sin;
      switch (layout) {
        case Layout::vertex_face: {
          const S d = (b.u8() % 4 == 0) ? S(std::fabs(double(severity<S>(b)))) : S(0.05 + b.unit());
          p[1] = V(0, 0, 0);
          p[2] = V(1, 0, 0);
          p[3] = V(S(b.sym()), d, 0);
          const S h = (b.u8() % 2) ? severity<S>(b) : S(b.sym());
          const S px = S(2 * b.sym());
          p[0] = V(px, S(2 * b.sym()), h);
          break;
        }
        case Layout::edge_edge: {
          const S h = (b.u8() % 2) ? severity<S>(b) : S(b.sym());
          const S th = (b.u8() % 4 == 0) ? severity<S>(b) : S(3 * b.sym());
          p[0] = V(-1, 0, 0);
          p[1] = V(1, 0, 0);
          const S cx = S(b.sym());
          const V c(cx, S(b.sym()), h);
          p[2] = c - V(cos(th), sin(th), 0);
          p[3] = c + V(cos(th), sin(th), 0);
          break;
        }
        case Layout::point_edge: {  // edge (0,0,0)-(len,0,0), p at distance h from its line
          const S len = (b.u8() % 4 == 0) ? S(std::fabs(double(severity<S>(b)))) : S(0.2 + 2 * b.unit());
          p[1] = V(0, 0, 0);
          p[2] = V(len, 0, 0);
          const S h = (b.u8() % 2) ? severity<S>(b) : S(b.sym());  // 0: on the line
          const S phi = S(3.2 * b.sym());
          // along the line: an endpoint exactly, between them, or beyond them
          const S px = (b.u8() % 4 == 0) ? S(b.range(0, 1)) * len : S(2 * b.sym());
          p[0] = V(px, h * cos(phi), h * sin(phi));
          break;
        }
        case Layout::point_point: {  // q = p + 0, 10^-k or a few ulps, or anywhere
          p[0] = sym3<S>(b);
          if (b.u8() % 4 == 0)
            p[1] = sym3<S>(b);
          else
            p[1] = p[0] + offset<S>(b);
          break;
        }
      }
      break;
    }
    case 3:
    case 4:  // small integers: exact coincidences, collinearity and coplanarity
      for (int q = 0; q < npts; ++q)
        for (int c = 0; c < 3; ++c) p[q][c] = S(b.range(-2, 2));
      break;
    case 5:
    case 6:  // uniform
      for (int q = 0; q < npts; ++q) p[q] = sym3<S>(b);
      break;
    default:  // coordinates from the special menu (each with probability 1/2), else uniform
      for (int q = 0; q < npts; ++q)
        for (int c = 0; c < 3; ++c) p[q][c] = (b.u8() & 1) ? special<S>(b) : S(b.sym());
      break;
  }
  const int nops = b.u8() % 5;
  g_case.ops.clear();
  for (int o = 0; o < nops; ++o) {
    const int op = b.u8() % 12;
    const int ri = b.u8(), rj = b.u8(), rk = b.u8();
    const int i = ri % npts, j = rj % npts, k = rk % npts;
    const int c = rj % 3;  // a coordinate (ops 7 and 10)
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%d(%d,%d,%d)", o ? " " : "", op, i, j, k);
    g_case.ops += buf;
    switch (op) {
      case 0:
        p[i] = p[j];
        break;   // exact duplicate
      case 1: {  // on the line through p[j], p[k], then off it by 10^-m
        const S t = (b.u8() % 2) ? S(b.range(-2, 3)) / S(2) : S(b.sym() * 3);
        p[i] = p[j] + t * (p[k] - p[j]);
        if (b.u8() % 2) p[i] += offset<S>(b);
        break;
      }
      case 2: {  // in the plane of p[j], p[k], p[m]
        const int m = b.u8() % npts;
        const S u = S(b.sym() * 2);
        p[i] = p[j] + u * (p[k] - p[j]) + S(b.sym() * 2) * (p[m] - p[j]);
        break;
      }
      case 3:
        p[i] += offset<S>(b);
        break;   // perturb by 10^-m
      case 4: {  // nearly parallel: p[i] − p[i^1] ∥ p[j] − p[k], up to 10^-m
        const int i2 = (i ^ 1) % npts;
        const S u = S(b.sym() * 2);
        p[i] = p[i2] + u * (p[j] - p[k]) + offset<S>(b);
        break;
      }
      case 5: {  // scale: 10^[-8, 8] or 2^[-128, 127]
        const S s = (b.u8() % 2) ? pow10<S>(b.range(-8, 8)) : S(std::ldexp(S(1), int(int8_t(b.u8()))));
        for (auto& q : p) q *= s;
        break;
      }
      case 6: {  // offset by 10^[0, 8] (1e6 often)
        const int e = (b.u8() % 2) ? 6 : b.range(0, 8);
        const V off = pow10<S>(e) * axis<S>(b);
        for (auto& q : p) q += off;
        break;
      }
      case 7:
        p[i][c] = special<S>(b);
        break;
      case 8:
        std::swap(p[i], p[j]);
        break;
      case 9: {  // rotate: no coordinate stays exact
        const S angle = S(b.sym() * 3.2);
        const Eigen::AngleAxis<S> R(angle, axis<S>(b));
        const pce::Mat3<S> M = R.toRotationMatrix();
        for (auto& q : p) q = M * q;
        break;
      }
      case 10: {  // nudge one coordinate by 1..4 ulps
        using std::nextafter;
        const S to = (b.u8() % 2) ? std::numeric_limits<S>::infinity() : -std::numeric_limits<S>::infinity();
        for (int n = b.range(1, 4); n > 0; --n) p[i][c] = nextafter(p[i][c], to);
        break;
      }
      default:  // all points in the plane z = p[j].z: exactly coplanar
        for (auto& q : p) q[2] = p[j][2];
        break;
    }
  }
  return p;
}

// ---------------------------------------------------------------------------------------
// Checks on a set of projections.

namespace {

long double max_abs(const LdMat& M) { return M.cwiseAbs().maxCoeff(); }
long double max2(long double a, long double b) { return a > b ? a : b; }

const char* check_name(int c) {
  static const char* names[pce_fuzz_checks] = {
      "analytic",       "numerical", "gauss_newton", "abs", "exact", "abs - analytic", "analytic - gauss_newton",
      "exact - hessian"};
  return names[c];
}

/// λ_min(M) ≥ −tol·scale, M symmetric up to tol·scale. `check` indexes `worst_psd`.
/// `underflow`: an intermediate of the library's computation underflowed (IEEE underflow
/// flag), so relative accuracy is not defined there; a violation is then counted, not failed.
template <class S> void check_psd(const LdMat& M, long double scale, int check, bool underflow) {
  PceFuzzStats& st = pce_fuzz_stats();
  const int si = scalar_index<S>();
  if (!(scale > 0)) return;
  const long double tol = psd_tolerance<S>();
  const long double asym = (M - M.transpose()).cwiseAbs().maxCoeff() / scale;
  if (underflow) ++st.psd_checks_underflow;

  if (asym > tol && underflow) {
    ++st.underflow_excused;
    return;
  }
  if (!underflow && double(asym) > st.worst_asym[si]) st.worst_asym[si] = double(asym);
  PCE_FUZZ_CHECK(asym <= tol, "%s projection not symmetric: max|P - P^T| / scale = %.3Le > %.1Le", check_name(check),
                 asym, tol);
  const MinEig e = min_eigenvalue(M);
  ++st.psd_checks;
  if (!e.converged) {
    ++st.eig_no_convergence;
    return;
  }
  const long double ratio = e.lambda_min / scale;
  if (ratio < -tol && underflow) {
    ++st.underflow_excused;
    return;
  }
  if (!underflow && double(ratio) < st.worst_psd[si][check]) st.worst_psd[si][check] = double(ratio);
  PCE_FUZZ_CHECK(ratio >= -tol, "%s not PSD: lambda_min = %.6Le, scale %.6Le, ratio %.3Le < -%.1Le", check_name(check),
                 e.lambda_min, scale, ratio, tol);
}

}  // namespace

template <class S> void check_projection_set(const ProjectionSet& ps) {
  PceFuzzStats& st = pce_fuzz_stats();
  const int si = scalar_index<S>();
  const long double tol = psd_tolerance<S>();
  const LdMat* P = ps.P;
  const bool* fin = ps.fin;
  const bool* uf = ps.uf;
  long double sc[kNumStrategies] = {};
  for (int s = 0; s < kNumStrategies; ++s) {
    if (fin[s])
      sc[s] = max_abs(P[s]);
    else if (s != 0 && fin[0])
      ++st.projection_overflow;
  }
  if (fin[0] && sc[0] > 0) {
    const long double asym = (P[0] - P[0].transpose()).cwiseAbs().maxCoeff() / sc[0];
    if (asym > tol && ps.underflow)
      ++st.underflow_excused;
    else
      PCE_FUZZ_CHECK(asym <= tol, "exact Hessian not symmetric: %.3Le", asym);
  }
  // PSD-ness of every strategy but none. numerical and exact are computed from (or as the
  // projection of) H, so their rounding is relative to max|H_ij|, which can be much larger
  // than max|P_ij| when H is mostly negative.
  if (fin[1]) check_psd<S>(P[1], sc[1], pce_fuzz_check_analytic, uf[1]);
  if (fin[2]) check_psd<S>(P[2], fin[0] ? max2(sc[2], sc[0]) : sc[2], pce_fuzz_check_numerical, uf[2]);
  if (fin[3]) check_psd<S>(P[3], sc[3], pce_fuzz_check_gauss_newton, uf[3]);
  if (fin[4]) check_psd<S>(P[4], sc[4], pce_fuzz_check_abs, uf[4]);
  if (fin[5]) check_psd<S>(P[5], fin[0] ? max2(sc[5], sc[0]) : sc[5], pce_fuzz_check_exact, uf[5]);
  // The Loewner orderings the definitions give: abs ⪰ analytic ⪰ gauss_newton, and
  // exact − H = Q max(−S, 0) Qᵀ ⪰ 0 (for H = Q S Qᵀ, whether or not Q is orthonormal).
  if (fin[4] && fin[1])
    check_psd<S>(P[4] - P[1], max2(sc[4], sc[1]), pce_fuzz_check_abs_minus_analytic, uf[4] || uf[1]);
  if (fin[1] && fin[3]) check_psd<S>(P[1] - P[3], max2(sc[1], sc[3]), pce_fuzz_check_analytic_minus_gn, uf[1] || uf[3]);
  if (fin[5] && fin[0]) check_psd<S>(P[5] - P[0], max2(sc[5], sc[0]), pce_fuzz_check_exact_minus_hessian, uf[5]);
  // exact and numerical are the same matrix up to rounding and up to the frame basis'
  // orthonormality defect δ (a basis off by δ moves the two apart by at most ~10 δ‖H‖_F,
  // docs/fuzzing.md): ‖P_exact − P_num‖_F relative to the largest of ‖H‖_F, ‖P_exact‖_F,
  // ‖P_num‖_F (computed on matrices divided by their largest entry, so that long double
  // cannot overflow) is at most 1024 ε + 16 δ.
  if (fin[0] && fin[2] && fin[5]) {
    const long double m = max2(sc[0], max2(sc[2], sc[5]));
    if (m > 0) {
      const LdMat H = P[0] / m, N = P[2] / m, X = P[5] / m;
      const long double scale = max2(H.norm(), max2(N.norm(), X.norm()));
      const long double ratio = (X - N).norm() / scale;
      const long double bound = tol + 16 * ps.basis_defect;
      const bool underflow = uf[2] || uf[5];
      ++st.exact_compared;
      if (ratio > tol && ratio <= bound) ++st.exact_basis_defect;
      if (ratio > bound && underflow) {
        ++st.underflow_excused;
      } else {
        if (!underflow) {
          if (double(ratio) > st.worst_exact_vs_numerical[si]) st.worst_exact_vs_numerical[si] = double(ratio);
          if (16 * ps.basis_defect <= tol && double(ratio) > st.worst_exact_vs_numerical_orthonormal[si])
            st.worst_exact_vs_numerical_orthonormal[si] = double(ratio);
          if (ratio > tol && ps.basis_defect > 0 &&
              double((ratio - tol) / ps.basis_defect) > st.worst_exact_per_defect[si])
            st.worst_exact_per_defect[si] = double((ratio - tol) / ps.basis_defect);
        }
        PCE_FUZZ_CHECK(
            ratio <= bound,
            "exact differs from numerical: |P_exact - P_numerical|_F / scale = %.3Le > 1024 eps + 16 delta = %.3Le "
            "(basis defect delta = %.3Le)",
            ratio, bound, ps.basis_defect);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------
// The plane kinds.

namespace {

/// The lower-level outputs of one `ok` energy (gradient, exact Hessian, eigensystem and
/// every projection) and the invariants on them that involve neither the pair kind, the
/// length nor the penalty. Templated on the scalar alone, so it is compiled 3 times rather
/// than once per scalar × pair × length × penalty (36).
template <class S> struct LowerLevel {
  pce::Vec12<S> g;
  pce::Mat12<S> H;
  pce::FrameEigensystem<S> eig;
  pce::Mat12<S> P[kNumStrategies];
  bool core_finite = false;
};

template <class S> void check_lower_level(const pce::PairEnergy<S>& e, LowerLevel<S>& out) {
  PceFuzzStats& st = pce_fuzz_stats();
  pce::Vec12<S>& g = out.g;
  pce::Mat12<S>& H = out.H;
  pce::FrameEigensystem<S>& eig = out.eig;
  if (e.psi.first != S(0) || e.psi.second != S(0)) ++st.active;
  g = pce::energy_gradient(e);
  H = pce::energy_hessian(e);
  eig = pce::energy_eigensystem(e);
  g_escape = &g;
  g_escape = &H;
  g_escape = &eig;
  // Underflow in the frame, ψ or the exact Hessian, and in each projection.
  const bool underflow = std::fetestexcept(FE_UNDERFLOW) != 0;
  ProjectionSet ps;
  compute_projections(e, H, underflow, out.P, ps);
  ps.basis_defect = basis_defect(e.frame.t0, e.frame.t1, e.frame.n);
  out.core_finite = finite(g) && finite(H) && finite(eig.values) && finite(e.length);

  // evaluate() tests only the eigenvalues for overflow: finite values must imply finite vectors.
  PCE_FUZZ_CHECK(!finite(eig.values) || finite(eig.vectors),
                 "eigensystem: finite eigenvalues but a non-finite eigenvector");
  PCE_FUZZ_CHECK(same_values(out.P[0], H) || !finite(H), "projection none differs from energy_hessian");
  if (finite(eig.values)) {
    int zeros = 0;
    bool has_psi2 = false;
    for (int i = 0; i < 9; ++i) {
      if (i + 1 < 9)
        PCE_FUZZ_CHECK(eig.values[i] <= eig.values[i + 1], "eigenvalues not ascending at %d: %.17Lg > %.17Lg", i,
                       (long double)eig.values[i], (long double)eig.values[i + 1]);
      if (eig.values[i] == S(0)) ++zeros;
      if (eig.values[i] == e.psi.second) has_psi2 = true;
    }
    PCE_FUZZ_CHECK(zeros >= 4, "eigensystem: %d exact zeros, expected at least 4", zeros);
    PCE_FUZZ_CHECK(has_psi2, "eigensystem: psi'' = %.17Lg is not an eigenvalue", (long double)e.psi.second);
  }
  check_projection_set<S>(ps);
}

template <class S, class Pair, class Length, class Penalty> void check_case(const pce::Vec12<S>& x, const Length& len,
                                                                            const Penalty& pen, bool barrier,
                                                                            double eps_or_dhat, pce::Projection proj) {
  using pce::Status;
  PceFuzzStats& st = pce_fuzz_stats();

  bool nonfinite = false, absurd = false;
  for (int i = 0; i < 12; ++i) {
    using std::abs;
    if (!std::isfinite(x[i]))
      nonfinite = true;
    else if (abs(x[i]) > pce::Constants<S>::max_coordinate())
      absurd = true;
  }
  const bool valid = pce::penalty_valid(pen);

  // --- the frame ------------------------------------------------------------------------
  pce::Frame<S> f;
  fill(f);
  const Snapshot<pce::Frame<S>> fsnap(f);
  const Status fs = Pair::frame(x, f);
  if (nonfinite || absurd)
    PCE_FUZZ_CHECK(fs == Status::invalid_input, "frame: coordinate %s but status %s",
                   nonfinite ? "NaN/Inf" : "beyond max_coordinate", pce::to_string(fs));
  else
    PCE_FUZZ_CHECK(fs == Status::ok || fs == Status::degenerate || fs == Status::overflow,
                   "frame: valid coordinates but status %s", pce::to_string(fs));
  if (fs != Status::ok) {
    PCE_FUZZ_CHECK(fsnap.unchanged(f), "frame: status %s but the output was written", pce::to_string(fs));
  } else {
    PCE_FUZZ_CHECK(finite(f.P) && finite(f.n) && finite(f.t0) && finite(f.t1) && finite(f.l) && finite(f.a0) &&
                       finite(f.a1) && finite(f.alpha) && finite(f.beta) && finite(f.gamma),
                   "frame: status ok but a non-finite member");
    PCE_FUZZ_CHECK(f.a0 >= S(0) && f.a1 >= S(0), "frame: negative |e0| or |e1perp|");
  }

  // --- pair_energy ----------------------------------------------------------------------
  S L = S(0);
  if (fs == Status::ok) L = len.sigma(f) * f.l;
  pce::PairEnergy<S> e;
  fill(e);
  const Snapshot<pce::PairEnergy<S>> esnap(e);
  g_escape = &e;
  std::feclearexcept(FE_ALL_EXCEPT);
  const Status ps = pce::pair_energy<Pair>(x, len, pen, e);
  if (!valid || nonfinite || absurd) {
    PCE_FUZZ_CHECK(ps == Status::invalid_input, "pair_energy: %s but status %s",
                   !valid ? "invalid penalty parameters" : "invalid coordinates", pce::to_string(ps));
  } else if (fs != Status::ok) {
    PCE_FUZZ_CHECK(ps == fs, "pair_energy: frame status %s but pair_energy status %s", pce::to_string(fs),
                   pce::to_string(ps));
  } else if (barrier && !(L > S(0))) {
    PCE_FUZZ_CHECK(ps == Status::out_of_domain, "pair_energy: log barrier at L = %.17Lg <= 0 but status %s",
                   (long double)L, pce::to_string(ps));
  } else {
    const pce::PenaltyDerivatives<S> d = pen.template evaluate<S>(L);
    const bool psi_finite = finite(d.value) && finite(d.first) && finite(d.second);
    PCE_FUZZ_CHECK(ps == (psi_finite ? Status::ok : Status::overflow), "pair_energy: status %s, psi %s finite",
                   pce::to_string(ps), psi_finite ? "is" : "is not");
  }
  if (ps == Status::out_of_domain)
    PCE_FUZZ_CHECK(barrier, "pair_energy: out_of_domain for a penalty defined everywhere");
  if (ps != Status::ok) {
    PCE_FUZZ_CHECK(esnap.unchanged(e), "pair_energy: status %s but the output was written", pce::to_string(ps));
  } else {
    PCE_FUZZ_CHECK(finite(e.length) && finite(e.psi.value) && finite(e.psi.first) && finite(e.psi.second),
                   "pair_energy: status ok but L = %.17Lg, psi = %.17Lg, psi' = %.17Lg, psi'' = %.17Lg",
                   (long double)e.length, (long double)e.psi.value, (long double)e.psi.first,
                   (long double)e.psi.second);
    PCE_FUZZ_CHECK(e.length == L && (e.sigma == S(1) || e.sigma == S(-1)), "pair_energy: length or sigma inconsistent");
    PCE_FUZZ_CHECK(e.frame.l == f.l && same_values(e.frame.P, f.P) && same_values(e.frame.n, f.n),
                   "pair_energy: frame differs from Pair::frame");
    if (std::is_same<Length, pce::UnsignedLength>::value)
      PCE_FUZZ_CHECK(e.length >= S(0), "unsigned length negative: %.17Lg", (long double)e.length);
    // ψ ≥ 0, ψ′ ≤ 0, ψ″ ≥ 0 for the three built-in penalties (k ≥ 0); all zero when inactive.
    PCE_FUZZ_CHECK(e.psi.value >= S(0) && e.psi.first <= S(0) && e.psi.second >= S(0),
                   "penalty signs: psi = %.17Lg, psi' = %.17Lg, psi'' = %.17Lg", (long double)e.psi.value,
                   (long double)e.psi.first, (long double)e.psi.second);
    const bool active = e.length < S(eps_or_dhat);
    if (!active)
      PCE_FUZZ_CHECK(e.psi.value == S(0) && e.psi.first == S(0) && e.psi.second == S(0),
                     "inactive penalty (L >= activation length) but psi, psi' or psi'' nonzero");
  }

  // --- lower-level outputs ----------------------------------------------------------------
  LowerLevel<S> low;
  if (ps == Status::ok) check_lower_level(e, low);
  const pce::Vec12<S>& g = low.g;
  const pce::Mat12<S>& H = low.H;
  const pce::FrameEigensystem<S>& eig = low.eig;
  const pce::Mat12<S>* const P = low.P;
  const bool core_finite = low.core_finite;

  // --- evaluate ---------------------------------------------------------------------------
  pce::PairResult<S> r;
  fill(r);
  const Snapshot<pce::PairResult<S>> rsnap(r);
  const Status es = pce::evaluate<Pair>(x, len, pen, proj, r);
  ++st.status[static_cast<int>(es)];
  ++st.kind_status[std::is_same<Pair, pce::EdgeEdge>::value ? pce_fuzz_edge_edge : pce_fuzz_vertex_face]
                  [static_cast<int>(es)];
  if (nonfinite)
    PCE_FUZZ_CHECK(es == Status::invalid_input, "evaluate: NaN/Inf coordinate but status %s", pce::to_string(es));
  if (ps != Status::ok) {
    PCE_FUZZ_CHECK(es == ps, "evaluate: status %s, pair_energy status %s", pce::to_string(es), pce::to_string(ps));
  } else {
    const bool all = core_finite && finite(P[static_cast<int>(proj)]);
    PCE_FUZZ_CHECK(es == (all ? Status::ok : Status::overflow),
                   "evaluate: status %s but the lower-level outputs are %sfinite", pce::to_string(es),
                   all ? "" : "not ");
  }
  if (es != Status::ok) {
    PCE_FUZZ_CHECK(rsnap.unchanged(r), "evaluate: status %s but the output was written", pce::to_string(es));
  } else {
    PCE_FUZZ_CHECK(finite(r.length) && finite(r.value) && finite(r.gradient) && finite(r.hessian) &&
                       finite(r.projected_hessian) && finite(r.eigen.values) && finite(r.eigen.vectors),
                   "evaluate: status ok but a non-finite output");
    PCE_FUZZ_CHECK(r.length == e.length && r.value == e.psi.value && same_values(r.gradient, g) &&
                       same_values(r.hessian, H) && same_values(r.projected_hessian, P[static_cast<int>(proj)]) &&
                       same_values(r.eigen.values, eig.values) && same_values(r.eigen.vectors, eig.vectors),
                   "evaluate: outputs differ from the lower-level functions");
  }
}

// ---------------------------------------------------------------------------------------
// Dispatch.

template <class S, class Pair, class Length> void run_length(Bytes& b, const pce::Vec12<S>& x, const Length& len) {
  const int penalty = b.u8() % 3;
  const pce::Projection proj = kStrategies[b.u8() % kNumStrategies];
  g_case.projection = pce::to_string(proj);
  // The geometry's own L, so that the activation lengths can be placed around it.
  double Lhint = 1.0;
  pce::Frame<S> f;
  if (Pair::frame(x, f) == pce::Status::ok) Lhint = double(len.sigma(f) * f.l);
  const DecodedPenalty d = decode_penalty(b, penalty, Lhint);
  with_penalty(d, [&](const auto& pen) { check_case<S, Pair>(x, len, pen, d.type == 2, d.activation, proj); });
}

template <class S, class Pair> void run_pair(Bytes& b, const pce::Vec12<S>& x, int length) {
  switch (length) {
    case 0:
      g_case.length = "signed(positive)";
      run_length<S, Pair>(b, x, pce::SignedLength{pce::Side::positive});
      break;
    case 1:
      g_case.length = "signed(negative)";
      run_length<S, Pair>(b, x, pce::SignedLength{pce::Side::negative});
      break;
    default:
      g_case.length = "unsigned";
      run_length<S, Pair>(b, x, pce::UnsignedLength{});
      break;
  }
}

}  // namespace

template <class S> void run_scalar(Bytes& b) {
  g_case.scalar = scalar_name<S>();
  // Half of the inputs are plane kinds (their frames have the most hard cases), an eighth
  // each point_edge, point_point and the two closest-feature candidates.
  static constexpr int kinds[8] = {pce_fuzz_vertex_face, pce_fuzz_vertex_face, pce_fuzz_edge_edge,
                                   pce_fuzz_edge_edge,   pce_fuzz_point_edge,  pce_fuzz_point_point,
                                   pce_fuzz_closest_vf,  pce_fuzz_closest_ee};
  const int kind = kinds[b.u8() % 8];
  if (kind != pce_fuzz_vertex_face && kind != pce_fuzz_edge_edge) {
    run_new_kind<S>(b, kind);
    return;
  }
  const bool edge_edge = kind == pce_fuzz_edge_edge;
  const int length = b.u8() % 3;
  g_case.pair = edge_edge ? pce::EdgeEdge::name : pce::VertexFace::name;
  const pce::Vec12<S> x = decode_x<S, 12>(b, edge_edge ? Layout::edge_edge : Layout::vertex_face);
  if (edge_edge)
    run_pair<S, pce::EdgeEdge>(b, x, length);
  else
    run_pair<S, pce::VertexFace>(b, x, length);
}

}  // namespace pce_fuzz
