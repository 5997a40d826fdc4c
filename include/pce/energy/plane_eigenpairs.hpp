// SPDX-License-Identifier: MIT
/// @file
/// The two negative eigenpairs of the plane kinds' reduced Hessian (`docs/math.md` §9.3),
/// what `Projection::exact` needs: `proj(S) = S − λ₁q₁q₁ᵀ − λ₂q₂q₂ᵀ` (M29).
///
/// In the basis of `energy/exact_projection.hpp`, with `r_k` the columns of `R₃ = h Pᵀ`,
///
///     S = [[A, B], [Bᵀ, 0]],   A = Σ_k d_k r_k r_kᵀ (k = 0, 1, 2),   B = [e₀r₀, e₁r₁],
///
/// (d_k = m_0, m_1, ψ″ and e_k = μ_k |p_2| of (M28)). Eliminating the last two coordinates
/// leaves a 3×3 quadratic eigenproblem whose 2×2 core is closed form (M31): the
/// eigenvalues are the roots of a scalar function `F(λ)`, found by Newton's method from
/// the first-order approximations (M30), and each eigenvector follows from its eigenvalue
/// in closed form (M32). No tridiagonalisation, no iteration on vectors. The result is
/// accepted only if its residuals prove it (Kahan's theorem, M33); otherwise the caller
/// falls back to the QR algorithm.
#pragma once

#include <pce/core/scaling.hpp>
#include <pce/core/types.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace pce::detail {

/// The two negative eigenpairs of `S = [[Σ d_k r_k r_kᵀ, [e₀r₀, e₁r₁]], [·ᵀ, 0]]` (`r_k` the
/// columns of `R`), as `lambda` (ascending) and orthonormal 5-vectors `q`, by Newton's
/// method on the secular function (M31) from the approximations (M30) and closed-form
/// eigenvectors (M32). Returns false, outputs unspecified, unless the results are proven
/// (M33): each residual `|S q_k − λ_k q_k|` is below `64ε·s` (`s` = the largest of
/// `|d_k||r_k|²` and `|e_k||r_k|`, the size of S's terms), each `λ_k` below `−128ε·s`, and
/// `q_1, q_2` orthonormal, so that S has two distinct eigenvalues within `91ε·s` of them,
/// both negative. Written for the contact regime (`d₂ = ψ″ > 0` dominant, `e_k ≠ 0`, as the
/// Sylvester argument of §9.3 requires for exactly two negative eigenvalues); elsewhere it
/// may return false, never an unproven answer.
template <class Scalar> PCE_HOST_DEVICE bool plane_negative_eigenpairs(const Mat3<Scalar>& R, const Scalar (&d_in)[3],
                                                                       const Scalar (&e_in)[2], Scalar (&lambda)[2],
                                                                       VecN<Scalar, 5> (&q)[2]) {
  using std::abs;
  using std::sqrt;
  const Vec3<Scalar> r0 = R.col(0), r1 = R.col(1), r2 = R.col(2);
  const Scalar G00 = r0.squaredNorm(), G11 = r1.squaredNorm(), G01 = r0.dot(r1);  // G = UᵀU, U = [r0 r1]
  const Scalar w0 = r0.dot(r2), w1 = r1.dot(r2), rho = r2.squaredNorm();          // w = Uᵀr2, ρ = |r2|²
  if (!(rho > Scalar(0))) return false;
  // Rescale by a power of two so that |λ| ~ 1 (the negative eigenvalues are ≈ −|e_k||r_k|):
  // the secular function is of degree 5 in λ, and the approximations square the e_k.
  const PowerOfTwoScale<Scalar> scale(std::max(Scalar(abs(e_in[0]) * sqrt(G00)), Scalar(abs(e_in[1]) * sqrt(G11))));
  const Scalar d[3] = {scale.down(d_in[0]), scale.down(d_in[1]), scale.down(d_in[2])};
  const Scalar e[2] = {scale.down(e_in[0]), scale.down(e_in[1])};
  const Scalar ee[2] = {e[0] * e[0], e[1] * e[1]};
  // (M30): B′ = (I − vvᵀ)B with v = r2/|r2|, B′ᵀB′ = E G⊥ E, G⊥ = G − wwᵀ/ρ, E = diag(e).
  // y: eigenvector of the 2×2 E G⊥ E for its larger eigenvalue σ0², unnormalised (|y|² = yy);
  // r_j·x_k = (G⊥ E y_k)_j with x_k = B′y_k.
  const Scalar P00 = G00 - w0 * (w0 / rho), P11 = G11 - w1 * (w1 / rho), P01 = G01 - w0 * (w1 / rho);
  const Scalar a = ee[0] * P00, c = ee[1] * P11, b = e[0] * e[1] * P01;
  const Scalar half = (a - c) / Scalar(2), root = sqrt(half * half + b * b), mean = (a + c) / Scalar(2);
  Scalar y[2] = {Scalar(1), Scalar(0)};
  if (root > Scalar(0)) {
    if (half >= Scalar(0))
      y[0] = half + root, y[1] = b;
    else
      y[0] = b, y[1] = root - half;
  }
  const Scalar yy = y[0] * y[0] + y[1] * y[1];
  const Scalar s2[2] = {Scalar(mean + root), Scalar(mean - root)};
  Scalar x[2];
  for (int k = 0; k < 2; ++k) {
    if (!(s2[k] > Scalar(0))) return false;
    const Scalar f0 = e[0] * (k == 0 ? y[0] : -y[1]), f1 = e[1] * (k == 0 ? y[1] : y[0]);  // E y_k
    const Scalar c0 = P00 * f0 + P01 * f1, c1 = P01 * f0 + P11 * f1;
    x[k] = -sqrt(s2[k]) + (d[0] * c0 * c0 + d[1] * c1 * c1) / (Scalar(2) * s2[k] * yy);
  }
  if (x[1] < x[0]) Eigen::numext::swap(x[0], x[1]);
  if (!(x[1] < Scalar(0)) || !(x[0] > Scalar(-16))) return false;  // also NaN
  // (M31) Newton on F(λ) = λm − d₂(ρm + h), m = det M, h = wᵀ D adj(M) w, M = λ²I − G D,
  // D = diag(λd₀ + e₀², λd₁ + e₁²), until a step is small enough that the next error, of
  // order step²/gap, is below 4ε|λ|: the eigenvector below is then good to a few ε, its
  // Rayleigh quotient gives λ to rounding, and the residual test decides (on the pce-bench
  // pools: two steps for about 2/3 of the first chain and nearly all of the second, else
  // three). The two chains are independent, so their latencies overlap.
  const Scalar eps = Constants<Scalar>::epsilon();
  const Scalar gap = x[1] - x[0];
  bool done[2] = {false, false};
  for (int it = 0; it < 8 && !(done[0] && done[1]); ++it) {
    for (int k = 0; k < 2; ++k) {
      if (done[k]) continue;
      const Scalar l = x[k], l2 = l * l, a0 = l * d[0] + ee[0], a1 = l * d[1] + ee[1];
      const Scalar p = l2 - a0 * G00, s = l2 - a1 * G11, pp = Scalar(2) * l - d[0] * G00,
                   sp = Scalar(2) * l - d[1] * G11;
      const Scalar a01 = a0 * a1, a01p = d[0] * a1 + a0 * d[1];
      const Scalar m = p * s - a01 * G01 * G01, mp = pp * s + p * sp - a01p * G01 * G01;
      const Scalar h = a0 * s * w0 * w0 + a1 * p * w1 * w1 + Scalar(2) * a01 * G01 * w0 * w1;
      const Scalar hp =
          (d[0] * s + a0 * sp) * w0 * w0 + (d[1] * p + a1 * pp) * w1 * w1 + Scalar(2) * a01p * G01 * w0 * w1;
      const Scalar F = l * m - d[2] * (rho * m + h), Fp = m + l * mp - d[2] * (rho * mp + hp);
      const Scalar step = F / Fp;
      x[k] = l - step;
      done[k] = !(step * step > Scalar(4) * eps * abs(x[k]) * gap) ||
                abs(step) <= Scalar(4) * eps * abs(x[k]);  // NaN: done, refused below
    }
  }
  if (!(x[0] < Scalar(0) && x[1] < Scalar(0))) return false;  // also NaN
  // (M32) the eigenvectors: u ∝ K(λ)⁻¹ r2 = (m r2 + U D adj(M) w)/(λ² m) (Woodbury), then its
  // component along v recomputed from the v-row of the 3×3 problem, where the large ψ″ term
  // balances vᵀK u⊥ (from K⁻¹r2 it would carry an error of ε·ψ″/|λ| relative); the Rayleigh
  // quotient of the result is λ to rounding.
  const Scalar rn = sqrt(rho);
  const Vec3<Scalar> v = r2 / rn;
  const Scalar v0 = w0 / rn, v1 = w1 / rn;
  for (int k = 0; k < 2; ++k) {
    const Scalar l = x[k], l2 = l * l, a0 = l * d[0] + ee[0], a1 = l * d[1] + ee[1];
    const Scalar p = l2 - a0 * G00, s = l2 - a1 * G11, a01 = a0 * a1;
    const Scalar m = p * s - a01 * G01 * G01;
    const Scalar z0 = a0 * s * w0 + a01 * G01 * w1, z1 = a01 * G01 * w0 + a1 * p * w1;
    const Vec3<Scalar> u0 = m * r2 + z0 * r0 + z1 * r1;
    const Vec3<Scalar> up = u0 - v.dot(u0) * v;
    const Scalar vKu = -a0 * v0 * r0.dot(up) - a1 * v1 * r1.dot(up);
    const Scalar vKv = l2 - a0 * v0 * v0 - a1 * v1 * v1;
    const Scalar sv = vKu / (l * d[2] * rho - vKv);
    const Vec3<Scalar> u = up + sv * v;
    const Scalar t0 = r0.dot(u), t1 = r1.dot(u), t2 = rn * sv;
    const Scalar y0 = e[0] * t0 / l, y1 = e[1] * t1 / l;  // the last two coordinates: Bᵀu/λ
    const Scalar b2 = y0 * y0 + y1 * y1, nq2 = u.squaredNorm() + b2;
    if (!(nq2 > Scalar(0))) return false;
    x[k] = (d[0] * t0 * t0 + d[1] * t1 * t1 + d[2] * t2 * t2 + Scalar(2) * l * b2) / nq2;
    q[k][0] = u[0], q[k][1] = u[1], q[k][2] = u[2], q[k][3] = y0, q[k][4] = y1;
    q[k] /= sqrt(nq2);
  }
  q[1] -= q[0].dot(q[1]) * q[0];
  const Scalar n1 = q[1].norm();
  if (!(n1 > Scalar(0.5))) return false;  // parallel: both converged to the same eigenvalue
  q[1] /= n1;
  // (M33) the proof: residuals of the orthonormal pair against the size of S's terms.
  const Scalar size = std::max(std::max(abs(d[0]) * G00, abs(d[1]) * G11),
                               std::max(abs(d[2]) * rho, std::max(abs(e[0]) * sqrt(G00), abs(e[1]) * sqrt(G11))));
  const Scalar tol = Scalar(64) * eps * size;
  for (int k = 0; k < 2; ++k) {
    const Vec3<Scalar> u = q[k].template head<3>();
    const Scalar t0 = r0.dot(u), t1 = r1.dot(u), t2 = r2.dot(u);
    const Vec3<Scalar> top =
        (d[0] * t0 + e[0] * q[k][3]) * r0 + (d[1] * t1 + e[1] * q[k][4]) * r1 + (d[2] * t2) * r2 - x[k] * u;
    const Scalar b0 = e[0] * t0 - x[k] * q[k][3], b1 = e[1] * t1 - x[k] * q[k][4];
    if (!(top.squaredNorm() + b0 * b0 + b1 * b1 <= tol * tol)) return false;
    if (!(x[k] < Scalar(-2) * tol)) return false;
    lambda[k] = scale.up(x[k]);
  }
  return true;
}

}  // namespace pce::detail
