// SPDX-License-Identifier: MIT
/// @file
/// One-sided quadratic penalty (Shi & Kim 2023, Sec. 3; the classic penalty spring):
/// `ψ(L) = k (L − ε)²` for `L < ε`, else 0.
/// Domain: every L. Smoothness: C¹ (ψ″ jumps from 2k to 0 at L = ε).
/// Units: k is energy per length², ε a length (the activation distance).
#pragma once

#include <pce/penalties/penalty.hpp>

#include <cmath>

namespace pce {

/// `ψ = k (L − eps)²` for `L < eps`, else 0; `ψ′ = 2k (L − eps)`, `ψ″ = 2k` when active.
struct QuadraticPenalty {
  double stiffness = 1.0;  ///< k ≥ 0
  double eps = 0.0;        ///< activation length ε

  /// Whether the parameters are admissible (finite, k ≥ 0, …); else `invalid_input`.
  PCE_HOST_DEVICE bool valid() const { return std::isfinite(stiffness) && stiffness >= 0 && std::isfinite(eps); }

  /// ψ(L), ψ′(L), ψ″(L).
  template <class Scalar> PCE_HOST_DEVICE PenaltyDerivatives<Scalar> evaluate(const Scalar& L) const {
    const Scalar e = Scalar(eps);
    if (!(L < e)) return {Scalar(0), Scalar(0), Scalar(0)};
    const Scalar k = Scalar(stiffness), d = L - e;
    return {k * d * d, Scalar(2) * k * d, Scalar(2) * k};
  }
};

}  // namespace pce
