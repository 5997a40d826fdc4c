// SPDX-License-Identifier: MIT
/// @file
/// Opt-in mollified pair energy, the continuous way through degenerate frames:
///
///     E_m(x) = m(X) ψ(L),   X = |e0 × e1|²,
///     m(X) = (X/X̂)(2 − X/X̂) for X < X̂,  1 otherwise            (IPC's edge-edge mollifier,
///                                                                Li et al. 2020, Sec. 4.3)
///
/// For X ≥ X̂ it is exactly the plain energy (`pair_energy.hpp`). As the edges become
/// parallel (edge-edge) or the triangle collapses (vertex-face), X → 0 and E_m → 0 with
/// gradient → 0, so the energy is C¹ across the degenerate set; there (X = 0, where the
/// plain energy reports `Status::degenerate`) it returns `ok` with E = 0, ∇E = 0, ∇²E = 0
/// and `mollifier = 0`. The fading force is never silent: `MollifiedEnergy::mollifier`
/// reports m for every pair, and a solver that uses this variant must let other pairs
/// (closest-feature point-edge / point-point) carry contact between parallel edges, as
/// IPC does. X̂ is a per-pair constant, typically `1e-3 |ea|²|eb|²` at rest
/// (`mollifier_threshold`).
///
/// X depends on the frame only through c0 × c1 (α, β, γ cancel as for l), so the exact
/// Hessian is again `Jᵀ H_F J` with the frame Hessian (docs/math.md §8)
///
///     H_F = mψ″ ggᵀ + mσψ′ H_l + ψ(m″ ∇X∇Xᵀ + m′ ∇²X) + σψ′m′ (∇X gᵀ + g ∇Xᵀ),
///
/// whose eigensystem splits into invariant subspaces of dimensions 3, 2, 2, 2, each solved
/// in closed form, except the 3×3 one, which takes a few Jacobi rotations (`detail::jacobi3`:
/// the trigonometric closed form loses its small eigenvalue, see there).
#pragma once

#include <pce/core/jacobi.hpp>
#include <pce/energy/pair_energy.hpp>

#include <array>
#include <cmath>
#include <type_traits>
#include <utility>

namespace pce {

/// IPC mollifier `m(X) = (X/X̂)(2 − X/X̂)` below the threshold X̂, 1 above: C¹ at X̂.
struct Mollifier {
  double threshold = 0;  ///< X̂ > 0, in length⁴ (same units as |e0 × e1|²)

  /// Whether X̂ is finite and positive (else evaluation reports `invalid_input`).
  PCE_HOST_DEVICE bool valid() const { return std::isfinite(threshold) && threshold > 0; }
};

/// X̂ = `factor` |e0|²|e1|² of a pair's rest configuration (IPC uses factor 1e-3).
template <class Pair, class Scalar>
PCE_HOST_DEVICE Scalar mollifier_threshold(const Vec12<Scalar>& rest, double factor = 1e-3) {
  Vec3<Scalar> e0, e1;
  if constexpr (std::is_same_v<Pair, VertexFace>) {
    e0 = rest.template segment<3>(6) - rest.template segment<3>(3);
    e1 = rest.template segment<3>(9) - rest.template segment<3>(3);
  } else {
    e0 = rest.template segment<3>(3) - rest.template segment<3>(0);
    e1 = rest.template segment<3>(9) - rest.template segment<3>(6);
  }
  return Scalar(factor) * e0.squaredNorm() * e1.squaredNorm();
}

/// Everything one mollified pair needs, evaluated once.
template <class Scalar> struct MollifiedEnergy {
  bool has_frame = false;   ///< false only where X = 0 (then every derivative is zero)
  PairEnergy<Scalar> base;  ///< the plain energy's frame, length and ψ (valid when has_frame)
  Scalar X = 0;             ///< |e0 × e1|²
  Scalar mollifier = 0;     ///< m(X) ∈ [0, 1]; 1 means identical to the plain energy
  ///@{
  Scalar dm = 0, d2m = 0;  ///< m′(X), m″(X)
  ///@}
  Scalar value = 0;  ///< m ψ
};

/// Evaluates the mollified energy of pair `x`. Statuses as `pair_energy`, except that a
/// vanishing `e0 × e1` (parallel edges, zero-area triangle, zero-length edge) is `ok`
/// with `mollifier = 0`; `invalid_input` also for an invalid `Mollifier`.
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE Status mollified_pair_energy(const Vec12<Scalar>& x, const Length& length, const Penalty& penalty,
                                             const Mollifier& mollifier, MollifiedEnergy<Scalar>& out) {
  if (!mollifier.valid() || !penalty_valid(penalty)) return Status::invalid_input;
  MollifiedEnergy<Scalar> r;
  const Status s = pair_energy<Pair>(x, length, penalty, r.base);
  if (s == Status::degenerate) {  // X = 0 in the rescaled coordinates: the energy is 0 to first order
    out = r;
    return Status::ok;
  }
  if (s != Status::ok) return s;
  r.has_frame = true;
  const Frame<Scalar>& f = r.base.frame;
  using std::sqrt;
  const Scalar sh = sqrt(Scalar(mollifier.threshold));
  const Scalar q = (f.a0 / sh) * f.a1;  // s/√X̂, s = |e0 × e1| = a0 a1
  r.X = (f.a0 * f.a1) * (f.a0 * f.a1);
  const Scalar Q = q * q;  // X/X̂
  if (Q < Scalar(1)) {
    const Scalar Xh = Scalar(mollifier.threshold);
    r.mollifier = Q * (Scalar(2) - Q);
    r.dm = (Scalar(2) - Scalar(2) * Q) / Xh;
    r.d2m = Scalar(-2) / (Xh * Xh);
  } else {
    r.mollifier = Scalar(1);
  }
  r.value = r.mollifier * r.base.psi.value;
  if (!detail::is_finite(r.value)) return Status::overflow;
  out = r;
  return Status::ok;
}

namespace detail {

/// Coefficients of H_F (docs/math.md §8): A = ψm″, B = ψm′, C = σψ′m′, D = mσψ′, E = mψ″.
template <class Scalar> struct MollifiedCoefficients { Scalar A, B, C, D, E, s; };

template <class Scalar>
PCE_HOST_DEVICE MollifiedCoefficients<Scalar> mollified_coefficients(const MollifiedEnergy<Scalar>& e) {
  const PairEnergy<Scalar>& b = e.base;
  return {b.psi.value * e.d2m,          b.psi.value * e.dm,
          b.sigma * b.psi.first * e.dm, e.mollifier * b.sigma * b.psi.first,
          e.mollifier * b.psi.second,   b.frame.a0 * b.frame.a1};
}

/// X ≥ X̂: the mollified energy is the plain one, evaluated by the plain (faster) code.
template <class Scalar> PCE_HOST_DEVICE bool unmollified(const MollifiedEnergy<Scalar>& e) {
  return e.mollifier == Scalar(1) && e.dm == Scalar(0);
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations with no
/// absolute threshold (`core/jacobi.hpp`). Unlike the trigonometric closed form it keeps
/// small eigenvalues of graded matrices accurate to their own size (Demmel & Veselić 1992),
/// which matters here: the {x0, y1, z2} block has entries O(1), O(s), O(s²) near parallel
/// edges and its pullback multiplies the z2 part by |J|² ~ 1/s².
template <class Scalar> PCE_HOST_DEVICE void jacobi3(Mat3<Scalar>& A, Mat3<Scalar>& V) {
  jacobi_eigen<Scalar, 3>(A, V, Scalar(0));
}

/// Unit 9-vector with direction `d` in frame slot `k`.
template <class Scalar> PCE_HOST_DEVICE Vec9<Scalar> slot(int k, const Vec3<Scalar>& d) {
  Vec9<Scalar> v = Vec9<Scalar>::Zero();
  v.template segment<3>(3 * k) = d;
  return v;
}

}  // namespace detail

/// ∇E_m = mσψ′ Jᵀg + ψ m′ Jᵀ∇X, ∇X = 2s (a1 ê0, a0 ê1, 0) in frame space.
template <class Scalar> PCE_HOST_DEVICE Vec12<Scalar> energy_gradient(const MollifiedEnergy<Scalar>& e) {
  if (!e.has_frame) return Vec12<Scalar>::Zero();
  if (detail::unmollified(e)) return energy_gradient(e.base);
  const Frame<Scalar>& f = e.base.frame;
  const auto c = detail::mollified_coefficients(e);
  Vec9<Scalar> gc;
  gc << (Scalar(2) * c.s * f.a1 * c.B) * f.t0, (Scalar(2) * c.s * f.a0 * c.B) * f.t1, c.D * f.n;
  return pullback(f, gc);
}

/// Frame Hessian H_F of the mollified energy (dense 9×9, docs/math.md §8).
template <class Scalar> PCE_HOST_DEVICE Mat9<Scalar> energy_frame_hessian(const MollifiedEnergy<Scalar>& e) {
  if (!e.has_frame) return Mat9<Scalar>::Zero();
  const Frame<Scalar>& f = e.base.frame;
  const auto c = detail::mollified_coefficients(e);
  using detail::slot;
  const Vec9<Scalar> x0 = slot(0, f.t0), y0 = slot(0, f.t1), x1 = slot(1, f.t0), y1 = slot(1, f.t1), z0 = slot(0, f.n),
                     z1 = slot(1, f.n), g = slot(2, f.n);
  const Vec9<Scalar> ds = f.a1 * x0 + f.a0 * y1;  // ∇s
  const Vec9<Scalar> dX = Scalar(2) * c.s * ds;   // ∇X
  // ∇²s = (x0 y1ᵀ + y1 x0ᵀ) − (y0 x1ᵀ + x1 y0ᵀ) + (a1/a0) z0z0ᵀ + (a0/a1) z1z1ᵀ
  const Mat9<Scalar> d2s = x0 * y1.transpose() + y1 * x0.transpose() - y0 * x1.transpose() - x1 * y0.transpose() +
                           (f.a1 / f.a0) * z0 * z0.transpose() + (f.a0 / f.a1) * z1 * z1.transpose();
  const Mat9<Scalar> d2X = Scalar(2) * ds * ds.transpose() + Scalar(2) * c.s * d2s;
  return c.E * g * g.transpose() + c.D * detail::frame_hessian_blocks(f, Scalar(1), Scalar(0)).dense() +
         c.A * dX * dX.transpose() + c.B * d2X + c.C * (dX * g.transpose() + g * dX.transpose());
}

/// Exact Hessian ∇²E_m = Jᵀ H_F J (0 where X = 0: the limit depends on the direction of approach).
template <class Scalar> PCE_HOST_DEVICE Mat12<Scalar> energy_hessian(const MollifiedEnergy<Scalar>& e) {
  if (!e.has_frame) return Mat12<Scalar>::Zero();
  if (detail::unmollified(e)) return energy_hessian(e.base);
  const Eigen::Matrix<Scalar, 9, 12> J = frame_jacobian(e.base.frame);
  return J.transpose() * energy_frame_hessian(e) * J;
}

/// Eigensystem of H_F (frame space, ascending) by its invariant subspaces:
/// {x0, y1, z2} (3×3, Jacobi rotations), {y0, x1} (±2ψm′s), {z0, x2} and
/// {z1, y2} (2×2 with a zero corner), where x_k, y_k, z_k are ê0, ê1, n̂ in slot k.
/// Where X = 0: all zero, with the identity as eigenvectors.
template <class Scalar> PCE_HOST_DEVICE FrameEigensystem<Scalar> energy_eigensystem(const MollifiedEnergy<Scalar>& e) {
  FrameEigensystem<Scalar> out;
  if (!e.has_frame) {
    out.values.setZero();
    out.vectors.setIdentity();
    return out;
  }
  if (detail::unmollified(e)) return energy_eigensystem(e.base);
  using std::abs;
  using std::sqrt;
  const Frame<Scalar>& f = e.base.frame;
  const auto c = detail::mollified_coefficients(e);
  using detail::slot;
  std::array<Scalar, 9> val;
  std::array<Vec9<Scalar>, 9> vec;
  // {x0, y1, z2}
  {
    Mat3<Scalar> M;
    const Scalar two = Scalar(2), s = c.s;
    M(0, 0) = Scalar(4) * c.A * s * s * f.a1 * f.a1 + two * c.B * f.a1 * f.a1;
    M(1, 1) = Scalar(4) * c.A * s * s * f.a0 * f.a0 + two * c.B * f.a0 * f.a0;
    M(0, 1) = M(1, 0) = Scalar(4) * c.A * s * s * f.a1 * f.a0 + two * c.B * f.a1 * f.a0 + two * c.B * s;
    M(0, 2) = M(2, 0) = two * c.C * s * f.a1;
    M(1, 2) = M(2, 1) = two * c.C * s * f.a0;
    M(2, 2) = c.E;
    Mat3<Scalar> V;
    detail::jacobi3(M, V);
    const Vec9<Scalar> b[3] = {slot(0, f.t0), slot(1, f.t1), slot(2, f.n)};
    for (int i = 0; i < 3; ++i) {
      val[i] = M(i, i);
      vec[i] = V(0, i) * b[0] + V(1, i) * b[1] + V(2, i) * b[2];
    }
  }
  // {y0, x1}: [[0, −k], [−k, 0]], k = 2ψm′s: eigenpairs (k, (y0 − x1)/√2), (−k, (y0 + x1)/√2).
  {
    const Scalar k = Scalar(2) * c.B * c.s, r = Scalar(1) / sqrt(Scalar(2));
    val[3] = k;
    vec[3] = r * (slot(0, f.t1) - slot(1, f.t0));
    val[4] = -k;
    vec[4] = r * (slot(0, f.t1) + slot(1, f.t0));
  }
  // {z0, x2} and {z1, y2}: [[p, q], [q, 0]] with λ_big = p/2 + sgn(p)√(p²/4 + q²), λ_small = −q²/λ_big.
  const Scalar a[2] = {f.a0, f.a1}, other[2] = {f.a1, f.a0};
  const Vec3<Scalar>* tk[2] = {&f.t0, &f.t1};
  for (int k = 0; k < 2; ++k) {
    const Scalar p = -c.D * ((f.l / a[k]) / a[k]) + Scalar(2) * c.B * other[k] * other[k];
    const Scalar q = -c.D / a[k];
    const Scalar hp = p / Scalar(2);
    const Scalar big = hp + detail::sign_nonneg(p) * sqrt(hp * hp + q * q);
    const Scalar small = big == Scalar(0) ? Scalar(0) : Scalar(-(q * q) / big);
    // (big, q) ⟂ (−q, big); both zero only if p = q = 0, then any basis will do.
    Scalar n = sqrt(big * big + q * q), u0 = big, u1 = q;
    if (!(n > Scalar(0))) {
      n = Scalar(1);
      u0 = Scalar(1);
      u1 = Scalar(0);
    }
    const Vec9<Scalar> bz = slot(k, f.n), be = slot(2, *tk[k]);
    val[5 + 2 * k] = big;
    vec[5 + 2 * k] = (u0 / n) * bz + (u1 / n) * be;
    val[6 + 2 * k] = small;
    vec[6 + 2 * k] = (-u1 / n) * bz + (u0 / n) * be;
  }
  std::array<int, 9> order{0, 1, 2, 3, 4, 5, 6, 7, 8};
  for (int i = 1; i < 9; ++i)
    for (int j = i; j > 0 && val[order[j]] < val[order[j - 1]]; --j) Eigen::numext::swap(order[j], order[j - 1]);
  for (int i = 0; i < 9; ++i) {
    out.values[i] = val[order[i]];
    out.vectors.col(i) = vec[order[i]];
  }
  return out;
}

/// PSD Hessian of the mollified energy by the strategy `P`, chosen at compile time:
/// `analytic`/`abs` clamp/flip the closed-form frame eigenvalues and pull back;
/// `gauss_newton` is max(mψ″, 0) ∇L∇Lᵀ; `numerical` and `none` as for the plain energy;
/// `exact` the nearest PSD matrix through a 9×9 reduced problem.
template <Projection P, class Scalar>
PCE_HOST_DEVICE Mat12<Scalar> projected_hessian(const MollifiedEnergy<Scalar>& e) {
  if (!e.has_frame) return Mat12<Scalar>::Zero();
  if (detail::unmollified(e)) return projected_hessian<P>(e.base);
  if constexpr (P == Projection::none) {
    return energy_hessian(e);
  } else if constexpr (P == Projection::numerical) {
    return project_psd(energy_hessian(e));
  } else if constexpr (P == Projection::gauss_newton) {
    PairEnergy<Scalar> b = e.base;
    b.psi.second *= e.mollifier;
    return projected_hessian<Projection::gauss_newton>(b);
  } else {
    static_assert(P == Projection::analytic || P == Projection::abs || P == Projection::exact,
                  "a strategy without a case");
    using std::abs;
    const FrameEigensystem<Scalar> es = energy_eigensystem(e);
    if constexpr (P == Projection::exact) {  // frame Hessian of rank up to 9: a 9×9 reduced problem
      return detail::exact_projection(e.base.frame,
                                      Mat9<Scalar>(es.vectors * es.values.asDiagonal() * es.vectors.transpose()));
    } else {
      Vec9<Scalar> lam = es.values;
      for (int i = 0; i < 9; ++i)
        lam[i] = P == Projection::abs ? Scalar(abs(lam[i])) : (lam[i] > Scalar(0) ? lam[i] : Scalar(0));
      const Mat9<Scalar> Hc = es.vectors * lam.asDiagonal() * es.vectors.transpose();
      const Eigen::Matrix<Scalar, 9, 12> J = frame_jacobian(e.base.frame);
      return J.transpose() * Hc * J;
    }
  }
}

/// PSD Hessian of the mollified energy by the strategy chosen at run time (compiles every
/// strategy: `energy/projection.hpp`).
template <class Scalar>
PCE_HOST_DEVICE Mat12<Scalar> projected_hessian(const MollifiedEnergy<Scalar>& e, Projection strategy) {
  return with_projection(strategy, [&e](auto p) { return projected_hessian<decltype(p)::value>(e); });
}

/// The instantiations `pce::precompiled` compiles (`core/precompiled.hpp`).
// (EXTERN is `extern` or nothing and S a type: neither can be parenthesised.)
// NOLINTBEGIN(bugprone-macro-parentheses)
#define PCE_MOLLIFIED_ENERGY_INSTANCES(EXTERN, S) \
  EXTERN template Mat12<S> projected_hessian<S>(const MollifiedEnergy<S>&, Projection);
// NOLINTEND(bugprone-macro-parentheses)
PCE_DECLARE_PRECOMPILED(PCE_MOLLIFIED_ENERGY_INSTANCES)

}  // namespace pce
