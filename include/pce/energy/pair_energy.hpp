// SPDX-License-Identifier: MIT
/// @file
/// The energy of one pair, `E(x) = ψ(L(c(x)))` (Shi & Kim 2023, Sec. 4), its gradient,
/// exact Hessian, closed-form frame-space eigensystem and PSD Hessians.
///
/// With σ = dL/dl, g = (0,0,n̂) and the frame map c = J x (`frames/frame.hpp`):
///
///     ∇E   = σ ψ′ Jᵀ g                                   (chain rule; supplement Eq. 13)
///     ∇²E  = Jᵀ (ψ″ g gᵀ + σ ψ′ H_l) J                    (paper Sec. 4.3; exact: the
///                                                          derivatives of α, β, γ cancel)
///
/// The frame matrix `ψ″ggᵀ + σψ′H_l` has the closed-form eigenpairs (ψ″, g), (σψ′λ, q)
/// for the four eigenpairs of H_l, and four zeros (`lengths/length_hessian.hpp`).
#pragma once

#include <pce/energy/psd_projection.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/lengths/unsigned_length.hpp>
#include <pce/penalties/penalty.hpp>

#include <cmath>

namespace pce {

/// How `projected_hessian` makes the Hessian positive semidefinite (`docs/math.md`).
enum class Projection {
  none,          ///< the exact Hessian ∇²E, not PSD in general
  analytic,      ///< Jᵀ [max(ψ″,0) ggᵀ + Σ max(σψ′λ,0) qqᵀ] J: clamp the closed-form eigenvalues
  numerical,     ///< V max(Λ,0) Vᵀ of the exact 12×12 Hessian: the true nearest PSD matrix
  gauss_newton,  ///< max(ψ″,0) ∇L ∇Lᵀ: drops the length's curvature
  abs,           ///< Jᵀ [|ψ″| ggᵀ + Σ |σψ′λ| qqᵀ] J: flip negative eigenvalues instead
};

/// Name of a strategy, as `pce-probe` spells it.
inline const char* to_string(Projection p) {
  switch (p) {
    case Projection::none: return "none";
    case Projection::analytic: return "analytic";
    case Projection::numerical: return "numerical";
    case Projection::gauss_newton: return "gauss_newton";
    case Projection::abs: return "abs";
  }
  return "unknown";
}

/// Everything one pair needs, evaluated once: the frame, σ = dL/dl, L and ψ, ψ′, ψ″.
template <class Scalar> struct PairEnergy {
  Frame<Scalar> frame;
  Scalar sigma;   ///< dL/dl (±1)
  Scalar length;  ///< L = σ l
  PenaltyDerivatives<Scalar> psi;
};

/// Evaluates the frame, the length and the penalty of pair `x` (`Pair` is `VertexFace` or
/// `EdgeEdge`). Returns `invalid_input` for bad coordinates or penalty parameters,
/// `degenerate` when the frame does not exist, `out_of_domain` when ψ is undefined at L,
/// `overflow` when ψ is not finite; `out` is written only on `ok`.
template <class Pair, class Scalar, class Length, class Penalty>
Status pair_energy(const Vec12<Scalar>& x, const Length& length, const Penalty& penalty, PairEnergy<Scalar>& out) {
  if (!penalty_valid(penalty)) return Status::invalid_input;
  PairEnergy<Scalar> e;
  const Status s = Pair::frame(x, e.frame);
  if (s != Status::ok) return s;
  e.sigma = length.sigma(e.frame);
  e.length = e.sigma * e.frame.l;
  if (!penalty_in_domain(penalty, e.length)) return Status::out_of_domain;
  e.psi = penalty.template evaluate<Scalar>(e.length);
  if (!detail::is_finite(e.psi.value) || !detail::is_finite(e.psi.first) || !detail::is_finite(e.psi.second))
    return Status::overflow;
  out = e;
  return Status::ok;
}

/// ∇E = σψ′ Jᵀ(0,0,n̂): vertex j gets σψ′ P(2,j) n̂.
template <class Scalar> Vec12<Scalar> energy_gradient(const PairEnergy<Scalar>& e) {
  const Scalar c = e.sigma * e.psi.first;
  Vec12<Scalar> g;
  for (int j = 0; j < 4; ++j) g.template segment<3>(3 * j) = (c * e.frame.P(2, j)) * e.frame.n;
  return g;
}

/// Frame-space Hessian `ψ″ggᵀ + σψ′H_l` (blocks with exact zeros).
template <class Scalar> FrameBlocks<Scalar> energy_frame_hessian(const PairEnergy<Scalar>& e) {
  return detail::frame_hessian_blocks(e.frame, Scalar(e.sigma * e.psi.first), e.psi.second);
}

/// Exact Hessian ∇²E = Jᵀ(ψ″ggᵀ + σψ′H_l)J.
template <class Scalar> Mat12<Scalar> energy_hessian(const PairEnergy<Scalar>& e) {
  return pullback(e.frame, energy_frame_hessian(e));
}

/// Closed-form eigensystem of the frame Hessian `ψ″ggᵀ + σψ′H_l` (9×9, frame space),
/// ascending. The eigenvalues of ∇²E itself differ (J is not orthogonal).
template <class Scalar> FrameEigensystem<Scalar> energy_eigensystem(const PairEnergy<Scalar>& e) {
  return detail::frame_eigensystem(e.frame, Scalar(e.sigma * e.psi.first), e.psi.second);
}

namespace detail {

/// Frame blocks of Σ f(μ) q qᵀ over the closed-form eigenpairs, f = max(·,0) or |·|.
template <class Scalar, class F> FrameBlocks<Scalar> filtered_frame_hessian(const PairEnergy<Scalar>& e, F f) {
  const Frame<Scalar>& fr = e.frame;
  FrameBlocks<Scalar> b = FrameBlocks<Scalar>::Zero();
  const Mat3<Scalar> nn = fr.n * fr.n.transpose();
  b.h22 = f(e.psi.second) * nn;
  const Scalar c1 = e.sigma * e.psi.first;
  if (c1 == Scalar(0)) return b;
  const Vec3<Scalar>* tk[2] = {&fr.t0, &fr.t1};
  Mat3<Scalar>* hkk[2] = {&b.h00, &b.h11};
  Mat3<Scalar>* hk2[2] = {&b.h02, &b.h12};
  const Scalar a[2] = {fr.a0, fr.a1};
  for (int k = 0; k < 2; ++k) {
    const LengthFamily<Scalar> fam = length_family(fr.l, a[k]);
    const Scalar mb = f(Scalar(c1 * fam.lambda_big)), ms = f(Scalar(c1 * fam.lambda_small));
    // Σ μ q qᵀ in the family's 2-D basis (n̂ in slot k, ê_k in slot 2), with
    // q_big = (s, w)√n2 and q_small = (w, −s)√n2: no square root needed.
    const Scalar w = fam.w, w2 = w * w;
    const Scalar s00 = fam.n2 * (mb + ms * w2);
    const Scalar s01 = fam.n2 * fam.s * w * (mb - ms);
    const Scalar s11 = fam.n2 * (mb * w2 + ms);
    *hkk[k] = s00 * nn;
    *hk2[k] = s01 * (fr.n * tk[k]->transpose());
    b.h22 += s11 * (*tk[k] * tk[k]->transpose());
  }
  return b;
}

}  // namespace detail

/// PSD (except for `none`) Hessian of the pair by the chosen strategy; see `Projection`.
template <class Scalar> Mat12<Scalar> projected_hessian(const PairEnergy<Scalar>& e, Projection strategy) {
  using std::abs;
  const auto clamp = [](const Scalar& v) { return v > Scalar(0) ? v : Scalar(0); };
  const auto flip = [](const Scalar& v) { return Scalar(abs(v)); };
  switch (strategy) {
    case Projection::none: return energy_hessian(e);
    case Projection::numerical: return project_psd(energy_hessian(e));
    case Projection::analytic: return pullback(e.frame, detail::filtered_frame_hessian(e, clamp));
    case Projection::abs: return pullback(e.frame, detail::filtered_frame_hessian(e, flip));
    case Projection::gauss_newton: {  // rank one: max(ψ″,0) ∇L∇Lᵀ, ∇L = σ Jᵀ g
      Vec12<Scalar> gL;
      for (int j = 0; j < 4; ++j) gL.template segment<3>(3 * j) = (e.sigma * e.frame.P(2, j)) * e.frame.n;
      return clamp(e.psi.second) * gL * gL.transpose();
    }
  }
  return energy_hessian(e);
}

/// All outputs of one pair.
template <class Scalar> struct PairResult {
  Scalar length;                      ///< L
  Scalar value;                       ///< E = ψ(L)
  Vec12<Scalar> gradient;             ///< ∇E
  Mat12<Scalar> hessian;              ///< exact ∇²E
  Mat12<Scalar> projected_hessian;    ///< by the requested strategy
  FrameEigensystem<Scalar> eigen;     ///< closed-form, frame space (9), ascending
};

/// Evaluates everything for one pair. On any non-ok status `out` is not written; a result
/// that is not finite gives `overflow`.
template <class Pair, class Scalar, class Length, class Penalty>
Status evaluate(const Vec12<Scalar>& x, const Length& length, const Penalty& penalty, Projection strategy,
                PairResult<Scalar>& out) {
  PairEnergy<Scalar> e;
  const Status s = pair_energy<Pair>(x, length, penalty, e);
  if (s != Status::ok) return s;
  PairResult<Scalar> r;
  r.length = e.length;
  r.value = e.psi.value;
  r.gradient = energy_gradient(e);
  r.hessian = energy_hessian(e);
  r.projected_hessian = strategy == Projection::none ? r.hessian : projected_hessian(e, strategy);
  r.eigen = energy_eigensystem(e);
  if (!detail::all_finite(r.gradient) || !detail::all_finite(r.hessian) || !detail::all_finite(r.projected_hessian) ||
      !detail::all_finite(r.eigen.values) || !detail::is_finite(r.length))
    return Status::overflow;
  out = r;
  return Status::ok;
}

}  // namespace pce
