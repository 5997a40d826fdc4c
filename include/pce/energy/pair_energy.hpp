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
#include <pce/energy/plane_assembly.hpp>
#include <pce/energy/projection.hpp>
#include <pce/energy/psd_projection.hpp>
#include <pce/frames/edge_edge.hpp>
#include <pce/frames/vertex_face.hpp>
#include <pce/lengths/unsigned_length.hpp>
#include <pce/penalties/penalty.hpp>

#include <cmath>
#include <type_traits>

namespace pce {

/// Whether `Length` is the signed length (meaningless for the point kinds and for
/// closest-feature evaluation, which report `invalid_input` for it).
template <class Length> PCE_HOST_DEVICE constexpr bool is_signed_length() {
  return std::is_same_v<Length, SignedLength>;
}

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
/// `c Jᵀ(0,0,m̂)`: vertex j gets `(c P(2,j)) m̂`.
template <class Scalar, class Row>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE Vec12<Scalar> plane_gradient(const Scalar& c, const Row& p2, const Vec3<Scalar>& m) {
  Vec12<Scalar> g;
  for (int j = 0; j < 4; ++j) g.template segment<3>(3 * j) = (c * p2[j]) * m;
  return g;
}
/// The point kinds' `pair_energy` (their length is the frame's distance d, unsigned only):
/// `invalid_input` for a `SignedLength` or invalid penalty parameters, then the frame's
/// status, then the penalty's; `out` is written only on `ok`.
template <class Pair, class Energy, class X, class Length, class Penalty>
PCE_HOST_DEVICE Status distance_pair_energy(const X& x, const Penalty& penalty, Energy& out) {
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
PCE_HOST_DEVICE Status pair_energy(const Vec12<Scalar>& x, const Length& length, const Penalty& penalty,
                                   PairEnergy<Scalar>& out) {
  if (!penalty_valid(penalty)) return Status::invalid_input;
  PairEnergy<Scalar> e;
  const Status s = Pair::frame(x, e.frame);
  if (s != Status::ok) return s;
  e.sigma = length.sigma(e.frame);
  e.length = e.sigma * e.frame.l;
  const Status sp = evaluate_penalty(penalty, e.length, e.psi);
  if (sp != Status::ok) return sp;
  out = e;
  return Status::ok;
}

/// ∇E = σψ′ Jᵀ(0,0,n̂): vertex j gets σψ′ P(2,j) n̂ (with n̂ = `Frame::m_hat`, the normal l is
/// computed with; `value_gradient` gives the same bits without the rest of the frame).
template <class Scalar> PCE_HOST_DEVICE Vec12<Scalar> energy_gradient(const PairEnergy<Scalar>& e) {
  return detail::plane_gradient(Scalar(e.sigma * e.psi.first), e.frame.P.row(2), e.frame.m_hat);
}

/// Frame-space Hessian `ψ″ggᵀ + σψ′H_l` (blocks with exact zeros).
template <class Scalar> PCE_HOST_DEVICE FrameBlocks<Scalar> energy_frame_hessian(const PairEnergy<Scalar>& e) {
  return detail::frame_hessian_blocks(e.frame, Scalar(e.sigma * e.psi.first), e.psi.second);
}

namespace detail {
/// The terms of `energy_hessian(e)`, summed entry by entry (`energy/plane_assembly.hpp`).
template <class Scalar> PCE_HOST_DEVICE void hessian_terms(const PairEnergy<Scalar>& e, DenseSymmetric12<Scalar>& H) {
  plane_exact_hessian(PlaneValues<Scalar>(e.frame), Scalar(e.sigma * e.psi.first), e.psi.second, H);
}
/// 1/√ε, beyond which √(1+t²) rounds to t (`length_family`).
template <class Scalar> PCE_HOST_DEVICE Scalar family_big_t() {
  using std::sqrt;
  return Scalar(1) / sqrt(Constants<Scalar>::epsilon());
}
}  // namespace detail

/// Exact Hessian ∇²E = Jᵀ(ψ″ggᵀ + σψ′H_l)J, written as the rank-one and rank-two terms it
/// is (`docs/math.md` §6): `ψ″ w₂w₂ᵀ + Σ_k [m_k w_k w_kᵀ + μ_k (w_k u_kᵀ + u_k w_kᵀ)]` with
/// `m_k = −σψ′ l/a_k²`, `μ_k = −σψ′/a_k` (the families of (M14); exact zeros stay zero).
template <class Scalar> PCE_HOST_DEVICE Mat12<Scalar> energy_hessian(const PairEnergy<Scalar>& e) {
  Mat12<Scalar> M;
  detail::DenseSymmetric12<Scalar> H{M};
  detail::hessian_terms(e, H);
  H.mirror();
  return M;
}

/// Closed-form eigensystem of the frame Hessian `ψ″ggᵀ + σψ′H_l` (9×9, frame space),
/// ascending. The eigenvalues of ∇²E itself differ (J is not orthogonal).
template <class Scalar> PCE_HOST_DEVICE FrameEigensystem<Scalar> energy_eigensystem(const PairEnergy<Scalar>& e) {
  return detail::frame_eigensystem(e.frame, Scalar(e.sigma * e.psi.first), e.psi.second);
}

/// PSD (except for `none`) Hessian of the pair by the strategy `P`, chosen at compile time
/// (only that strategy is compiled); see `Projection`.
template <Projection P, class Scalar> PCE_HOST_DEVICE Mat12<Scalar> projected_hessian(const PairEnergy<Scalar>& e) {
  Mat12<Scalar> M;  // the one object returned, so that it is built in the caller's (no copy)
  detail::DenseSymmetric12<Scalar> H{M};
  const Scalar c1 = e.sigma * e.psi.first;
  if constexpr (P == Projection::analytic || P == Projection::abs) {
    detail::plane_filtered_hessian(detail::PlaneValues<Scalar>(e.frame), c1, e.psi.second, P == Projection::abs,
                                   detail::family_big_t<Scalar>(), H);
    H.mirror();
  } else if constexpr (P == Projection::exact) {
    detail::exact_projection(e.frame, c1, e.psi.second, M);
  } else if constexpr (P == Projection::gauss_newton) {  // rank one: max(ψ″,0) ∇L∇Lᵀ, ∇L = σ Jᵀ g
    Vec12<Scalar> gL;
    for (int j = 0; j < 4; ++j) gL.template segment<3>(3 * j) = (e.sigma * e.frame.P(2, j)) * e.frame.n;
    M.noalias() = (e.psi.second > Scalar(0) ? e.psi.second : Scalar(0)) * gL * gL.transpose();
  } else if constexpr (P == Projection::numerical) {
    detail::hessian_terms(e, H);
    H.mirror();
    M = project_psd(M);
  } else {
    static_assert(P == Projection::none, "a strategy without a case");
    detail::hessian_terms(e, H);
    H.mirror();
  }
  return M;
}

/// PSD (except for `none`) Hessian of the pair by the strategy chosen at run time (compiles
/// every strategy: `energy/projection.hpp`); the same bits as `projected_hessian<P>(e)`.
template <class Scalar>
PCE_HOST_DEVICE Mat12<Scalar> projected_hessian(const PairEnergy<Scalar>& e, Projection strategy) {
  return with_projection(strategy, [&e](auto p) { return projected_hessian<decltype(p)::value>(e); });
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
PCE_HOST_DEVICE Status evaluate(const VecN<Scalar, Pair::dofs>& x, const Length& length, const Penalty& penalty,
                                Projection strategy, PairResult<Scalar, Pair::dofs, Pair::frame_dofs>& out) {
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

/// The instantiations `pce::precompiled` compiles (`core/precompiled.hpp`).
// (EXTERN is `extern` or nothing and S a type: neither can be parenthesised.)
// NOLINTBEGIN(bugprone-macro-parentheses)
#define PCE_PAIR_ENERGY_INSTANCES(EXTERN, S) \
  EXTERN template Mat12<S> projected_hessian<S>(const PairEnergy<S>&, Projection);
// NOLINTEND(bugprone-macro-parentheses)
PCE_DECLARE_PRECOMPILED(PCE_PAIR_ENERGY_INSTANCES)

}  // namespace pce
