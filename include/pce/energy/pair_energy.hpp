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

#include <pce/energy/exact_projection.hpp>
#include <pce/energy/psd_projection.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/lengths/unsigned_length.hpp>
#include <pce/penalties/penalty.hpp>

#include <cmath>
#include <type_traits>

namespace pce {

/// How `projected_hessian` makes the Hessian positive semidefinite (`docs/math.md`).
enum class Projection {
  none,          ///< the exact Hessian ∇²E, not PSD in general
  analytic,      ///< Jᵀ [max(ψ″,0) ggᵀ + Σ max(σψ′λ,0) qqᵀ] J: clamp the closed-form eigenvalues
  numerical,     ///< V max(Λ,0) Vᵀ of the exact 12×12 Hessian: the true nearest PSD matrix
  gauss_newton,  ///< max(ψ″,0) ∇L ∇Lᵀ: drops the length's curvature
  abs,           ///< Jᵀ [|ψ″| ggᵀ + Σ |σψ′λ| qqᵀ] J: flip negative eigenvalues instead
  exact,         ///< the same matrix as `numerical` (the nearest PSD matrix in x-space), through
                 ///< the Hessian's rank ≤ 5 structure: a ≤ 5×5 eigenproblem, no 12×12 eigensolve
};

/// Name of a strategy, as `pce-probe` spells it.
inline const char* to_string(Projection p) {
  switch (p) {
    case Projection::none:
      return "none";
    case Projection::analytic:
      return "analytic";
    case Projection::numerical:
      return "numerical";
    case Projection::gauss_newton:
      return "gauss_newton";
    case Projection::abs:
      return "abs";
    case Projection::exact:
      return "exact";
  }
  return "unknown";
}

/// Whether `Length` is the signed length (meaningless for the point kinds and for
/// closest-feature evaluation, which report `invalid_input` for it).
template <class Length> constexpr bool is_signed_length() { return std::is_same_v<Length, SignedLength>; }

/// Everything one pair needs, evaluated once: the frame, σ = dL/dl, L and ψ, ψ′, ψ″.
template <class Scalar> struct PairEnergy {
  /// The pair's reduced frame (`frames/frame.hpp`).
  Frame<Scalar> frame;
  Scalar sigma;   ///< dL/dl (±1)
  Scalar length;  ///< L = σ l
  /// Ψ, ψ′, ψ″ at L.
  PenaltyDerivatives<Scalar> psi;
};

namespace detail {
/// ψ, ψ′, ψ″ at `L`: `out_of_domain` where the penalty is undefined, `overflow` when a
/// derivative is not finite; `psi` is written only on `ok`.
template <class Penalty, class Scalar>
Status evaluate_penalty(const Penalty& penalty, const Scalar& L, PenaltyDerivatives<Scalar>& psi) {
  if (!penalty_in_domain(penalty, L)) return Status::out_of_domain;
  const PenaltyDerivatives<Scalar> v = penalty.template evaluate<Scalar>(L);
  if (!is_finite(v.value) || !is_finite(v.first) || !is_finite(v.second)) return Status::overflow;
  psi = v;
  return Status::ok;
}
/// The point kinds' `pair_energy` (their length is the frame's distance d, unsigned only):
/// `invalid_input` for a `SignedLength` or invalid penalty parameters, then the frame's
/// status, then the penalty's; `out` is written only on `ok`.
template <class Pair, class Energy, class X, class Length, class Penalty>
Status distance_pair_energy(const X& x, const Penalty& penalty, Energy& out) {
  if (is_signed_length<Length>() || !penalty_valid(penalty)) return Status::invalid_input;
  Energy e;
  const Status s = Pair::frame(x, e.frame);
  if (s != Status::ok) return s;
  e.length = e.frame.d;
  const Status sp = evaluate_penalty(penalty, e.length, e.psi);
  if (sp != Status::ok) return sp;
  out = e;
  return Status::ok;
}
}  // namespace detail

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
  const Status sp = detail::evaluate_penalty(penalty, e.length, e.psi);
  if (sp != Status::ok) return sp;
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

namespace detail {
/// The x-space vectors `Jᵀ(d in slot k) = P.row(k) ⊗ d` the plane kinds' Hessians are made of.
template <class Scalar> struct PlaneVectors {
  Vec12<Scalar> w[3];  ///< w_k = p_k ⊗ n̂ (w_2 = ∇l)
  Vec12<Scalar> u[2];  ///< u_k = p_2 ⊗ ê_k
  explicit PlaneVectors(const Frame<Scalar>& f) {
    for (int k = 0; k < 3; ++k) w[k] = kron<Scalar>(f.P.row(k), f.n);
    u[0] = kron<Scalar>(f.P.row(2), f.t0);
    u[1] = kron<Scalar>(f.P.row(2), f.t1);
  }
};

/// The terms of `energy_hessian(e)`, not yet summed (`Projection::exact` adds two more).
template <class Scalar> SymmetricSum<Scalar, 12> hessian_terms(const PairEnergy<Scalar>& e) {
  const Frame<Scalar>& f = e.frame;
  const PlaneVectors<Scalar> v(f);
  const Scalar c1 = e.sigma * e.psi.first;
  const Scalar a[2] = {f.a0, f.a1};
  SymmetricSum<Scalar, 12> sum;
  sum.rank_one(e.psi.second, v.w[2]);
  for (int k = 0; k < 2; ++k) {
    const Scalar m = -c1 * ((f.l / a[k]) / a[k]), mu = -c1 / a[k];
    sum.rank_two(v.w[k], (Scalar(m / Scalar(2)) * v.w[k] + mu * v.u[k]).eval());
  }
  return sum;
}
}  // namespace detail

/// Exact Hessian ∇²E = Jᵀ(ψ″ggᵀ + σψ′H_l)J, written as the rank-one and rank-two terms it
/// is (`docs/math.md` §6): `ψ″ w₂w₂ᵀ + Σ_k [m_k w_k w_kᵀ + μ_k (w_k u_kᵀ + u_k w_kᵀ)]` with
/// `m_k = −σψ′ l/a_k²`, `μ_k = −σψ′/a_k` (the families of (M14); exact zeros stay zero).
template <class Scalar> Mat12<Scalar> energy_hessian(const PairEnergy<Scalar>& e) {
  return detail::hessian_terms(e).matrix();
}

/// Closed-form eigensystem of the frame Hessian `ψ″ggᵀ + σψ′H_l` (9×9, frame space),
/// ascending. The eigenvalues of ∇²E itself differ (J is not orthogonal).
template <class Scalar> FrameEigensystem<Scalar> energy_eigensystem(const PairEnergy<Scalar>& e) {
  return detail::frame_eigensystem(e.frame, Scalar(e.sigma * e.psi.first), e.psi.second);
}

namespace detail {

/// x-space `Jᵀ [f(ψ″) ggᵀ + Σ f(σψ′λ) q qᵀ] J` assembled from rank-one terms
/// `f(μ) (Jᵀq)(Jᵀq)ᵀ` (terms with f(μ) = 0 cost nothing: one per family for `analytic`).
template <class Scalar, class F> Mat12<Scalar> filtered_hessian(const PairEnergy<Scalar>& e, F f) {
  const Frame<Scalar>& fr = e.frame;
  const PlaneVectors<Scalar> v(fr);
  SymmetricSum<Scalar, 12> sum;
  const Scalar c2 = f(e.psi.second);
  if (c2 != Scalar(0)) sum.rank_one(c2, v.w[2]);
  const Scalar c1 = e.sigma * e.psi.first;
  if (c1 == Scalar(0)) return sum.matrix();
  const Scalar a[2] = {fr.a0, fr.a1};
  for (int k = 0; k < 2; ++k) {
    const LengthFamily<Scalar> fam = length_family(fr.l, a[k]);
    const Scalar mb = f(Scalar(c1 * fam.lambda_big)), ms = f(Scalar(c1 * fam.lambda_small));
    // q_big = (s, w)√n2 and q_small = (w, −s)√n2 in the basis (w_k, u_k); the √n2 goes
    // into the weight, so no square root is taken.
    if (mb != Scalar(0)) sum.rank_one(Scalar(mb * fam.n2), (fam.s * v.w[k] + fam.w * v.u[k]).eval());
    if (ms != Scalar(0)) sum.rank_one(Scalar(ms * fam.n2), (fam.w * v.w[k] - fam.s * v.u[k]).eval());
  }
  return sum.matrix();
}

}  // namespace detail

/// PSD (except for `none`) Hessian of the pair by the chosen strategy; see `Projection`.
template <class Scalar> Mat12<Scalar> projected_hessian(const PairEnergy<Scalar>& e, Projection strategy) {
  using std::abs;
  const auto clamp = [](const Scalar& v) { return v > Scalar(0) ? v : Scalar(0); };
  const auto flip = [](const Scalar& v) { return Scalar(abs(v)); };
  switch (strategy) {
    case Projection::none:
      return energy_hessian(e);
    case Projection::numerical:
      return project_psd(energy_hessian(e));
    case Projection::analytic:
      return detail::filtered_hessian(e, clamp);
    case Projection::abs:
      return detail::filtered_hessian(e, flip);
    case Projection::exact:
      return detail::exact_projection(e.frame, Scalar(e.sigma * e.psi.first), e.psi.second,
                                      [&e] { return detail::hessian_terms(e); });
    case Projection::gauss_newton: {  // rank one: max(ψ″,0) ∇L∇Lᵀ, ∇L = σ Jᵀ g
      Vec12<Scalar> gL;
      for (int j = 0; j < 4; ++j) gL.template segment<3>(3 * j) = (e.sigma * e.frame.P(2, j)) * e.frame.n;
      return clamp(e.psi.second) * gL * gL.transpose();
    }
  }
  return energy_hessian(e);
}

/// All outputs of one pair (`Dofs` coordinates, `FrameDofs` frame coordinates: 12 and 9
/// for the plane kinds, 9 and 6 for point-edge, 6 and 3 for point-point).
template <class Scalar, int Dofs = 12, int FrameDofs = 9> struct PairResult {
  Scalar length;                              ///< L
  Scalar value;                               ///< E = ψ(L)
  VecN<Scalar, Dofs> gradient;                ///< ∇E
  MatN<Scalar, Dofs> hessian;                 ///< exact ∇²E
  MatN<Scalar, Dofs> projected_hessian;       ///< by the requested strategy
  FrameEigensystem<Scalar, FrameDofs> eigen;  ///< closed-form, frame space, ascending
};

/// Evaluates everything for one pair of kind `Pair` (`VertexFace`, `EdgeEdge`, `PointEdge`,
/// `PointPoint`). On any non-ok status `out` is not written; a result that is not finite
/// gives `overflow`.
template <class Pair, class Scalar, class Length, class Penalty>
Status evaluate(const VecN<Scalar, Pair::dofs>& x, const Length& length, const Penalty& penalty, Projection strategy,
                PairResult<Scalar, Pair::dofs, Pair::frame_dofs>& out) {
  typename Pair::template Energy<Scalar> e;
  const Status s = pair_energy<Pair>(x, length, penalty, e);
  if (s != Status::ok) return s;
  PairResult<Scalar, Pair::dofs, Pair::frame_dofs> r;
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
