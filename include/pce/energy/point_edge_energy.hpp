// SPDX-License-Identifier: MIT
/// @file
/// The energy `E = ψ(d)` of a point-edge pair (`frames/point_edge.hpp`), its gradient,
/// exact Hessian, closed-form frame-space eigensystem and every PSD strategy
/// (`docs/math.md` §9).
///
/// The distance is a function of the frame `c = (c0, c1)` alone, `d(c) = |c1 − (c1·ĉ0)ĉ0|`,
/// and `d(c(x; β)) = d(x)` for every β, so (as for the plane kinds, §3) the exact Hessian
/// is `Jᵀ Hc J` with β frozen. At the orthogonal frame, in the basis (t̂, û, n̂):
///
///     ∂d/∂c = (0, û),
///     H_d[c0,c0] = −(d/a²) ûûᵀ,   H_d[c0,c1] = −û t̂ᵀ/a,   H_d[c1,c1] = n̂n̂ᵀ/d,
///
/// i.e. one family `B = [[−d/a², −1/a], [−1/a, 0]]` on (û in slot 0, t̂ in slot 1) — the
/// plane kinds' (M14) with `l → d` — plus the line's curvature `1/d` along n̂ in slot 1.
/// The frame Hessian `ψ″ggᵀ + ψ′H_d` therefore has the eigenpairs (ψ″, g), (ψ′/d, n̂ in
/// slot 1), (ψ′λ_big, q_big), (ψ′λ_small, q_small) and two zeros.
#pragma once

#include <pce/energy/pair_energy.hpp>
#include <pce/frames/point_edge.hpp>

#include <array>

namespace pce {

/// Everything one point-edge pair needs, evaluated once.
template <class Scalar> struct PointEdgeEnergy {
  /// The pair's frame.
  PointEdgeFrame<Scalar> frame;
  Scalar length;  ///< L = d
  /// Ψ, ψ′, ψ″ at L.
  PenaltyDerivatives<Scalar> psi;
};

/// Evaluates the frame, the distance and the penalty of `x = (p, e0, e1)`. The length must
/// be `UnsignedLength`; a `SignedLength` gives `invalid_input` (a point-edge distance has
/// no side). Other statuses as `PointEdge::frame` and `pair_energy` of the plane kinds;
/// `out` is written only on `ok`.
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE Status pair_energy(const Vec9<Scalar>& x, const Length&, const Penalty& penalty,
                                   PointEdgeEnergy<Scalar>& out) {
  static_assert(std::is_same_v<Pair, PointEdge>, "a 9-coordinate pair is a PointEdge");
  return detail::distance_pair_energy<PointEdge, PointEdgeEnergy<Scalar>, Vec9<Scalar>, Length>(x, penalty, out);
}

namespace detail {
/// x-space vectors of the point-edge Hessian terms: `P.row(k) ⊗ d`.
template <class Scalar> struct PointEdgeVectors {
  Vec9<Scalar> w0;  ///< p0 ⊗ û (family, slot 0)
  Vec9<Scalar> wg;  ///< p1 ⊗ û = ∇d
  Vec9<Scalar> u1;  ///< p1 ⊗ t̂ (family, slot 1)
  Vec9<Scalar> wn;  ///< p1 ⊗ n̂ (curvature of the line distance)
  PCE_HOST_DEVICE explicit PointEdgeVectors(const PointEdgeFrame<Scalar>& f)
      : w0(kron<Scalar>(f.P.row(0), f.u)),
        wg(kron<Scalar>(f.P.row(1), f.u)),
        u1(kron<Scalar>(f.P.row(1), f.t)),
        wn(kron<Scalar>(f.P.row(1), f.n)) {}
};
}  // namespace detail

/// ∇E = ψ′ Jᵀ(0, û): point j gets ψ′ P(1,j) û.
template <class Scalar> PCE_HOST_DEVICE Vec9<Scalar> energy_gradient(const PointEdgeEnergy<Scalar>& e) {
  return detail::kron<Scalar>(e.frame.P.row(1), Vec3<Scalar>(e.psi.first * e.frame.u));
}

/// Exact Hessian `ψ″ wg wgᵀ + ψ′[−(d/a²) w0w0ᵀ − (w0u1ᵀ + u1w0ᵀ)/a + wn wnᵀ/d]`.
template <class Scalar> PCE_HOST_DEVICE Mat9<Scalar> energy_hessian(const PointEdgeEnergy<Scalar>& e) {
  const PointEdgeFrame<Scalar>& f = e.frame;
  const detail::PointEdgeVectors<Scalar> v(f);
  const Scalar c1 = e.psi.first;
  const Scalar m = -c1 * ((f.d / f.a) / f.a), mu = -c1 / f.a;
  detail::SymmetricSum<Scalar, 9> sum;
  sum.rank_one(e.psi.second, v.wg);
  sum.rank_two(v.w0, (Scalar(m / Scalar(2)) * v.w0 + mu * v.u1).eval());
  sum.rank_one(Scalar(c1 / f.d), v.wn);
  return sum.matrix();
}

/// Closed-form eigensystem of the frame Hessian `ψ″ggᵀ + ψ′H_d` (6×6, frame space c =
/// (e, r⊥)), ascending.
template <class Scalar>
PCE_HOST_DEVICE FrameEigensystem<Scalar, 6> energy_eigensystem(const PointEdgeEnergy<Scalar>& e) {
  const PointEdgeFrame<Scalar>& f = e.frame;
  const LengthFamily<Scalar> fam = length_family(f.d, f.a);
  const Scalar c1 = e.psi.first;
  std::array<Scalar, 6> val;
  std::array<Vec6<Scalar>, 6> vec;
  for (auto& v : vec) v.setZero();
  const Eigen::Matrix<Scalar, 2, 1> qb = fam.big(), qs = fam.small();
  val[0] = e.psi.second;
  vec[0].template segment<3>(3) = f.u;
  val[1] = c1 / f.d;
  vec[1].template segment<3>(3) = f.n;
  val[2] = c1 * fam.lambda_big;
  vec[2].template segment<3>(0) = qb[0] * f.u;
  vec[2].template segment<3>(3) = qb[1] * f.t;
  val[3] = c1 * fam.lambda_small;
  vec[3].template segment<3>(0) = qs[0] * f.u;
  vec[3].template segment<3>(3) = qs[1] * f.t;
  val[4] = val[5] = Scalar(0);
  vec[4].template segment<3>(0) = f.t;
  vec[5].template segment<3>(0) = f.n;
  return detail::sorted_eigensystem<Scalar, 6>(val, vec);
}

namespace detail {
/// `Jᵀ[f(ψ″)ggᵀ + Σ f(μ)qqᵀ]J` from rank-one terms (f = clamp or |·|).
template <class Scalar, class F> PCE_HOST_DEVICE Mat9<Scalar> filtered_hessian(const PointEdgeEnergy<Scalar>& e, F f) {
  const PointEdgeFrame<Scalar>& fr = e.frame;
  const PointEdgeVectors<Scalar> v(fr);
  SymmetricSum<Scalar, 9> sum;
  const Scalar c1 = e.psi.first;
  const Scalar cg = f(e.psi.second), cn = f(Scalar(c1 / fr.d));
  if (cg != Scalar(0)) sum.rank_one(cg, v.wg);
  if (cn != Scalar(0)) sum.rank_one(cn, v.wn);
  if (c1 == Scalar(0)) return sum.matrix();
  const LengthFamily<Scalar> fam = length_family(fr.d, fr.a);
  const Scalar mb = f(Scalar(c1 * fam.lambda_big)), ms = f(Scalar(c1 * fam.lambda_small));
  if (mb != Scalar(0)) sum.rank_one(Scalar(mb * fam.n2), (fam.s * v.w0 + fam.w * v.u1).eval());
  if (ms != Scalar(0)) sum.rank_one(Scalar(ms * fam.n2), (fam.w * v.w0 - fam.s * v.u1).eval());
  return sum.matrix();
}

/// Exact projection (`energy/exact_projection.hpp`): range basis `h_i ⊗ û` (i = 0, 1) for
/// {w0, wg}, `p̂1 ⊗ t̂` and `p̂1 ⊗ n̂`; the n̂ direction is an x-space eigenvector by itself.
template <class Scalar> PCE_HOST_DEVICE Mat9<Scalar> exact_projection(const PointEdgeEnergy<Scalar>& e) {
  using std::sqrt;
  const PointEdgeFrame<Scalar>& f = e.frame;
  const Eigen::Matrix<Scalar, 2, 3> h = helmert_basis<Scalar, 3>();
  const Eigen::Matrix<Scalar, 2, 2> R = h * f.P.transpose();
  const Scalar r1 = sqrt(f.P.row(1).squaredNorm());
  const Scalar c1 = e.psi.first;
  const Scalar m = -c1 * ((f.d / f.a) / f.a), mu = -c1 / f.a;
  Mat3<Scalar> S;
  S.template topLeftCorner<2, 2>() = R * Eigen::Matrix<Scalar, 2, 1>(m, e.psi.second).asDiagonal() * R.transpose();
  S.template block<2, 1>(0, 2) = (mu * r1) * R.col(0);
  S.template block<1, 2>(2, 0) = S.template block<2, 1>(0, 2).transpose();
  S(2, 2) = Scalar(0);
  const Eigen::Matrix<Scalar, 1, 3> p1 = f.P.row(1) / r1;
  Eigen::Matrix<Scalar, 9, 3> Q;
  Q.col(0) = kron<Scalar>(h.row(0), f.u);
  Q.col(1) = kron<Scalar>(h.row(1), f.u);
  Q.col(2) = kron<Scalar>(p1, f.t);
  Mat9<Scalar> H = projected_in_basis(Q, S);
  const Scalar cn = c1 / f.d;  // eigenvalue cn·|p1|² on p̂1 ⊗ n̂
  if (cn > Scalar(0)) {
    SymmetricSum<Scalar, 9> sum;
    sum.rank_one(cn, kron<Scalar>(f.P.row(1), f.n));
    H += sum.matrix();
  }
  return H;
}
}  // namespace detail

/// PSD (except for `none`) Hessian of the pair by the strategy `P`, chosen at compile time
/// (`Projection`; only that strategy is compiled).
template <Projection P, class Scalar> PCE_HOST_DEVICE Mat9<Scalar> projected_hessian(const PointEdgeEnergy<Scalar>& e) {
  using std::abs;
  const auto clamp = [](const Scalar& v) { return v > Scalar(0) ? v : Scalar(0); };
  if constexpr (P == Projection::numerical) {
    return project_psd(energy_hessian(e));
  } else if constexpr (P == Projection::analytic) {
    return detail::filtered_hessian(e, clamp);
  } else if constexpr (P == Projection::abs) {
    return detail::filtered_hessian(e, [](const Scalar& v) { return Scalar(abs(v)); });
  } else if constexpr (P == Projection::exact) {
    return detail::exact_projection(e);
  } else if constexpr (P == Projection::gauss_newton) {
    const Vec9<Scalar> gL = detail::kron<Scalar>(e.frame.P.row(1), e.frame.u);
    return clamp(e.psi.second) * gL * gL.transpose();
  } else {
    static_assert(P == Projection::none, "a strategy without a case");
    return energy_hessian(e);
  }
}

/// PSD (except for `none`) Hessian of the pair by the strategy chosen at run time (compiles
/// every strategy: `energy/projection.hpp`).
template <class Scalar>
PCE_HOST_DEVICE Mat9<Scalar> projected_hessian(const PointEdgeEnergy<Scalar>& e, Projection strategy) {
  return with_projection(strategy, [&e](auto p) { return projected_hessian<decltype(p)::value>(e); });
}

/// The instantiations `pce::precompiled` compiles (`core/precompiled.hpp`).
// (EXTERN is `extern` or nothing and S a type: neither can be parenthesised.)
// NOLINTBEGIN(bugprone-macro-parentheses)
#define PCE_POINT_EDGE_ENERGY_INSTANCES(EXTERN, S) \
  EXTERN template Mat9<S> projected_hessian<S>(const PointEdgeEnergy<S>&, Projection);
// NOLINTEND(bugprone-macro-parentheses)
PCE_DECLARE_PRECOMPILED(PCE_POINT_EDGE_ENERGY_INSTANCES)

}  // namespace pce
