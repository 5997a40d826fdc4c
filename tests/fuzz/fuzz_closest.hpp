// SPDX-License-Identifier: MIT
/// @file
/// The fuzz body of `docs/fuzzing.md`, closest-feature evaluation
/// (`pce::closest_feature_energy` of vertex-face and edge-edge candidates): statuses, the
/// chosen feature and points, the length between the plane (line) distance and the vertex
/// distances, the outputs on all 12 coordinates against the chosen kind's own, and every
/// projection. Decoding, the helpers and the projection checks are shared with
/// `fuzz_plane.hpp` and `fuzz_points.hpp` (`fuzz_common.hpp`); included, like them, only by
/// the translation unit of each scalar type (`fuzz_float.cpp`, ...), so its helpers stay in
/// an unnamed namespace.
///
/// The penalty-typed library calls are in `run_closest_penalty` (3 scalars × 3 penalties ×
/// 2 candidates); the checks in `check_closest`, templated on the scalar alone.
#pragma once

#include "fuzz_common.hpp"

#include <cstdio>

namespace pce_fuzz {
namespace {

using pce::Status;

template <class S> struct ClosestCase {
  bool vf = true;  ///< vertex-face candidate (else edge-edge)
  pce::Vec12<S> x;
  pce::Projection proj = pce::Projection::none;
  pce::Side side = pce::Side::positive;
  bool barrier = false;
  double activation = 0;
  bool valid = true;

  pce::ClosestFeatureEnergy<S> e;
  Status cs = Status::invalid_input;
  bool points_ok = false;  ///< e.points has the structure of e.feature for this candidate
  /// The chosen kind evaluated directly on the chosen points (with the same penalty).
  Status ds = Status::invalid_input;
  pce::PairEnergy<S> plane;
  pce::PointEdgeEnergy<S> edge;
  pce::PointPointEnergy<S> point;
};

/// Whether `feature` and `points` are possible for the candidate: vertex-face p = 0 with
/// triangle vertices 1..3; edge-edge one edge's endpoint with the other edge.
inline bool points_valid(bool vf, pce::Feature feature, const std::array<int, 3>& pt) {
  const auto in = [](int v, int lo, int hi) { return v >= lo && v <= hi; };
  switch (feature) {
    case pce::Feature::point_plane:
      return vf;
    case pce::Feature::line_line:
      return !vf;
    case pce::Feature::point_edge:
      if (vf) return pt[0] == 0 && in(pt[1], 1, 3) && in(pt[2], 1, 3) && pt[1] != pt[2];
      if (in(pt[0], 0, 1)) return (pt[1] == 2 && pt[2] == 3) || (pt[1] == 3 && pt[2] == 2);
      return in(pt[0], 2, 3) && ((pt[1] == 0 && pt[2] == 1) || (pt[1] == 1 && pt[2] == 0));
    case pce::Feature::point_point:
      if (vf) return pt[0] == 0 && in(pt[1], 1, 3);
      return (in(pt[0], 0, 1) && in(pt[1], 2, 3)) || (in(pt[0], 2, 3) && in(pt[1], 0, 1));
  }
  return false;
}

/// Whether some point-edge or point-point sub-pair the candidate can be evaluated as is
/// degenerate (closest-feature evaluation is degenerate only through its chosen point kind).
template <class S> bool some_subpair_degenerate(const pce::Vec12<S>& x, bool vf) {
  static constexpr int vf_pe[3][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}};
  static constexpr int ee_pe[4][3] = {{0, 2, 3}, {1, 2, 3}, {2, 0, 1}, {3, 0, 1}};
  static constexpr int vf_pp[3][2] = {{0, 1}, {0, 2}, {0, 3}};
  static constexpr int ee_pp[4][2] = {{0, 2}, {0, 3}, {1, 2}, {1, 3}};
  for (int c = 0; c < (vf ? 3 : 4); ++c) {
    const int* k = vf ? vf_pe[c] : ee_pe[c];
    pce::PointEdgeFrame<S> f;
    if (pce::PointEdge::frame(gather<9>(x, {k[0], k[1], k[2]}), f) == Status::degenerate) return true;
    const int* q = vf ? vf_pp[c] : ee_pp[c];
    pce::PointPointFrame<S> g;
    if (pce::PointPoint::frame(gather<6>(x, {q[0], q[1], -1}), g) == Status::degenerate) return true;
  }
  return false;
}

/// The candidate's own plane (line) frame.
template <class S> Status plane_frame(const pce::Vec12<S>& x, bool vf, pce::Frame<S>& f) {
  return vf ? pce::VertexFace::frame(x, f) : pce::EdgeEdge::frame(x, f);
}

/// Templated on the scalar alone (the candidate kind is `c.vf`), so it is compiled 3 times.
template <class S> void check_closest(ClosestCase<S>& c, const Snapshot<pce::ClosestFeatureEnergy<S>>& esnap) {
  PceFuzzStats& st = pce_fuzz_stats();
  const bool vf = c.vf;
  const Status cs = c.cs;
  ++st.status[static_cast<int>(cs)];
  ++st.kind_status[vf ? pce_fuzz_closest_vf : pce_fuzz_closest_ee][static_cast<int>(cs)];
  bool nonfinite = false;
  const bool invalid_coords = coordinates_invalid<S, 12>(c.x, nonfinite);
  const bool underflow = std::fetestexcept(FE_UNDERFLOW) != 0;  // in the classification, the frames or ψ

  if (!c.valid || invalid_coords)
    PCE_FUZZ_CHECK(cs == Status::invalid_input, "closest_feature_energy: %s but status %s",
                   !c.valid ? "invalid penalty parameters" : "invalid coordinates", pce::to_string(cs));
  else
    PCE_FUZZ_CHECK(cs != Status::invalid_input, "closest_feature_energy: valid inputs but status invalid_input");
  if (cs == Status::out_of_domain)
    PCE_FUZZ_CHECK(c.barrier, "closest_feature_energy: out_of_domain for a penalty defined everywhere");
  if (cs == Status::degenerate)
    PCE_FUZZ_CHECK(some_subpair_degenerate<S>(c.x, vf),
                   "closest_feature_energy: degenerate but no point-edge or point-point sub-pair is degenerate");
  if (cs != Status::ok) {
    PCE_FUZZ_CHECK(esnap.unchanged(c.e), "closest_feature_energy: status %s but the output was written",
                   pce::to_string(cs));
    return;
  }

  const pce::ClosestFeatureEnergy<S>& e = c.e;
  const int fi = static_cast<int>(e.feature);
  PCE_FUZZ_CHECK(c.points_ok,
                 "closest_feature_energy: feature %d with points (%d, %d, %d) impossible for a %s candidate", fi,
                 e.points[0], e.points[1], e.points[2], vf ? "vertex-face" : "edge-edge");
  if (!c.points_ok) return;
  ++st.feature[vf ? 0 : 1][fi];
  const bool plane = e.feature == pce::Feature::point_plane || e.feature == pce::Feature::line_line;
  const bool is_pe = e.feature == pce::Feature::point_edge;
  const char* fname = pce::to_string(e.feature);

  // The chosen kind evaluated directly on the chosen points gives the same energy.
  PCE_FUZZ_CHECK(c.ds == Status::ok, "closest_feature_energy: ok, but %s on the chosen points gives %s", fname,
                 pce::to_string(c.ds));
  if (c.ds != Status::ok) return;
  const S dlen = plane ? c.plane.length : is_pe ? c.edge.length : c.point.length;
  const pce::PenaltyDerivatives<S> dpsi = plane ? c.plane.psi : is_pe ? c.edge.psi : c.point.psi;
  PCE_FUZZ_CHECK(
      e.length == dlen && e.psi.value == dpsi.value && e.psi.first == dpsi.first && e.psi.second == dpsi.second,
      "closest_feature_energy: length or psi differs from %s evaluated directly", fname);
  PCE_FUZZ_CHECK(finite(e.length) && finite(e.psi.value) && finite(e.psi.first) && finite(e.psi.second),
                 "closest_feature_energy: status ok but a non-finite length or psi");
  PCE_FUZZ_CHECK(e.length >= S(0), "closest_feature_energy: negative length %.17Lg", (long double)e.length);
  check_psi(e.psi, e.length, c.activation, "closest_feature_energy");

  // --- gradient, Hessians, projections on all 12 coordinates ---
  if (e.psi.first != S(0) || e.psi.second != S(0)) ++st.active;
  pce::Vec12<S> g = pce::energy_gradient(e);
  pce::Mat12<S> H = pce::energy_hessian(e);
  g_escape = &g;
  g_escape = &H;
  const bool uf_h = std::fetestexcept(FE_UNDERFLOW) != 0;
  ProjectionSet ps;
  pce::Mat12<S> P[kNumStrategies];
  compute_projections(e, H, uf_h, P, ps);
  ps.basis_defect = plane   ? basis_defect(e.plane.frame.t0, e.plane.frame.t1, e.plane.frame.n)
                    : is_pe ? basis_defect(e.edge.frame.t, e.edge.frame.u, e.edge.frame.n)
                            : basis_defect(e.point.frame.u, e.point.frame.v, e.point.frame.w);

  // --- the distance between the primitives: at least the plane (line) distance |l| and at
  // most every vertex-to-vertex distance, up to rounding ---
  pce::Frame<S> f;
  g_escape = &f;
  std::feclearexcept(FE_ALL_EXCEPT);
  const Status fs = plane_frame<S>(c.x, vf, f);
  const bool bounds_underflow = underflow || std::fetestexcept(FE_UNDERFLOW) != 0;
  if (plane)
    PCE_FUZZ_CHECK(fs == Status::ok && e.length == (f.l < S(0) ? S(-f.l) : f.l),
                   "closest_feature_energy: %s but the length is not |l| of the plane frame", fname);
  {
    // In units of 2^k ≥ the largest coordinate difference (exact scaling, see unit_exponent).
    LdVec3 p[4];
    long double big = 0;
    for (int j = 0; j < 4; ++j) p[j] = point_ld<S>(c.x, j) - point_ld<S>(c.x, 0);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) big = (std::max)(big, (p[i] - p[j]).cwiseAbs().maxCoeff());
    const int k = unit_exponent(big);
    for (int j = 0; j < 4; ++j) p[j] = down(p[j], k);
    long double diam = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) diam = (std::max)(diam, (p[i] - p[j]).norm());
    // Conditioning of the plane (line) frame: |e0||e1|/|e0 × e1| (1/sin of the angle).
    // (Edges from the raw points, not from p[] relative to point 0: for long double a
    // difference of two such rounded differences is off by ε times the configuration's
    // size, which for a short edge far from point 0 is a wrong direction.)
    const LdVec3 e0 = down(
        vf ? LdVec3(point_ld<S>(c.x, 2) - point_ld<S>(c.x, 1)) : LdVec3(point_ld<S>(c.x, 1) - point_ld<S>(c.x, 0)), k);
    const LdVec3 e1 = down(
        vf ? LdVec3(point_ld<S>(c.x, 3) - point_ld<S>(c.x, 1)) : LdVec3(point_ld<S>(c.x, 3) - point_ld<S>(c.x, 2)), k);
    const long double cross = e0.cross(e1).norm();
    const long double cond = cross > 0 ? e0.norm() * e1.norm() / cross : std::numeric_limits<long double>::infinity();
    const long double eps = eps_ld<S>();
    // Rounding of the differences and cross products (256 ε of the configuration's size;
    // times the frame's conditioning where the plane or line frame is involved), and of a
    // subnormal result (a few denorm_min).
    const long double dmin = down(static_cast<long double>(std::numeric_limits<S>::denorm_min()), k);
    const long double tol_point = 256 * eps * diam + 4 * dmin, tol_plane = 256 * eps * diam * (1 + cond) + 4 * dmin;
    const long double L = down(static_cast<long double>(e.length), k);
    bool ok_bounds = true;
    long double bad = 0, bound = 0;
    // The lower bound needs a meaningful l: at an angle below about 64 ε (ε·cond > 1/64)
    // the computed normal is rounding noise (e0 × e1 is, yet not exactly zero, so the frame
    // is ok) and so is l — e.g. l = 1.5e4 for a float sliver with sin = 1.4e-8 whose vertex
    // is 2.2 away; closest-feature evaluation then never picks the plane kind with it
    // (docs/math.md §10), which the upper bounds below check.
    if (fs == Status::ok && eps * cond <= 1.0L / 64) {
      const long double l = down(std::fabs(static_cast<long double>(f.l)), k);
      if (!(l <= L + tol_plane)) ok_bounds = false, bad = l, bound = L + tol_plane;
    }
    static constexpr int vf_vv[3][2] = {{0, 1}, {0, 2}, {0, 3}};
    static constexpr int ee_vv[4][2] = {{0, 2}, {0, 3}, {1, 2}, {1, 3}};
    for (int v = 0; v < (vf ? 3 : 4); ++v) {
      const int* q = vf ? vf_vv[v] : ee_vv[v];
      const long double dv = (p[q[0]] - p[q[1]]).norm();
      const long double tol = plane ? tol_plane : tol_point;
      if (!(L <= dv + tol)) ok_bounds = false, bad = L, bound = dv + tol;
    }
    if (!ok_bounds && bounds_underflow) {
      ++st.underflow_excused;
    } else {
      PCE_FUZZ_CHECK(ok_bounds,
                     "closest_feature_energy (%s): length %.17Lg not between |l| = %.17Lg and the vertex distances "
                     "(scaled by 2^%d: %.17Le beyond the bound %.17Le)",
                     fname, (long double)e.length, fs == Status::ok ? std::fabs((long double)f.l) : -1.0L, -k, bad,
                     bound);
    }
  }

  // The gradient is finite whenever |ψ′| times the largest frame coefficient is representable.
  {
    long double pmax = 1;
    if (plane)
      pmax = static_cast<long double>(e.plane.frame.P.row(2).cwiseAbs().maxCoeff());
    else if (is_pe)
      pmax = static_cast<long double>(e.edge.frame.P.row(1).cwiseAbs().maxCoeff());
    const long double bound_g = std::fabs(static_cast<long double>(e.psi.first)) * pmax;
    if (bound_g < static_cast<long double>((std::numeric_limits<S>::max)()) / 8)
      PCE_FUZZ_CHECK(finite(g), "closest_feature_energy: non-finite gradient although |psi'| max|P| = %.6Le", bound_g);
  }
  // Exact zeros on the points the chosen point kind does not use.
  if (!plane) {
    bool zero = true;
    for (int j = 0; j < 4; ++j) {
      const bool used = j == e.points[0] || j == e.points[1] || (is_pe && j == e.points[2]);
      if (used) continue;
      if (!(g.template segment<3>(3 * j).array() == S(0)).all()) zero = false;
      for (int s = 0; s < kNumStrategies; ++s)
        if (!(P[s].template middleRows<3>(3 * j).array() == S(0)).all() ||
            !(P[s].template middleCols<3>(3 * j).array() == S(0)).all())
          zero = false;
    }
    PCE_FUZZ_CHECK(zero, "closest_feature_energy (%s): nonzero gradient or Hessian entries on a point it does not use",
                   fname);
  }
  // The same outputs as the chosen kind's, embedded.
  const int pi = static_cast<int>(c.proj);
  bool same = false, same_eig = false;
  const pce::FeatureEigenvalues<S> fe = pce::feature_eigenvalues(e);
  if (plane) {
    same = same_values(g, pce::energy_gradient(c.plane)) && same_values(H, pce::energy_hessian(c.plane)) &&
           same_values(P[pi], pce::projected_hessian(c.plane, c.proj));
    same_eig = fe.count == 9 && same_values(fe.values, pce::energy_eigensystem(c.plane).values);
  } else if (is_pe) {
    same = same_values(g, scatter<9>(pce::energy_gradient(c.edge), e.points)) &&
           same_values(H, scatter<9>(pce::energy_hessian(c.edge), e.points)) &&
           same_values(P[pi], scatter<9>(pce::projected_hessian(c.edge, c.proj), e.points));
    same_eig = fe.count == 6 && same_values(fe.values.template head<6>(), pce::energy_eigensystem(c.edge).values);
  } else {
    same = same_values(g, scatter<6>(pce::energy_gradient(c.point), e.points)) &&
           same_values(H, scatter<6>(pce::energy_hessian(c.point), e.points)) &&
           same_values(P[pi], scatter<6>(pce::projected_hessian(c.point, c.proj), e.points));
    same_eig = fe.count == 3 && same_values(fe.values.template head<3>(), pce::energy_eigensystem(c.point).values);
  }
  PCE_FUZZ_CHECK(same || !finite(H),
                 "closest_feature_energy (%s): gradient, Hessian or %s projection differs from the kind's own", fname,
                 pce::to_string(c.proj));
  PCE_FUZZ_CHECK(same_eig, "closest_feature_energy (%s): feature_eigenvalues differ from the kind's eigensystem",
                 fname);
  PCE_FUZZ_CHECK(same_values(P[0], H) || !finite(H),
                 "closest_feature_energy: projection none differs from energy_hessian");
  check_projection_set<S>(ps);
}

template <class S, class Pair, class Penalty> void run_closest_penalty(ClosestCase<S>& c, const Penalty& pen) {
  c.valid = pce::penalty_valid(pen);
  fill(c.e);
  const Snapshot<pce::ClosestFeatureEnergy<S>> esnap(c.e);
  g_escape = &c.e;
  std::feclearexcept(FE_ALL_EXCEPT);
  c.cs = pce::closest_feature_energy<Pair>(c.x, pce::UnsignedLength{}, pen, c.e);
  if (c.cs == Status::ok) {
    c.points_ok = points_valid(c.vf, c.e.feature, c.e.points);
    if (c.points_ok) {
      switch (c.e.feature) {
        case pce::Feature::point_plane:
        case pce::Feature::line_line:
          c.ds = pce::pair_energy<Pair>(c.x, pce::UnsignedLength{}, pen, c.plane);
          break;
        case pce::Feature::point_edge:
          c.ds = pce::pair_energy<pce::PointEdge>(gather<9>(c.x, c.e.points), pce::UnsignedLength{}, pen, c.edge);
          break;
        case pce::Feature::point_point:
          c.ds = pce::pair_energy<pce::PointPoint>(gather<6>(c.x, c.e.points), pce::UnsignedLength{}, pen, c.point);
          break;
      }
    }
  }
  check_closest<S>(c, esnap);
}

template <class S, class Pair> void run_closest_pair(Bytes& b, pce::Side side) {
  ClosestCase<S> c;
  c.side = side;
  constexpr bool vf = std::is_same<Pair, pce::VertexFace>::value;
  c.vf = vf;
  c.x = decode_x<S, 12>(b, vf ? Layout::vertex_face : Layout::edge_edge);
  const int penalty = b.u8() % 3;
  c.proj = kStrategies[b.u8() % kNumStrategies];
  g_case.projection = pce::to_string(c.proj);
  // The distance between the primitives, so that the activation lengths can be placed around it.
  double Lhint = 1.0;
  {
    pce::ClosestFeatureEnergy<S> probe;
    if (pce::closest_feature_energy<Pair>(c.x, pce::UnsignedLength{}, pce::QuadraticPenalty{0.0, 1.0}, probe) ==
        Status::ok)
      Lhint = double(probe.length);
  }
  const DecodedPenalty d = decode_penalty(b, penalty, Lhint);
  c.barrier = d.type == 2;
  c.activation = d.activation;
  with_penalty(d, [&](const auto& pen) { run_closest_penalty<S, Pair>(c, pen); });
  // A SignedLength request is invalid_input whatever else the input is (checked with the
  // decoded quadratic penalty only: one instantiation per scalar and candidate).
  pce::ClosestFeatureEnergy<S> e2;
  fill(e2);
  const Snapshot<pce::ClosestFeatureEnergy<S>> e2snap(e2);
  const Status s2 = pce::closest_feature_energy<Pair>(c.x, pce::SignedLength{c.side}, d.quadratic, e2);
  check_signed_rejected<S>(s2, e2snap, e2, "closest_feature_energy");
}

}  // namespace

template <class S> void run_closest(Bytes& b, pce::Side side, bool vf) {
  if (vf)
    run_closest_pair<S, pce::VertexFace>(b, side);
  else
    run_closest_pair<S, pce::EdgeEdge>(b, side);
}

}  // namespace pce_fuzz
