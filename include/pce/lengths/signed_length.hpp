// SPDX-License-Identifier: MIT
/// @file
/// The signed length `L = side · l`, `l = e2⊥·n̂ = e2·(e0 × e1)/|e0 × e1|`
/// (Shi & Kim 2023, Eq. 9 of the supplement). `side` says which side of the face (or of
/// the edge pair) counts as outside; it is tracked by the caller, typically fixed when
/// the pair enters the contact set.
#pragma once

#include <pce/lengths/length_hessian.hpp>

namespace pce {

/// Which side of the pair's plane is outside: `L = +l` or `L = −l`.
enum class Side : int { positive = 1, negative = -1 };

/// Signed length `L = side · l`. Smooth everywhere the frame exists.
struct SignedLength {
  /// Which side of the plane counts as outside (L > 0).
  Side side = Side::positive;

  /// dL/dl: +1 or −1 according to `side`.
  template <class Scalar> PCE_HOST_DEVICE Scalar sigma(const Frame<Scalar>&) const {
    return side == Side::negative ? Scalar(-1) : Scalar(1);
  }
};

/// Length value `L = σ l` (σ = dL/dl; for the signed length σ = side).
template <class Scalar, class Length> PCE_HOST_DEVICE Scalar length_value(const Frame<Scalar>& f, const Length& len) {
  return len.sigma(f) * f.l;
}

/// Frame gradient `∂L/∂c = σ (0, 0, n̂)` (supplement Eq. 13), n̂ = `Frame::m_hat`.
template <class Scalar, class Length>
PCE_HOST_DEVICE Vec9<Scalar> length_gradient(const Frame<Scalar>& f, const Length& len) {
  Vec9<Scalar> g = Vec9<Scalar>::Zero();
  g.template segment<3>(6) = len.sigma(f) * f.m_hat;
  return g;
}

/// Frame Hessian `∂²L/∂c² = σ H_l` (supplement Eqs. 16–37), dense 9×9.
template <class Scalar, class Length>
PCE_HOST_DEVICE Mat9<Scalar> length_hessian(const Frame<Scalar>& f, const Length& len) {
  return detail::frame_hessian_blocks(f, len.sigma(f), Scalar(0)).dense();
}

/// Closed-form eigensystem of `σ H_l` (supplement Sec. 2): eigenvalues `σλ_big`,
/// `σλ_small` of both families and five zeros (one along the gradient), ascending.
template <class Scalar, class Length>
PCE_HOST_DEVICE FrameEigensystem<Scalar> length_eigensystem(const Frame<Scalar>& f, const Length& len) {
  return detail::frame_eigensystem(f, len.sigma(f), Scalar(0));
}

}  // namespace pce
