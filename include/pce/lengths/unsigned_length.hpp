// SPDX-License-Identifier: MIT
/// @file
/// The unsigned length `L = |l|` (the paper's `|e2⊥|`, Shi & Kim 2023 Sec. 4.4, which equals
/// |l| exactly at the frame). We differentiate it as `sgn(l) · l` rather than as the norm
/// `|e2⊥|`: the two are the same function of the 12 coordinates, but the norm form needs
/// the paper's "del" correction for the derivatives of α, β, γ, a difference of O(1/|l|)
/// terms that loses all accuracy as l → 0 (`docs/stability.md`, items 3–4). With
/// `σ = sgn(l)` the frame gradient is `σ(0,0,n̂)`, the frame Hessian `σ H_l`, and the
/// projected Hessian stays bounded as L → 0.
/// @note Not differentiable at l = 0; there we take σ = +1 (the limit from l > 0).
#pragma once

#include <pce/lengths/signed_length.hpp>

namespace pce {

/// Unsigned length `L = |l|`, with `σ = dL/dl = sgn(l)` (+1 at l = 0).
struct UnsignedLength {
  /// dL/dl = sgn(l), +1 at l = 0.
  template <class Scalar> PCE_HOST_DEVICE Scalar sigma(const Frame<Scalar>& f) const {
    return detail::sign_nonneg(f.l);
  }
};

}  // namespace pce
