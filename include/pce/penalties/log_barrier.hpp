// SPDX-License-Identifier: MIT
/// @file
/// IPC log barrier on a length (Li et al. 2020; Shi & Kim 2023, Sec. 3):
/// `ψ(L) = −k (L − d̂)² ln(L/d̂)` for `0 < L < d̂`, 0 for `L ≥ d̂`, undefined for L ≤ 0.
/// Domain: L > 0 (`in_domain`; the energy reports `Status::out_of_domain` otherwise).
/// Smoothness: C² at L = d̂ (ψ = ψ′ = ψ″ = 0 there), ψ → ∞ as L → 0⁺.
/// Units: k is energy per length², d̂ a length.
/// @note `ln(L/d̂)` is evaluated as `log1p((L − d̂)/d̂)` for L/d̂ > 1/2, where the plain
/// logarithm of a ratio near 1 would lose digits (`docs/stability.md`).
#pragma once

#include <pce/penalties/penalty.hpp>

#include <cmath>

namespace pce {

/// `ψ = −k (L − dhat)² ln(L/dhat)`, `ψ′ = −k (2(L − d̂) ln(L/d̂) + (L − d̂)²/L)`,
/// `ψ″ = −k (2 ln(L/d̂) + 4(L − d̂)/L − (L − d̂)²/L²)` on `0 < L < dhat`.
struct LogBarrierPenalty {
  double stiffness = 1.0;  ///< k ≥ 0
  double dhat = 1.0;       ///< barrier activation distance d̂ > 0

  /// Whether the parameters are admissible (finite, k ≥ 0, …); else `invalid_input`.
  PCE_HOST_DEVICE bool valid() const {
    return std::isfinite(stiffness) && stiffness >= 0 && std::isfinite(dhat) && dhat > 0;
  }

  /// The barrier is defined for L > 0 only (`out_of_domain` otherwise).
  template <class Scalar> PCE_HOST_DEVICE bool in_domain(const Scalar& L) const { return L > Scalar(0); }

  /// ψ(L), ψ′(L), ψ″(L).
  template <class Scalar> PCE_HOST_DEVICE PenaltyDerivatives<Scalar> evaluate(const Scalar& L) const {
    using std::log;
    using std::log1p;
    const Scalar h = Scalar(dhat);
    if (!(L < h)) return {Scalar(0), Scalar(0), Scalar(0)};
    const Scalar k = Scalar(stiffness), d = L - h;
    const Scalar lg = (L > h / Scalar(2)) ? Scalar(log1p(d / h)) : Scalar(log(L / h));
    const Scalar q = d / L;
    return {-k * d * d * lg, -k * d * (Scalar(2) * lg + q), -k * (Scalar(2) * lg + Scalar(4) * q - q * q)};
  }
};

}  // namespace pce
