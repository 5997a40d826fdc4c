// SPDX-License-Identifier: MIT
/// @file
/// The cheapest evaluations of one pair: the energy `E = ψ(L)` alone, and `E` with its gradient
///
///     ∇E = σψ′ Jᵀ(0,0,n̂)        (chain rule; supplement Eq. 13)
///
/// which a solver asks for far more often than a Hessian (every line-search trial, every
/// residual). For the plane kinds they build only the part of the frame these need: l, n̂ and
/// the third row of `P` (β and γ), not the basis (ê0, ê1), α's row or |e1⊥| the Hessians use,
/// and no `PairEnergy`. They run the frame's own arithmetic and checks (`frames/frame.hpp`), so
/// the status, `E` and `∇E` are those of `pair_energy` and `energy_gradient`, bit for bit.
/// The point kinds go through `pair_energy` (their frames are already this small).
#pragma once

#include <pce/energy/pair_energy.hpp>
#include <pce/energy/point_edge_energy.hpp>
#include <pce/energy/point_point_energy.hpp>

#include <type_traits>

namespace pce {

namespace detail {
/// σ = dL/dl of the two lengths, from l alone (what `Length::sigma(frame)` returns).
template <class Length, class Scalar> PCE_HOST_DEVICE Scalar length_sigma(const Length& length, const Scalar& l) {
  if constexpr (std::is_same_v<Length, SignedLength>)
    return length.side == Side::negative ? Scalar(-1) : Scalar(1);
  else {
    static_assert(std::is_same_v<Length, UnsignedLength>, "a length is SignedLength or UnsignedLength");
    return sign_nonneg(l);
  }
}

/// The plane kinds' lean evaluation: the status, L, ψ (ψ′, ψ″) and the part of the frame the
/// gradient needs, in the order and with the checks of `pair_energy`.
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE Status lean_plane_energy(const Vec12<Scalar>& x, const Length& length,
                                                           const Penalty& penalty, GradientFrame<Scalar>& f,
                                                           Scalar& sigma, PenaltyDerivatives<Scalar>& psi) {
  if (!penalty_valid(penalty)) return Status::invalid_input;
  const Status s = Pair::frame(x, f);
  if (s != Status::ok) return s;
  sigma = length_sigma(length, f.l);
  return evaluate_penalty(penalty, Scalar(sigma * f.l), psi);
}
}  // namespace detail

/// `E = ψ(L)` of pair `x`: the status and value of `pair_energy` (bit for bit), computing only
/// what the value needs. `value` is written only on `ok`.
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE Status value_only(const VecN<Scalar, Pair::dofs>& x, const Length& length, const Penalty& penalty,
                                  Scalar& value) {
  if constexpr (Pair::dofs == 12) {
    detail::GradientFrame<Scalar> f;
    Scalar sigma;
    PenaltyDerivatives<Scalar> psi;
    const Status s = detail::lean_plane_energy<Pair>(x, length, penalty, f, sigma, psi);
    if (s == Status::ok) value = psi.value;
    return s;
  } else {
    typename Pair::template Energy<Scalar> e;
    const Status s = pair_energy<Pair>(x, length, penalty, e);
    if (s == Status::ok) value = e.psi.value;
    return s;
  }
}

/// `E = ψ(L)` and `∇E = σψ′ Jᵀ(0,0,n̂)` of pair `x`: the value of `pair_energy` and the gradient
/// of `energy_gradient`, bit for bit, computing only what they need. The status is
/// `pair_energy`'s, or `overflow` when the gradient is not finite (as `evaluate`); `value` and
/// `gradient` are written only on `ok`.
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE Status value_gradient(const VecN<Scalar, Pair::dofs>& x, const Length& length, const Penalty& penalty,
                                      Scalar& value, VecN<Scalar, Pair::dofs>& gradient) {
  if constexpr (Pair::dofs == 12) {
    detail::GradientFrame<Scalar> f;
    Scalar sigma;
    PenaltyDerivatives<Scalar> psi;
    const Status s = detail::lean_plane_energy<Pair>(x, length, penalty, f, sigma, psi);
    if (s != Status::ok) return s;
    // as `energy_gradient`: vertex j gets (σψ′ P(2,j)) m̂; finite iff Σ 0·g_i = 0
    const Scalar c = sigma * psi.first;
    Scalar g[12], z[4];
    for (int j = 0; j < 4; ++j) {
      const Scalar cj = c * f.p2[j];
      for (int i = 0; i < 3; ++i) g[3 * j + i] = cj * f.m_hat[i];
      z[j] = (Scalar(0) * g[3 * j] + Scalar(0) * g[3 * j + 1]) + Scalar(0) * g[3 * j + 2];
    }
    if (!((z[0] + z[1]) + (z[2] + z[3]) == Scalar(0))) return Status::overflow;
    value = psi.value;
    for (int i = 0; i < 12; ++i) gradient[i] = g[i];
    return Status::ok;
  } else {
    typename Pair::template Energy<Scalar> e;
    const Status s = pair_energy<Pair>(x, length, penalty, e);
    if (s != Status::ok) return s;
    const VecN<Scalar, Pair::dofs> g = energy_gradient(e);
    if (!detail::all_finite(g)) return Status::overflow;
    value = e.psi.value;
    gradient = g;
    return Status::ok;
  }
}

}  // namespace pce
