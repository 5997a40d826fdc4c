// SPDX-License-Identifier: MIT
/// @file
/// One-sided smoothed cubic penalty (Shi & Kim 2023, Sec. 3):
/// `ψ(L) = k (L − ε)² √((L − ε)² + δ)` for `L < ε`, else 0.
/// Domain: every L. Smoothness: C¹ for δ > 0 (ψ″ jumps from 2k√δ to 0 at L = ε);
/// C² for δ = 0, where ψ = k |L − ε|³. Units: k is energy per length³, ε a length,
/// δ a length².
/// @note Evaluated through r = d/s ∈ [−1, 1] (d = L − ε, s = √(d² + δ)):
/// `ψ = k s³ r²`, `ψ′ = k s² r (2 + r²)`, `ψ″ = k s (2 + 5r² − r⁴)`, which neither overflows
/// for large d nor divides 0/0 at d = δ = 0.
#pragma once

#include <pce/penalties/penalty.hpp>

#include <cmath>

namespace pce {

/// `ψ = k d² √(d² + δ)`, `d = L − eps < 0`; else 0.
struct CubicPenalty {
  double stiffness = 1.0;  ///< k ≥ 0
  double eps = 0.0;        ///< activation length ε
  double delta = 0.0;      ///< smoothing δ ≥ 0 (a squared length)

  /// Whether the parameters are admissible (finite, k ≥ 0, …); else `invalid_input`.
  PCE_HOST_DEVICE bool valid() const {
    return std::isfinite(stiffness) && stiffness >= 0 && std::isfinite(eps) && std::isfinite(delta) && delta >= 0;
  }

  /// ψ(L), ψ′(L), ψ″(L).
  template <class Scalar> PCE_HOST_DEVICE PenaltyDerivatives<Scalar> evaluate(const Scalar& L) const {
    using std::abs;
    using std::sqrt;
    const Scalar e = Scalar(eps);
    if (!(L < e)) return {Scalar(0), Scalar(0), Scalar(0)};
    const Scalar k = Scalar(stiffness), d = L - e, sd = sqrt(Scalar(delta));
    // s = hypot(d, √δ) without overflow or underflow.
    const Scalar ad = abs(d), big = ad > sd ? ad : sd, small = ad > sd ? sd : ad;
    if (!(big > Scalar(0))) return {Scalar(0), Scalar(0), Scalar(0)};
    const Scalar q = small / big, s = big * sqrt(Scalar(1) + q * q);
    const Scalar r = d / s, r2 = r * r;
    return {k * s * s * s * r2, k * s * s * r * (Scalar(2) + r2), k * s * (Scalar(2) + Scalar(5) * r2 - r2 * r2)};
  }
};

}  // namespace pce
