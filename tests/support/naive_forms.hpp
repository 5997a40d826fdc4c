// SPDX-License-Identifier: MIT
/// @file
/// The paper's *direct* forms of the pair energy — the "before" column of the table in
/// docs/stability.md (rows 1–10), which pce deliberately does not use. Test support only:
/// `pce-stability-table` measures them next to the library, and
/// `tests/test_naive_forms.cpp` checks that they are correct in benign cases (they are the
/// paper's exact formulas, only evaluated the direct way), so the comparison is honest.
///
/// Same vertex conventions as the library (`docs/conventions.md`):
/// vertex-face `x = (p, t0, t1, t2)`, `e0 = t1 − t0`, `e1 = t2 − t0`, `e2 = p − t0`;
/// edge-edge `x = (ea0, ea1, eb0, eb1)`, `e0 = ea1 − ea0`, `e1 = eb1 − eb0`, `e2 = eb0 − ea0`.
///
/// What "direct" means here, row by row of docs/stability.md:
///  1. `α = e0·e1/(e0·e0)`; β, γ by Cramer's rule on the normal equations `G θ = b`,
///     `G = [[e0·e0, e0·e1], [e0·e1, e1·e1]]`, `b = (e0·e2, e1·e2)`, with the Gram
///     determinant `det = (e0·e0)(e1·e1) − (e0·e1)²`.
///  2. `l = e2·n̂`, `n̂ = (e0 × e1)/|e0 × e1|` (no e2⊥ in the formula).
///  3. unsigned `u = |e2⊥|` (the norm), `e2⊥ = e2 − βe0 − γe1`; gradient direction
///     `ê2⊥ = e2⊥/|e2⊥|`: `∇u = Jᵀ(0, 0, ê2⊥)`.
///  4. unsigned Hessian: the frame Hessian of the norm, `Jᵀ[(I − ê2⊥ê2⊥ᵀ)/u in slot 2]J`,
///     plus the "del" correction for the derivatives of β, γ (u does not depend on α). With
///     `r = e2⊥`, `dr = dc2 − w`, `dc2 = de2 − βde0 − γde1` (the J part),
///     `w = e0 dβ + e1 dγ`, `Π = I − r̂r̂ᵀ`, the exact `d²u = drᵀΠdr/u + r̂·d²r` splits into
///     the frame term `dc2ᵀΠdc2/u` and
///         del = (−dc2ᵢᵀΠwⱼ − dc2ⱼᵀΠwᵢ + wᵢᵀΠwⱼ)/u + r̂·d²rᵢⱼ,
///         d²rᵢⱼ = −de0ᵢdβⱼ − de0ⱼdβᵢ − de1ᵢdγⱼ − de1ⱼdγᵢ − e0 d²βᵢⱼ − e1 d²γᵢⱼ,
///     with dθ and d²θ from differentiating `G θ = b` once and twice
///     (`G dθ = db − dG θ`, `G d²θ = d²b − d²G θ − dGᵢdθⱼ − dGⱼdθᵢ`), solved with the same
///     Cramer's rule. The terms `(r̂·e0) d²β`, `(r̂·e1) d²γ` are zero mathematically and
///     evaluated as written. Frame term and del term are both O(1/u) and cancel.
///  5. eigenvalues `λ = −l/(2a²)(1 ± √(1 + 4a²/|e2⊥|²))`, `a = |e0|` resp. `|e1⊥|`
///     (`e1⊥ = e1 − αe0`, the norm of the computed vector). 0·∞ = NaN at `e2⊥ = 0`: that
///     is the direct form's behaviour, reported, not fixed.
///  6. eigenvectors `(e2⊥, 0, ω e0)` (e0 family) and `(0, e2⊥, ω e1⊥)` (e1 family),
///     `ω = λ/(λ − l/|e2⊥|²)`, normalised. (In the orthonormal basis (n̂ in slot k, ê_k in
///     slot 2) with `e2⊥ = l n̂` this is `(l, ω a)`, and the second row of
///     `B_k = [[−l/a², −1/a], [−1/a, 0]]` asks for `ω = −l/(a²λ)`, which the characteristic
///     equation `a²λ² + lλ − 1 = 0` turns into the paper's ω — the analogue holds for both
///     families.)
///  7. `H_l = Σ λ q qᵀ` reassembled from the four pairs (dense 9×9), frame Hessian
///     `ψ″ggᵀ + σψ′H_l` with `g = (0, 0, n̂)`, pulled back with the dense `J = P ⊗ I3` built
///     from the direct α, β, γ.
///  8. The signed length's del term is zero mathematically; the direct form here omits it
///     too (so row 8 has no separate "before" in the table).
///  9. log barrier with the plain `log(L/d̂)` (`naive::penalty`); the quadratic, cubic and
///     user penalties use the library's `evaluate` (so row 11, the cubic's ψ″, is *not* part
///     of "before").
/// 10. no rescaling: every product is formed from the raw coordinates.
#pragma once

#include "conformance.hpp"

#include <cmath>
#include <limits>

namespace pce_test {

/// Outputs of the direct forms. `ok` is false if anything is NaN/Inf or a division by zero
/// occurred; the per-output flags say which outputs are usable (e.g. the unsigned value
/// `|e2⊥| = 0` is fine where its gradient direction is 0/0).
template <class S> struct NaiveOutputs {
  bool ok = false;
  bool value_ok = false, gradient_ok = false, hessian_ok = false;
  S length = S(0);  ///< L
  S value = S(0);   ///< ψ(L)
  pce::Vec12<S> gradient = pce::Vec12<S>::Zero();
  pce::Mat12<S> hessian = pce::Mat12<S>::Zero();
};

namespace naive {

/// ψ, ψ′, ψ″ of the library's penalty types, unchanged (quadratic, cubic, user penalties).
template <class S, class Penalty> pce::PenaltyDerivatives<S> penalty(const Penalty& p, const S& L) {
  return p.template evaluate<S>(L);
}

/// Row 9 "before": the log barrier with the plain logarithm `log(L/d̂)` everywhere.
/// Outside its domain (L ≤ 0) the logarithm gives NaN/−Inf, which the caller reports.
template <class S> pce::PenaltyDerivatives<S> penalty(const pce::LogBarrierPenalty& p, const S& L) {
  using std::log;
  const S h = S(p.dhat);
  if (!(L < h)) return {S(0), S(0), S(0)};
  const S k = S(p.stiffness), d = L - h, lg = log(L / h);
  return {-k * d * d * lg, -k * (S(2) * d * lg + d * d / L), -k * (S(2) * lg + S(4) * d / L - d * d / (L * L))};
}

/// Everything the direct forms derive from the three edges.
template <class S> struct Geometry {
  pce::Mat34<S> D;  ///< e = D x (rows e0, e1, e2)
  pce::Mat34<S> P;  ///< frame coefficients from the direct α, β, γ
  pce::Vec3<S> e0, e1, e2;
  S G00, G01, G11, b0, b1, det;  ///< normal equations G θ = b and the Gram determinant
  S alpha, beta, gamma;
  pce::Vec3<S> m, n;                   ///< m = e0 × e1, n̂ = m/|m|
  S mn;                                ///< |m|
  S l;                                 ///< e2·n̂ (row 2)
  pce::Vec3<S> c1, c2;                 ///< e1⊥ = e1 − αe0, e2⊥ = e2 − βe0 − γe1
  bool alpha_ok, theta_ok, normal_ok;  ///< no division by zero in α, in β and γ, in n̂
};

template <class S> Geometry<S> geometry(PairKind kind, const pce::Vec12<S>& x) {
  Geometry<S> g;
  const pce::Vec3<S> v0 = x.template segment<3>(0), v1 = x.template segment<3>(3), v2 = x.template segment<3>(6),
                     v3 = x.template segment<3>(9);
  if (kind == PairKind::vertex_face) {  // x = (p, t0, t1, t2)
    g.D << S(0), S(-1), S(1), S(0),     //
        S(0), S(-1), S(0), S(1),        //
        S(1), S(-1), S(0), S(0);
    g.e0 = v2 - v1, g.e1 = v3 - v1, g.e2 = v0 - v1;
  } else {                           // x = (ea0, ea1, eb0, eb1)
    g.D << S(-1), S(1), S(0), S(0),  //
        S(0), S(0), S(-1), S(1),     //
        S(-1), S(0), S(1), S(0);
    g.e0 = v1 - v0, g.e1 = v3 - v2, g.e2 = v2 - v0;
  }
  using std::sqrt;
  g.G00 = g.e0.dot(g.e0), g.G01 = g.e0.dot(g.e1), g.G11 = g.e1.dot(g.e1);
  g.b0 = g.e0.dot(g.e2), g.b1 = g.e1.dot(g.e2);
  g.det = g.G00 * g.G11 - g.G01 * g.G01;  // row 1
  g.alpha_ok = g.G00 != S(0);
  g.theta_ok = g.det != S(0);
  g.alpha = g.G01 / g.G00;
  g.beta = (g.b0 * g.G11 - g.b1 * g.G01) / g.det;  // Cramer's rule
  g.gamma = (g.G00 * g.b1 - g.G01 * g.b0) / g.det;
  g.m = g.e0.cross(g.e1);
  g.mn = sqrt(g.m.dot(g.m));
  g.normal_ok = g.mn != S(0);
  g.n = g.m / g.mn;
  g.l = g.e2.dot(g.n);  // row 2
  g.c1 = g.e1 - g.alpha * g.e0;
  g.c2 = g.e2 - g.beta * g.e0 - g.gamma * g.e1;
  g.P.row(0) = g.D.row(0);
  g.P.row(1) = g.D.row(1) - g.alpha * g.D.row(0);
  g.P.row(2) = g.D.row(2) - g.beta * g.D.row(0) - g.gamma * g.D.row(1);
  return g;
}

/// Dense frame Jacobian `J = P ⊗ I3` (9×12).
template <class S> Eigen::Matrix<S, 9, 12> jacobian(const Geometry<S>& g) {
  Eigen::Matrix<S, 9, 12> J = Eigen::Matrix<S, 9, 12>::Zero();
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int c = 0; c < 3; ++c) J(3 * k + c, 3 * j + c) = g.P(k, j);
  return J;
}

/// Rows 5–7: the signed length's frame Hessian `H_l = Σ λ q qᵀ` from the paper's
/// eigenvalues and eigenvectors (four pairs), dense 9×9. `ok` turns false on a division
/// by zero.
template <class S> pce::Mat9<S> length_hessian_from_eigenpairs(const Geometry<S>& g, bool& ok) {
  using std::sqrt;
  pce::Mat9<S> H = pce::Mat9<S>::Zero();
  const S u2 = g.c2.dot(g.c2);  // |e2⊥|²
  if (u2 == S(0)) ok = false;
  const pce::Vec3<S>* ck[2] = {&g.e0, &g.c1};
  for (int k = 0; k < 2; ++k) {
    const S a2 = ck[k]->dot(*ck[k]);  // a² = |e0|² resp. |e1⊥|²
    if (a2 == S(0)) ok = false;
    const S root = sqrt(S(1) + S(4) * a2 / u2);
    for (int sgn : {1, -1}) {
      const S lambda = -g.l / (S(2) * a2) * (S(1) + S(sgn) * root);
      const S den = lambda - g.l / u2;
      if (den == S(0)) ok = false;
      const S omega = lambda / den;
      pce::Vec9<S> q = pce::Vec9<S>::Zero();
      q.template segment<3>(3 * k) = g.c2;
      q.template segment<3>(6) = omega * *ck[k];
      const S qn = sqrt(q.dot(q));
      if (qn == S(0)) ok = false;
      q /= qn;
      H += lambda * q * q.transpose();
    }
  }
  return H;
}

/// Row 4: the del correction of the unsigned norm `u = |e2⊥|` for the derivatives of β, γ
/// (see the file comment), 12×12, *without* the factor ψ′.
template <class S> pce::Mat12<S> unsigned_del_term(const Geometry<S>& g, const pce::Vec3<S>& r, const S& u) {
  // Inverse of G by Cramer's rule (the direct form of row 1).
  const S i00 = g.G11 / g.det, i01 = -g.G01 / g.det, i11 = g.G00 / g.det;
  const S beta = g.beta, gamma = g.gamma;
  S dG00[12], dG01[12], dG11[12], dbeta[12], dgamma[12];
  pce::Vec3<S> w[12], dc2[12];
  const auto D = [&](int row, int i) { return g.D(row, i / 3); };
  for (int i = 0; i < 12; ++i) {
    const int c = i % 3;
    dG00[i] = S(2) * D(0, i) * g.e0[c];
    dG01[i] = D(0, i) * g.e1[c] + D(1, i) * g.e0[c];
    dG11[i] = S(2) * D(1, i) * g.e1[c];
    const S db0 = D(0, i) * g.e2[c] + D(2, i) * g.e0[c];
    const S db1 = D(1, i) * g.e2[c] + D(2, i) * g.e1[c];
    const S r0 = db0 - (dG00[i] * beta + dG01[i] * gamma);
    const S r1 = db1 - (dG01[i] * beta + dG11[i] * gamma);
    dbeta[i] = i00 * r0 + i01 * r1;
    dgamma[i] = i01 * r0 + i11 * r1;
    w[i] = g.e0 * dbeta[i] + g.e1 * dgamma[i];
    dc2[i].setZero();
    dc2[i][c] = g.P(2, i / 3);
  }
  const pce::Vec3<S> rh = r / u;
  const pce::Mat3<S> Pi = pce::Mat3<S>::Identity() - rh * rh.transpose();
  const S re0 = rh.dot(g.e0), re1 = rh.dot(g.e1);
  pce::Mat12<S> del;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      const int ci = i % 3, cj = j % 3;
      const S same = ci == cj ? S(1) : S(0);
      // Second derivatives of G and b (constants: G and b are quadratic in x).
      const S d2G00 = S(2) * D(0, i) * D(0, j) * same;
      const S d2G01 = (D(0, i) * D(1, j) + D(0, j) * D(1, i)) * same;
      const S d2G11 = S(2) * D(1, i) * D(1, j) * same;
      const S d2b0 = (D(0, i) * D(2, j) + D(0, j) * D(2, i)) * same;
      const S d2b1 = (D(1, i) * D(2, j) + D(1, j) * D(2, i)) * same;
      const S r0 = d2b0 - (d2G00 * beta + d2G01 * gamma) - (dG00[i] * dbeta[j] + dG01[i] * dgamma[j]) -
                   (dG00[j] * dbeta[i] + dG01[j] * dgamma[i]);
      const S r1 = d2b1 - (d2G01 * beta + d2G11 * gamma) - (dG01[i] * dbeta[j] + dG11[i] * dgamma[j]) -
                   (dG01[j] * dbeta[i] + dG11[j] * dgamma[i]);
      const S d2beta = i00 * r0 + i01 * r1, d2gamma = i01 * r0 + i11 * r1;
      // r̂·d²r, term by term as written.
      const S rd2r = -D(0, i) * rh[ci] * dbeta[j] - D(0, j) * rh[cj] * dbeta[i] - D(1, i) * rh[ci] * dgamma[j] -
                     D(1, j) * rh[cj] * dgamma[i] - re0 * d2beta - re1 * d2gamma;
      const S quad = -dc2[i].dot(Pi * w[j]) - dc2[j].dot(Pi * w[i]) + w[i].dot(Pi * w[j]);
      del(i, j) = quad / u + rd2r;
    }
  return del;
}

template <class S, class Penalty>
NaiveOutputs<S> pair_energy(PairKind kind, LengthKind length, const Penalty& pen, const pce::Vec12<S>& x) {
  NaiveOutputs<S> o;
  const Geometry<S> g = geometry(kind, x);
  const Eigen::Matrix<S, 9, 12> J = jacobian(g);
  bool value_ok = true, gradient_ok = true, hessian_ok = true;
  pce::Vec9<S> gc = pce::Vec9<S>::Zero();  // frame gradient of the length
  pce::Mat9<S> Hc;                         // frame Hessian of the energy
  pce::PenaltyDerivatives<S> psi;
  if (length != LengthKind::unsigned_) {
    const S sigma = length == LengthKind::signed_negative ? S(-1) : S(1);
    value_ok = g.normal_ok;
    gradient_ok = g.normal_ok && g.theta_ok;
    hessian_ok = gradient_ok && g.alpha_ok;
    o.length = sigma * g.l;
    psi = penalty<S>(pen, o.length);
    gc.template segment<3>(6) = g.n;  // g = (0, 0, n̂)
    const pce::Mat9<S> Hl = length_hessian_from_eigenpairs(g, hessian_ok);
    Hc = psi.second * gc * gc.transpose() + (sigma * psi.first) * Hl;
    o.value = psi.value;
    o.gradient = (sigma * psi.first) * (J.transpose() * gc);
    o.hessian = J.transpose() * Hc * J;
  } else {
    using std::sqrt;
    const S u = sqrt(g.c2.dot(g.c2));  // row 3: |e2⊥|
    value_ok = g.theta_ok;
    gradient_ok = g.theta_ok && u != S(0);
    hessian_ok = gradient_ok && g.alpha_ok;
    o.length = u;
    psi = penalty<S>(pen, u);
    const pce::Vec3<S> rh = g.c2 / u;
    gc.template segment<3>(6) = rh;  // ê2⊥
    Hc = psi.second * gc * gc.transpose();
    Hc.template block<3, 3>(6, 6) += psi.first * (pce::Mat3<S>::Identity() - rh * rh.transpose()) / u;
    o.value = psi.value;
    o.gradient = psi.first * (J.transpose() * gc);
    o.hessian = J.transpose() * Hc * J + psi.first * unsigned_del_term(g, g.c2, u);  // row 4
  }
  using std::isfinite;
  o.value_ok = value_ok && isfinite(o.value) && isfinite(o.length);
  o.gradient_ok = gradient_ok && pce::detail::all_finite(o.gradient) && isfinite(psi.first);
  o.hessian_ok = hessian_ok && pce::detail::all_finite(o.hessian) && isfinite(psi.second);
  o.ok = o.value_ok && o.gradient_ok && o.hessian_ok;
  return o;
}

}  // namespace naive

/// The pair energy in the paper's direct forms (rows 1–10 of docs/stability.md): value,
/// gradient and exact Hessian, for any pair kind, length kind and penalty of `PenaltySpec`.
template <class S>
NaiveOutputs<S> naive_pair_energy(PairKind kind, LengthKind length, const PenaltySpec& spec, const pce::Vec12<S>& x) {
  return with_penalty(spec, [&](const auto& pen) { return naive::pair_energy<S>(kind, length, pen, x); });
}

/// Compiled once per scalar type in pce_test_support (`support/measure_<scalar>.cpp`).
#define PCE_TEST_NAIVE_FORMS(EXTERN, S) \
  EXTERN template NaiveOutputs<S> naive_pair_energy<S>(PairKind, LengthKind, const PenaltySpec&, const pce::Vec12<S>&);
PCE_TEST_NAIVE_FORMS(extern, float)
PCE_TEST_NAIVE_FORMS(extern, double)
PCE_TEST_NAIVE_FORMS(extern, long double)

}  // namespace pce_test
