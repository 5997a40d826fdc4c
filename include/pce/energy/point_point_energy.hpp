// SPDX-License-Identifier: MIT
/// @file
/// The energy `E = ψ(d)`, `d = |p − q|`, of a point-point pair (`frames/point_point.hpp`):
/// gradient, exact Hessian, closed-form eigensystem and every PSD strategy
/// (`docs/math.md` §9). With `e = p − q` and `û = e/d`,
///
///     ∂d/∂e = û,    ∂²d/∂e² = (I − ûûᵀ)/d,
///     Hc = ψ″ ûûᵀ + (ψ′/d)(I − ûûᵀ),     ∇²E = [[Hc, −Hc], [−Hc, Hc]] = Jᵀ Hc J.
///
/// `J = (1, −1) ⊗ I3` has orthogonal rows (`J Jᵀ = 2I`), so the x-space eigenpairs are
/// `(2μ, (q, −q)/√2)` for the frame pairs `(μ, q)`: clamping in frame space *is* the
/// nearest PSD matrix, and `analytic` and `exact` coincide for this kind.
#pragma once

#include <pce/energy/pair_energy.hpp>
#include <pce/frames/point_point.hpp>

#include <array>

namespace pce {

/// Everything one point-point pair needs, evaluated once.
template <class Scalar> struct PointPointEnergy {
  /// The pair's frame.
  PointPointFrame<Scalar> frame;
  Scalar length;  ///< L = d
  /// Ψ, ψ′, ψ″ at L.
  PenaltyDerivatives<Scalar> psi;
};

/// Evaluates the frame, the distance and the penalty of `x = (p, q)`. The length must be
/// `UnsignedLength`; a `SignedLength` gives `invalid_input`. `degenerate` for p = q.
/// `out` is written only on `ok`.
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE Status pair_energy(const Vec6<Scalar>& x, const Length&, const Penalty& penalty,
                                   PointPointEnergy<Scalar>& out) {
  static_assert(std::is_same_v<Pair, PointPoint>, "a 6-coordinate pair is a PointPoint");
  return detail::distance_pair_energy<PointPoint, PointPointEnergy<Scalar>, Vec6<Scalar>, Length>(x, penalty, out);
}

namespace detail {
/// `[[Hc, −Hc], [−Hc, Hc]]` with `Hc = a ûûᵀ + b (I − ûûᵀ)`.
template <class Scalar>
PCE_HOST_DEVICE Mat6<Scalar> point_point_hessian(const PointPointFrame<Scalar>& f, const Scalar& a, const Scalar& b) {
  const Mat3<Scalar> Hc = b * Mat3<Scalar>::Identity() + (a - b) * (f.u * f.u.transpose());
  Mat6<Scalar> H;
  H << Hc, -Hc, -Hc, Hc;
  return H;
}
}  // namespace detail

/// ∇E = ψ′ (û, −û).
template <class Scalar> PCE_HOST_DEVICE Vec6<Scalar> energy_gradient(const PointPointEnergy<Scalar>& e) {
  Vec6<Scalar> g;
  g << e.psi.first * e.frame.u, -e.psi.first * e.frame.u;
  return g;
}

/// Exact Hessian `Jᵀ[ψ″ûûᵀ + (ψ′/d)(I − ûûᵀ)]J`.
template <class Scalar> PCE_HOST_DEVICE Mat6<Scalar> energy_hessian(const PointPointEnergy<Scalar>& e) {
  return detail::point_point_hessian(e.frame, e.psi.second, Scalar(e.psi.first / e.frame.d));
}

/// Closed-form eigensystem of the frame Hessian (3×3, frame space c = p − q), ascending:
/// (ψ″, û) and (ψ′/d, v̂), (ψ′/d, ŵ).
template <class Scalar>
PCE_HOST_DEVICE FrameEigensystem<Scalar, 3> energy_eigensystem(const PointPointEnergy<Scalar>& e) {
  const Scalar c = e.psi.first / e.frame.d;
  return detail::sorted_eigensystem<Scalar, 3>({e.psi.second, c, c}, {e.frame.u, e.frame.v, e.frame.w});
}

/// PSD (except for `none`) Hessian by the strategy `P`, chosen at compile time (only that
/// strategy is compiled); `analytic` and `exact` are the same matrix for this kind (see the
/// file comment).
template <Projection P, class Scalar>
PCE_HOST_DEVICE Mat6<Scalar> projected_hessian(const PointPointEnergy<Scalar>& e) {
  using std::abs;
  const auto clamp = [](const Scalar& v) { return v > Scalar(0) ? v : Scalar(0); };
  const Scalar c = e.psi.first / e.frame.d;
  if constexpr (P == Projection::numerical) {
    return project_psd(energy_hessian(e));
  } else if constexpr (P == Projection::analytic || P == Projection::exact) {
    return detail::point_point_hessian(e.frame, clamp(e.psi.second), clamp(c));
  } else if constexpr (P == Projection::abs) {
    return detail::point_point_hessian(e.frame, Scalar(abs(e.psi.second)), Scalar(abs(c)));
  } else if constexpr (P == Projection::gauss_newton) {
    return detail::point_point_hessian(e.frame, clamp(e.psi.second), Scalar(0));
  } else {
    static_assert(P == Projection::none, "a strategy without a case");
    return energy_hessian(e);
  }
}

/// PSD (except for `none`) Hessian by the strategy chosen at run time (compiles every
/// strategy: `energy/projection.hpp`).
template <class Scalar>
PCE_HOST_DEVICE Mat6<Scalar> projected_hessian(const PointPointEnergy<Scalar>& e, Projection strategy) {
  return with_projection(strategy, [&e](auto p) { return projected_hessian<decltype(p)::value>(e); });
}

/// The instantiations `pce::precompiled` compiles (`core/precompiled.hpp`).
// (EXTERN is `extern` or nothing and S a type: neither can be parenthesised.)
// NOLINTBEGIN(bugprone-macro-parentheses)
#define PCE_POINT_POINT_ENERGY_INSTANCES(EXTERN, S) \
  EXTERN template Mat6<S> projected_hessian<S>(const PointPointEnergy<S>&, Projection);
// NOLINTEND(bugprone-macro-parentheses)
PCE_DECLARE_PRECOMPILED(PCE_POINT_POINT_ENERGY_INSTANCES)

}  // namespace pce
