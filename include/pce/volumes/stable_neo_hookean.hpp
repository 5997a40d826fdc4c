// SPDX-License-Identifier: MIT
/// @file
/// The stable Neo-Hookean energy density (Smith, de Goes & Kim, "Stable Neo-Hookean Flesh
/// Simulation", ACM TOG 37(2), 2018; in the form of Kim & Eberle, "Dynamic Deformables",
/// SIGGRAPH 2022 course, Sec. 6.4):
///
///     Ψ(F) = μ/2 (‖F‖² − 3) − μ (J − 1) + λ/2 (J − 1)²,   J = det F,
///
/// its first Piola–Kirchhoff stress `P = μ F + (λ(J − 1) − μ) cof F`, its Hessian
/// `∂²Ψ/∂F² = μ I + (λ(J − 1) − μ) H_J + λ vec(cof F) vec(cof F)ᵀ` (H_J = ∂ cof F/∂F, linear
/// in F), and that Hessian's eigensystem in closed form (Smith, de Goes & Kim, "Analytic
/// Eigensystems for Isotropic Distortion Energies", ACM TOG 38(1), 2019; Dynamic Deformables
/// Sec. 7): with the rotation-variant SVD `F = U Σ Vᵀ` (U, V rotations, σ₂ < 0 for an inverted
/// element) and `s = λ(J − 1) − μ`,
///
///     twist (i, j):  vec(U (e_i e_jᵀ − e_j e_iᵀ) Vᵀ)/√2,  μ + s σ_k
///     flip  (i, j):  vec(U (e_i e_jᵀ + e_j e_iᵀ) Vᵀ)/√2,  μ − s σ_k      ({i, j, k} = {0, 1, 2})
///     scaling:       vec(U diag(a) Vᵀ),  a and its value an eigenpair of the 3×3
///                    A = ∂²Ψ/∂σ²: A_ii = μ + λ (σ_j σ_k)², A_ij = σ_k (λ(2J − 1) − μ).
///
/// Ψ is a polynomial in F: defined for inverted (J < 0) and flat (J = 0) elements alike, with
/// no division anywhere, so every finite F whose Ψ is representable gives finite results.
/// λ here is the Lamé λ plus μ (Smith et al. 2018, Sec. 3.4), so that Ψ agrees with linear
/// elasticity of the given Lamé parameters at small strain (`from_lame`, `from_young_poisson`).
#pragma once

#include <pce/core/enum_names.hpp>
#include <pce/core/jacobi.hpp>
#include <pce/core/orthogonal.hpp>
#include <pce/core/precompiled.hpp>
#include <pce/core/scaling.hpp>
#include <pce/core/types.hpp>
#include <pce/volumes/tet_deformation.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <type_traits>
#include <utility>

namespace pce {

/// The material: μ and λ of the stable Neo-Hookean energy (Pa, energy per volume).
struct StableNeoHookean {
  double mu = 1.0;      ///< μ > 0, the shear modulus
  double lambda = 2.0;  ///< λ = λ_Lamé + μ > 0

  /// From the Lamé parameters μ, λ_Lamé (Smith et al. 2018, Eq. 16: λ = λ_Lamé + μ).
  static StableNeoHookean from_lame(double mu, double lambda_lame) { return {mu, lambda_lame + mu}; }
  /// From Young's modulus E and Poisson's ratio ν (−1 < ν < 1/2): μ = E/(2(1 + ν)),
  /// λ_Lamé = Eν/((1 + ν)(1 − 2ν)).
  static StableNeoHookean from_young_poisson(double E, double nu) {
    return from_lame(E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu)));
  }
  /// Whether μ and λ are finite and positive (λ_Lamé > −μ, which ν ∈ (−1, ½) gives).
  bool valid() const { return std::isfinite(mu) && std::isfinite(lambda) && mu > 0 && lambda > 0; }
};

namespace detail {
/// `cof F = J F⁻ᵀ`, column by column: `(f1 × f2, f2 × f0, f0 × f1)` (`∂J/∂F`).
template <class Scalar> Mat3<Scalar> cofactor(const Mat3<Scalar>& F) {
  Mat3<Scalar> C;
  C.col(0) = F.col(1).cross(F.col(2));
  C.col(1) = F.col(2).cross(F.col(0));
  C.col(2) = F.col(0).cross(F.col(1));
  return C;
}
/// `vec(a bᵀ)` (column-major: entry 3c + r is a_r b_c).
template <class Scalar> Vec9<Scalar> vec_outer(const Vec3<Scalar>& a, const Vec3<Scalar>& b) {
  Vec9<Scalar> v;
  for (int c = 0; c < 3; ++c) v.template segment<3>(3 * c) = b[c] * a;
  return v;
}
/// Ψ with J = det F given.
template <class Scalar> Scalar snh_energy_density(const StableNeoHookean& m, const Mat3<Scalar>& F, const Scalar& J) {
  const Scalar mu(m.mu), lambda(m.lambda), Jm1 = J - Scalar(1);
  return mu / Scalar(2) * (F.squaredNorm() - Scalar(3)) - mu * Jm1 + lambda / Scalar(2) * Jm1 * Jm1;
}
/// P with J = det F and C = cof F given.
template <class Scalar>
Mat3<Scalar> snh_stress(const StableNeoHookean& m, const Mat3<Scalar>& F, const Scalar& J, const Mat3<Scalar>& C) {
  const Scalar mu(m.mu), lambda(m.lambda);
  return mu * F + (lambda * (J - Scalar(1)) - mu) * C;
}
/// ∂²Ψ/∂F² with J = det F and C = cof F given: `λ (g_c g_d)` entry by entry (symmetric bit for
/// bit), μ on the diagonal, and `s H_J`, whose block (c, d), c ≠ d, is `−[s f_e]×` when
/// d = c + 1 (mod 3) and `+[s f_e]×` otherwise ({c, d, e} = {0, 1, 2}), added entry by entry
/// from `[v]× = [[0, −v2, v1], [v2, 0, −v0], [−v1, v0, 0]]` (antisymmetric: block (d, c) is
/// block (c, d) transposed, to the bit).
template <class Scalar>
Mat9<Scalar> snh_hessian(const StableNeoHookean& m, const Mat3<Scalar>& F, const Scalar& J, const Mat3<Scalar>& C) {
  const Scalar mu(m.mu), lambda(m.lambda), s = lambda * (J - Scalar(1)) - mu;
  const Vec9<Scalar> g = Eigen::Map<const Vec9<Scalar>>(C.data());
  const Mat3<Scalar> sF = s * F;
  Mat9<Scalar> H;
  for (int d = 0; d < 9; ++d) H.col(d) = lambda * (g * g[d]);
  for (int i = 0; i < 9; ++i) H(i, i) += mu;
  for (int c = 0; c < 3; ++c)
    for (int d = 0; d < 3; ++d) {
      if (c == d) continue;
      const Vec3<Scalar> v = (d == (c + 1) % 3 ? Scalar(-1) : Scalar(1)) * sF.col(3 - c - d);
      H(3 * c, 3 * d + 1) -= v[2];
      H(3 * c, 3 * d + 2) += v[1];
      H(3 * c + 1, 3 * d) += v[2];
      H(3 * c + 1, 3 * d + 2) -= v[0];
      H(3 * c + 2, 3 * d) -= v[1];
      H(3 * c + 2, 3 * d + 1) += v[0];
    }
  return H;
}
/// Whether every entry of the fixed-size `m` is finite: for the built-in floating types
/// `Σ 0·m_ij`, which is 0 exactly when each entry is finite (0·±∞ and 0·NaN are NaN), summed
/// column by column into one vectorised column of partial sums (for the 12×12 Hessian about
/// half the time of `all_finite`'s branch per entry; a 12-vector is quicker with the branches).
template <class Derived> bool entries_finite(const Eigen::MatrixBase<Derived>& m) {
  using Scalar = typename Derived::Scalar;
  if constexpr (std::is_floating_point_v<Scalar>) {
    Eigen::Array<Scalar, Derived::RowsAtCompileTime, 1> zero = m.col(0).array() * Scalar(0);
    for (Eigen::Index j = 1; j < m.cols(); ++j) zero += m.col(j).array() * Scalar(0);
    return zero.sum() == Scalar(0);
  } else {
    return all_finite(m);
  }
}
}  // namespace detail

/// `Ψ(F) = μ/2 (‖F‖² − 3) − μ (J − 1) + λ/2 (J − 1)²`.
template <class Scalar> Scalar snh_energy_density(const StableNeoHookean& m, const Mat3<Scalar>& F) {
  return detail::snh_energy_density(m, F, Scalar(F.determinant()));
}

/// `P = ∂Ψ/∂F = μ F + (λ(J − 1) − μ) cof F`.
template <class Scalar> Mat3<Scalar> snh_stress(const StableNeoHookean& m, const Mat3<Scalar>& F) {
  return detail::snh_stress(m, F, Scalar(F.determinant()), detail::cofactor(F));
}

/// `∂²Ψ/∂F² = μ I + (λ(J − 1) − μ) H_J + λ g gᵀ` on vec(F) (9×9), g = vec(cof F) and H_J the
/// block matrix `[[0, −[f2]×, [f1]×], [[f2]×, 0, −[f0]×], [−[f1]×, [f0]×, 0]]` (block (c, d):
/// ∂(cof F column c)/∂(F column d)). Symmetric bit for bit.
template <class Scalar> Mat9<Scalar> snh_hessian(const StableNeoHookean& m, const Mat3<Scalar>& F) {
  return detail::snh_hessian(m, F, Scalar(F.determinant()), detail::cofactor(F));
}

/// The nine eigenpairs of `snh_hessian`: `vectors` orthonormal (columns), `values` in the order
/// twist (0,1), (0,2), (1,2), flip (0,1), (0,2), (1,2), then the three scaling modes.
template <class Scalar> struct SnhEigensystem {
  Vec9<Scalar> values;   ///< eigenvalues
  Mat9<Scalar> vectors;  ///< the eigenvectors on vec(F), one per column
};

/// The rotation-variant SVD `F = U diag(sigma) Vᵀ`: U and V rotations, |σ₀| ≥ |σ₁| ≥ |σ₂|,
/// σ₀, σ₁ ≥ 0, and σ₂ carrying det F's sign. One-sided Jacobi (Hestenes; Demmel & Veselić,
/// "Jacobi's method is more accurate than QR", SIMAX 13(4), 1992) on F rescaled exactly by a
/// power of two to max|F_ij| in [½, 1) (no square or product below overflows, whatever |F|):
/// plane rotations from the right make F's columns orthogonal, `W = F V`, until every pair is
/// orthogonal to ε relative; then `u₀ = w₀/|w₀|`, `u₁` = w₁ orthogonalised against u₀ and
/// normalised (any unit vector orthogonal to u₀ if nothing is left), `u₂ = u₀ × u₁`, and
/// `σ_i = u_i·w_i` (scaled back). U is orthonormal to rounding whatever the singular values
/// (flat and inverted F included), and `F = U Σ Vᵀ` to about ε‖F‖.
template <class Scalar>
void rotation_variant_svd(const Mat3<Scalar>& F, Mat3<Scalar>& U, Vec3<Scalar>& sigma, Mat3<Scalar>& V) {
  using std::abs;
  using std::sqrt;
  const Scalar eps = Constants<Scalar>::epsilon(), eps2 = eps * eps;
  const detail::PowerOfTwoScale<Scalar> scale(F.cwiseAbs().maxCoeff());
  Mat3<Scalar> W = scale.down(F);
  V.setIdentity();
  // cyclic by pairs (0, 1), (0, 2), (1, 2); converged when the pairs checked since the last
  // rotation are all the others (the pair just rotated is orthogonal to rounding), or all
  // three when nothing was rotated
  constexpr int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  int quiet = -1;  // the pairs found orthogonal in a row, -1 before the first rotation
  for (int sweep = 0; sweep < 16 && quiet < 2; ++sweep)
    for (const auto& pq : pairs) {
      const int p = pq[0], q = pq[1];
      const Scalar a = W.col(p).squaredNorm(), b = W.col(q).squaredNorm(), c = W.col(p).dot(W.col(q));
      if (!(c * c > eps2 * (a * b))) {  // orthogonal to rounding (also 0 or NaN)
        if (++quiet == 2) break;
        continue;
      }
      quiet = 0;
      // the rotation [[cs, sn], [−sn, cs]] that zeroes w_p·w_q (Golub & Van Loan, Sec. 8.5.2):
      // t = tan θ = sgn(d)·2c/(|d| + r), d = b − a, r = √(d² + 4c²), |θ| ≤ π/4; with
      // s = |d| + r, 1 + t² = 2rs/s², so cs = s/√(2rs) and sn = t·cs = sgn(d)·2c/√(2rs).
      // When 4c² ≤ ε d², t = c/d and cs = 1 to rounding (relative errors (c/d)² ≤ ε/4 and
      // t²/2 ≤ ε/8), with one division.
      const Scalar d = b - a, c2 = Scalar(2) * c;
      Scalar cs(1), sn;
      if (c2 * c2 <= eps * (d * d)) {
        sn = c / d;
      } else {
        const Scalar r = sqrt(d * d + c2 * c2), s = abs(d) + r, inv = Scalar(1) / sqrt(Scalar(2) * r * s);
        cs = s * inv;
        sn = (d < Scalar(0) ? -c2 : c2) * inv;
      }
      const Vec3<Scalar> wp = W.col(p), vp = V.col(p);
      W.col(p) = cs * wp - sn * W.col(q);
      W.col(q) = sn * wp + cs * W.col(q);
      V.col(p) = cs * vp - sn * V.col(q);
      V.col(q) = sn * vp + cs * V.col(q);
    }
  // columns by decreasing norm, then V a rotation (F = W Vᵀ is unchanged by flipping a
  // column of both)
  Vec3<Scalar> n2(W.col(0).squaredNorm(), W.col(1).squaredNorm(), W.col(2).squaredNorm());
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2 - i; ++j)
      if (n2[j] < n2[j + 1]) {
        std::swap(n2[j], n2[j + 1]);
        W.col(j).swap(W.col(j + 1));
        V.col(j).swap(V.col(j + 1));
      }
  if (V.determinant() < Scalar(0)) V.col(2) = -V.col(2), W.col(2) = -W.col(2);
  const Scalar n0 = sqrt(n2[0]);
  U.col(0) = n0 > Scalar(0) ? Vec3<Scalar>(W.col(0) / n0) : Vec3<Scalar>::UnitX();
  Vec3<Scalar> u1 = W.col(1) - U.col(0).dot(W.col(1)) * U.col(0);
  const Scalar n1 = u1.norm();
  if (n1 > Scalar(0)) {
    u1 /= n1;
  } else {  // rank ≤ 1: any unit vector orthogonal to u₀
    u1 = any_orthogonal<Scalar>(U.col(0));
  }
  U.col(1) = u1;
  U.col(2) = U.col(0).cross(u1);
  for (int i = 0; i < 3; ++i) sigma[i] = scale.up(U.col(i).dot(W.col(i)));
}

namespace detail {
/// What the eigensystem is made of: the rotation-variant SVD, `s = λ(J − 1) − μ`, the 3×3
/// scaling block `A` and the vectors `vec(u_i v_jᵀ)`.
template <class Scalar> struct SnhModes {
  Mat3<Scalar> U, V;   ///< F = U diag(sigma) Vᵀ
  Vec3<Scalar> sigma;  ///< signed singular values
  Scalar s;            ///< λ(J − 1) − μ: twist μ + s σ_k, flip μ − s σ_k
  Mat3<Scalar> A;      ///< ∂²Ψ/∂σ²
  SnhModes(const StableNeoHookean& m, const Mat3<Scalar>& F) : SnhModes(m, F, Scalar(F.determinant())) {}
  /// With J = det F given.
  SnhModes(const StableNeoHookean& m, const Mat3<Scalar>& F, const Scalar& J) {
    rotation_variant_svd(F, U, sigma, V);
    // J as `snh_hessian` takes it (det F); the g gᵀ term's J as the singular values give it.
    // They agree to ε‖F‖³, but a large, nearly flat F leaves det F only that accurate, and
    // then this split keeps the eigensystem that of the Hessian actually computed.
    const Scalar mu(m.mu), lambda(m.lambda), J_sigma = sigma[0] * sigma[1] * sigma[2];
    s = lambda * (J - Scalar(1)) - mu;
    const Scalar kappa = s + lambda * J_sigma;  // λ(2J − 1) − μ when the two agree
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      A(i, i) = mu + lambda * (sigma[j] * sigma[k]) * (sigma[j] * sigma[k]);
      A(j, k) = A(k, j) = sigma[i] * kappa;
    }
  }
  /// vec(u_i v_jᵀ)
  Vec9<Scalar> uv(int i, int j) const { return vec_outer<Scalar>(U.col(i), V.col(j)); }
};
/// The axis pairs (i, j) of the twist and flip modes, and the third axis k.
inline constexpr int snh_pairs[3][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}};
}  // namespace detail

/// The closed-form eigensystem of `snh_hessian(m, F)` (see the file comment): one 3×3 SVD
/// (`rotation_variant_svd`) and one 3×3 symmetric eigenproblem, no 9×9 solve.
template <class Scalar> SnhEigensystem<Scalar> snh_eigensystem(const StableNeoHookean& m, const Mat3<Scalar>& F) {
  using std::sqrt;
  const detail::SnhModes<Scalar> md(m, F);
  const Scalar mu(m.mu), r = Scalar(1) / sqrt(Scalar(2));
  SnhEigensystem<Scalar> e;
  for (int p = 0; p < 3; ++p) {
    const int i = detail::snh_pairs[p][0], j = detail::snh_pairs[p][1], k = detail::snh_pairs[p][2];
    e.values[p] = mu + md.s * md.sigma[k];
    e.vectors.col(p) = r * (md.uv(i, j) - md.uv(j, i));
    e.values[3 + p] = mu - md.s * md.sigma[k];
    e.vectors.col(3 + p) = r * (md.uv(i, j) + md.uv(j, i));
  }
  // A by tridiagonal QR (`core/jacobi.hpp`): a closed form (Cardano, Eigen's `computeDirect`)
  // loses digits in the eigenvectors of nearly repeated eigenvalues, which here made the
  // analytic projection differ from the numerical one by up to 3700 ε‖H‖
  Vec3<Scalar> a;
  Mat3<Scalar> Q;
  detail::symmetric_qr_eigen<Scalar, 3>(md.A, a, Q);
  for (int c = 0; c < 3; ++c) {
    e.values[6 + c] = a[c];
    e.vectors.col(6 + c) = Q(0, c) * md.uv(0, 0) + Q(1, c) * md.uv(1, 1) + Q(2, c) * md.uv(2, 2);
  }
  return e;
}

/// How a tetrahedron's Hessian is made positive semidefinite: in F-space, `Bᵀ H⁺ B` with
/// `H⁺ = Q max(Λ, 0) Qᵀ` of the 9×9 `∂²Ψ/∂F²` (Teran et al. 2005; Smith et al. 2019).
enum class VolumeProjection {
  none,       ///< the exact Hessian `V Bᵀ (∂²Ψ/∂F²) B`, indefinite in general
  analytic,   ///< eigenvalues clamped in the closed-form eigensystem (`snh_eigensystem`)
  numerical,  ///< the same clamp after a numerical 9×9 eigensolve (the reference)
};

/// The names of `VolumeProjection` (the scene's `volume_elasticity.hessian` takes `analytic`
/// and `numerical`), in enumerator order.
inline constexpr EnumNames<VolumeProjection, 3> kVolumeProjectionNames{{
    {VolumeProjection::none, "none"},
    {VolumeProjection::analytic, "analytic"},
    {VolumeProjection::numerical, "numerical"},
}};

/// The table of `VolumeProjection`'s names (for `name_of` and `parse`).
constexpr const EnumNames<VolumeProjection, 3>& enum_names(VolumeProjection) { return kVolumeProjectionNames; }

namespace detail {
/// Whether the symmetric 3×3 `A` is positive definite, by the pivots of `A = L D Lᵀ` (Cholesky
/// without square roots): d₀ = a₀₀, d₁ = a₁₁ − a₁₀²/d₀, d₂ = a₂₂ − a₂₀²/d₀ − t²/d₁ with
/// t = a₂₁ − a₂₀a₁₀/d₀, all positive. Backward stable like Cholesky when they are (A is then
/// positive semidefinite to about ε‖A‖); false for NaN.
template <class Scalar> bool ldlt_positive(const Mat3<Scalar>& A) {
  const Scalar d0 = A(0, 0);
  if (!(d0 > Scalar(0))) return false;
  const Scalar l1 = A(1, 0) / d0, l2 = A(2, 0) / d0, d1 = A(1, 1) - l1 * A(1, 0);
  if (!(d1 > Scalar(0))) return false;
  const Scalar t = A(2, 1) - l2 * A(1, 0);
  return A(2, 2) - l2 * A(2, 0) - t * t / d1 > Scalar(0);
}

/// The analytic projection with J = det F and C = cof F given: `H⁺ = H − Σ_{λ_k < 0} λ_k q_k q_kᵀ`,
/// the exact Hessian less its negative modes in the closed-form eigensystem. At most one of an
/// axis pair's twist and flip is negative (they sum to 2μ > 0); they are q = (a ∓ b)/√2 with
/// a = vec(u_i v_jᵀ), b = vec(u_j v_iᵀ), added here as p pᵀ with p = √(−λ/2) (a ∓ b). The
/// scaling block A needs no eigensolve when it is positive definite (`ldlt_positive`), else its
/// negative eigenpairs (α, w) give the modes `M w`, M = [vec(u_d v_dᵀ)], added as
/// p = √(−α) M w. Each `H_cd += p_c p_d` keeps H symmetric bit for bit.
template <class Scalar> Mat9<Scalar> snh_analytic_projection(const StableNeoHookean& m, const Mat3<Scalar>& F,
                                                             const Scalar& J, const Mat3<Scalar>& C) {
  using std::sqrt;
  Mat9<Scalar> H = snh_hessian(m, F, J, C);
  const SnhModes<Scalar> md(m, F, J);
  const auto add = [&H](const Vec9<Scalar>& p) {
    for (int d = 0; d < 9; ++d) H.col(d) += p * p[d];
  };
  const Scalar mu(m.mu), half(0.5);
  for (const auto& ijk : snh_pairs) {
    const int i = ijk[0], j = ijk[1], k = ijk[2];
    const Scalar twist = mu + md.s * md.sigma[k], flip = mu - md.s * md.sigma[k];
    if (twist < Scalar(0)) add(sqrt(-half * twist) * (md.uv(i, j) - md.uv(j, i)));
    if (flip < Scalar(0)) add(sqrt(-half * flip) * (md.uv(i, j) + md.uv(j, i)));
  }
  if (!ldlt_positive(md.A)) {
    Vec3<Scalar> a;
    Mat3<Scalar> Q;
    symmetric_qr_eigen<Scalar, 3>(md.A, a, Q);
    for (int c = 0; c < 3; ++c)
      if (a[c] < Scalar(0)) add(sqrt(-a[c]) * (Q(0, c) * md.uv(0, 0) + Q(1, c) * md.uv(1, 1) + Q(2, c) * md.uv(2, 2)));
  }
  return H;
}

/// `VolumeProjection::numerical`: `Σ max(λ, 0) q qᵀ` of a symmetric 9×9 `A` from Eigen's
/// eigensolver, symmetrised.
template <class Scalar> Mat9<Scalar> snh_numerical_projection(const Mat9<Scalar>& A) {
  Mat9<Scalar> H = Mat9<Scalar>::Zero();
  const Eigen::SelfAdjointEigenSolver<Mat9<Scalar>> es(A);
  for (int i = 0; i < 9; ++i)
    if (es.eigenvalues()[i] > Scalar(0))
      H.noalias() += (es.eigenvalues()[i] * es.eigenvectors().col(i)) * es.eigenvectors().col(i).transpose();
  return Scalar(0.5) * (H + H.transpose());
}

/// The instantiations `pce::precompiled` compiles (`core/precompiled.hpp`).
// (EXTERN is `extern` or nothing and S a type: neither can be parenthesised.)
// NOLINTBEGIN(bugprone-macro-parentheses)
#define PCE_SNH_INSTANCES(EXTERN, S) EXTERN template Mat9<S> snh_numerical_projection<S>(const Mat9<S>&);
// NOLINTEND(bugprone-macro-parentheses)
PCE_DECLARE_PRECOMPILED(PCE_SNH_INSTANCES)

/// `snh_projected_hessian` with J = det F and C = cof F given.
template <class Scalar> Mat9<Scalar> snh_projected_hessian(const StableNeoHookean& m, const Mat3<Scalar>& F,
                                                           const Scalar& J, const Mat3<Scalar>& C,
                                                           VolumeProjection how) {
  if (how == VolumeProjection::none) return snh_hessian(m, F, J, C);
  if (how == VolumeProjection::analytic) return snh_analytic_projection(m, F, J, C);
  return snh_numerical_projection(snh_hessian(m, F, J, C));
}
}  // namespace detail

/// `H⁺ = Σ max(λ, 0) q qᵀ` of the 9×9 F-space Hessian, by `how` (`none`: the Hessian itself).
/// Symmetric bit for bit.
template <class Scalar>
Mat9<Scalar> snh_projected_hessian(const StableNeoHookean& m, const Mat3<Scalar>& F, VolumeProjection how) {
  return detail::snh_projected_hessian(m, F, Scalar(F.determinant()), detail::cofactor(F), how);
}

/// One tetrahedron's elastic energy `E = V Ψ(F)`, and when asked (non-null) its gradient
/// `V Bᵀ vec(P)` and Hessian `V Bᵀ H B` (`how`). `invalid_input` for an invalid material or a
/// coordinate that is not finite or beyond `Constants::max_coordinate`; `overflow` when a
/// requested result is not finite (Ψ beyond the scalar's range: |F| ≳ 1e102 in double). The
/// outputs are written only on `ok`.
template <class Scalar> Status snh_tet_energy(const StableNeoHookean& m, const TetRest<Scalar>& rest,
                                              const Vec12<Scalar>& x, VolumeProjection how, Scalar& value,
                                              Vec12<Scalar>* gradient, Mat12<Scalar>* hessian) {
  if (!m.valid() || !detail::coordinates_valid(x)) return Status::invalid_input;
  const Mat3<Scalar> F = deformation_gradient(rest, x);
  const Scalar J = F.determinant();  // det F and cof F once, for Ψ, P and the Hessian
  const Scalar E = rest.volume * detail::snh_energy_density(m, F, J);
  if (!detail::is_finite(E)) return Status::overflow;
  const Mat3<Scalar> C = detail::cofactor(F);
  Vec12<Scalar> g = Vec12<Scalar>::Zero();  // (written only when asked for)
  if (gradient) {
    g = rest.volume * pull_back_stress(rest, detail::snh_stress(m, F, J, C));
    if (!detail::all_finite(g)) return Status::overflow;
  }
  if (hessian) {  // the last check: written as soon as it passes
    const Mat12<Scalar> H = pull_back_hessian(rest, detail::snh_projected_hessian(m, F, J, C, how), rest.volume);
    if (!detail::entries_finite(H)) return Status::overflow;
    *hessian = H;
  }
  value = E;
  if (gradient) *gradient = g;
  return Status::ok;
}

}  // namespace pce
