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

#include <pce/core/jacobi.hpp>
#include <pce/core/orthogonal.hpp>
#include <pce/core/types.hpp>
#include <pce/volumes/tet_deformation.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <cmath>
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
/// `[v]×`, the matrix of `v × ·`.
template <class Scalar> Mat3<Scalar> cross_matrix(const Vec3<Scalar>& v) {
  Mat3<Scalar> m;
  m << Scalar(0), -v[2], v[1], v[2], Scalar(0), -v[0], -v[1], v[0], Scalar(0);
  return m;
}
/// `vec(a bᵀ)` (column-major: entry 3c + r is a_r b_c).
template <class Scalar> Vec9<Scalar> vec_outer(const Vec3<Scalar>& a, const Vec3<Scalar>& b) {
  Vec9<Scalar> v;
  for (int c = 0; c < 3; ++c) v.template segment<3>(3 * c) = b[c] * a;
  return v;
}
}  // namespace detail

/// `Ψ(F) = μ/2 (‖F‖² − 3) − μ (J − 1) + λ/2 (J − 1)²`.
template <class Scalar> Scalar snh_energy_density(const StableNeoHookean& m, const Mat3<Scalar>& F) {
  const Scalar mu(m.mu), lambda(m.lambda), Jm1 = F.determinant() - Scalar(1);
  return mu / Scalar(2) * (F.squaredNorm() - Scalar(3)) - mu * Jm1 + lambda / Scalar(2) * Jm1 * Jm1;
}

/// `P = ∂Ψ/∂F = μ F + (λ(J − 1) − μ) cof F`.
template <class Scalar> Mat3<Scalar> snh_stress(const StableNeoHookean& m, const Mat3<Scalar>& F) {
  const Scalar mu(m.mu), lambda(m.lambda), J = F.determinant();
  return mu * F + (lambda * (J - Scalar(1)) - mu) * detail::cofactor(F);
}

/// `∂²Ψ/∂F² = μ I + (λ(J − 1) − μ) H_J + λ g gᵀ` on vec(F) (9×9), g = vec(cof F) and H_J the
/// block matrix `[[0, −[f2]×, [f1]×], [[f2]×, 0, −[f0]×], [−[f1]×, [f0]×, 0]]` (block (c, d):
/// ∂(cof F column c)/∂(F column d)).
template <class Scalar> Mat9<Scalar> snh_hessian(const StableNeoHookean& m, const Mat3<Scalar>& F) {
  using detail::cross_matrix;
  const Scalar mu(m.mu), lambda(m.lambda), J = F.determinant(), s = lambda * (J - Scalar(1)) - mu;
  const Mat3<Scalar> C = detail::cofactor(F);
  const Vec9<Scalar> g = Eigen::Map<const Vec9<Scalar>>(C.data());
  Mat9<Scalar> H = lambda * g * g.transpose();
  H.diagonal().array() += mu;
  const Mat3<Scalar> x0 = s * cross_matrix<Scalar>(F.col(0)), x1 = s * cross_matrix<Scalar>(F.col(1)),
                     x2 = s * cross_matrix<Scalar>(F.col(2));
  H.template block<3, 3>(0, 3) -= x2;
  H.template block<3, 3>(0, 6) += x1;
  H.template block<3, 3>(3, 0) += x2;
  H.template block<3, 3>(3, 6) -= x0;
  H.template block<3, 3>(6, 0) -= x1;
  H.template block<3, 3>(6, 3) += x0;
  return H;
}

/// The nine eigenpairs of `snh_hessian`: `vectors` orthonormal (columns), `values` in the order
/// twist (0,1), (0,2), (1,2), flip (0,1), (0,2), (1,2), then the three scaling modes.
template <class Scalar> struct SnhEigensystem {
  Vec9<Scalar> values;   ///< eigenvalues
  Mat9<Scalar> vectors;  ///< the eigenvectors on vec(F), one per column
};

/// The rotation-variant SVD `F = U diag(sigma) Vᵀ`: U and V rotations, |σ₀| ≥ |σ₁| ≥ |σ₂|,
/// σ₀, σ₁ ≥ 0, and σ₂ carrying det F's sign. One-sided Jacobi (Hestenes; Demmel & Veselić,
/// "Jacobi's method is more accurate than QR", SIMAX 13(4), 1992): plane rotations from the
/// right make F's columns orthogonal, `W = F V`, until every pair is orthogonal to ε relative;
/// then `u₀ = w₀/|w₀|`, `u₁` = w₁ orthogonalised against u₀ and normalised (any unit vector
/// orthogonal to u₀ if nothing is left), `u₂ = u₀ × u₁`, and `σ_i = u_i·w_i`. U is orthonormal
/// to rounding whatever the singular values (flat and inverted F included), and
/// `F = U Σ Vᵀ` to about ε‖F‖. For |F| below about 1e150 (double; its squared column norms
/// must not overflow).
template <class Scalar>
void rotation_variant_svd(const Mat3<Scalar>& F, Mat3<Scalar>& U, Vec3<Scalar>& sigma, Mat3<Scalar>& V) {
  using std::abs;
  using std::sqrt;
  const Scalar eps = Constants<Scalar>::epsilon(), eps2 = eps * eps;
  Mat3<Scalar> W = F;
  V.setIdentity();
  constexpr int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  for (int sweep = 0; sweep < 16; ++sweep) {
    bool rotated = false;
    for (const auto& pq : pairs) {
      const int p = pq[0], q = pq[1];
      const Scalar a = W.col(p).squaredNorm(), b = W.col(q).squaredNorm(), c = W.col(p).dot(W.col(q));
      if (!(c * c > eps2 * (a * b))) continue;  // orthogonal to rounding (also 0 or NaN)
      rotated = true;
      // the rotation that zeroes w_p·w_q (Golub & Van Loan, Sec. 8.5.2): ζ = (b − a)/(2c)
      const Scalar zeta = (b - a) / (Scalar(2) * c);
      const Scalar t = (zeta >= Scalar(0) ? Scalar(1) : Scalar(-1)) / (abs(zeta) + sqrt(Scalar(1) + zeta * zeta));
      const Scalar cs = Scalar(1) / sqrt(Scalar(1) + t * t), sn = cs * t;
      const Vec3<Scalar> wp = W.col(p), vp = V.col(p);
      W.col(p) = cs * wp - sn * W.col(q);
      W.col(q) = sn * wp + cs * W.col(q);
      V.col(p) = cs * vp - sn * V.col(q);
      V.col(q) = sn * vp + cs * V.col(q);
    }
    if (!rotated) break;
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
    u1 = detail::any_orthogonal<Scalar>(U.col(0));
  }
  U.col(1) = u1;
  U.col(2) = U.col(0).cross(u1);
  for (int i = 0; i < 3; ++i) sigma[i] = U.col(i).dot(W.col(i));
}

namespace detail {
/// What the eigensystem is made of: the rotation-variant SVD, `s = λ(J − 1) − μ`, the 3×3
/// scaling block `A` and the vectors `vec(u_i v_jᵀ)`.
template <class Scalar> struct SnhModes {
  Mat3<Scalar> U, V;      ///< F = U diag(sigma) Vᵀ
  Vec3<Scalar> sigma;     ///< signed singular values
  Scalar s;               ///< λ(J − 1) − μ: twist μ + s σ_k, flip μ − s σ_k
  Mat3<Scalar> A;         ///< ∂²Ψ/∂σ²
  Vec9<Scalar> uv[3][3];  ///< vec(u_i v_jᵀ)
  SnhModes(const StableNeoHookean& m, const Mat3<Scalar>& F) {
    rotation_variant_svd(F, U, sigma, V);
    // J as `snh_hessian` takes it (det F); the g gᵀ term's J as the singular values give it.
    // They agree to ε‖F‖³, but a large, nearly flat F leaves det F only that accurate, and
    // then this split keeps the eigensystem that of the Hessian actually computed.
    const Scalar mu(m.mu), lambda(m.lambda), J = F.determinant(), J_sigma = sigma[0] * sigma[1] * sigma[2];
    s = lambda * (J - Scalar(1)) - mu;
    const Scalar kappa = s + lambda * J_sigma;  // λ(2J − 1) − μ when the two agree
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      A(i, i) = mu + lambda * (sigma[j] * sigma[k]) * (sigma[j] * sigma[k]);
      A(j, k) = A(k, j) = sigma[i] * kappa;
    }
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) uv[i][j] = vec_outer<Scalar>(U.col(i), V.col(j));
  }
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
    e.vectors.col(p) = r * (md.uv[i][j] - md.uv[j][i]);
    e.values[3 + p] = mu - md.s * md.sigma[k];
    e.vectors.col(3 + p) = r * (md.uv[i][j] + md.uv[j][i]);
  }
  // A by tridiagonal QR (`core/jacobi.hpp`): a closed form (Cardano, Eigen's `computeDirect`)
  // loses digits in the eigenvectors of nearly repeated eigenvalues, which here made the
  // analytic projection differ from the numerical one by up to 3700 ε‖H‖
  Vec3<Scalar> a;
  Mat3<Scalar> Q;
  detail::symmetric_qr_eigen<Scalar, 3>(md.A, a, Q);
  for (int c = 0; c < 3; ++c) {
    e.values[6 + c] = a[c];
    e.vectors.col(6 + c) = Q(0, c) * md.uv[0][0] + Q(1, c) * md.uv[1][1] + Q(2, c) * md.uv[2][2];
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

/// `H⁺ = Σ max(λ, 0) q qᵀ` of the 9×9 F-space Hessian, by `how` (`none`: the Hessian itself).
template <class Scalar>
Mat9<Scalar> snh_projected_hessian(const StableNeoHookean& m, const Mat3<Scalar>& F, VolumeProjection how) {
  if (how == VolumeProjection::none) return snh_hessian(m, F);
  Mat9<Scalar> H = Mat9<Scalar>::Zero();
  if (how == VolumeProjection::numerical) {
    const Eigen::SelfAdjointEigenSolver<Mat9<Scalar>> es(snh_hessian(m, F));
    for (int i = 0; i < 9; ++i)
      if (es.eigenvalues()[i] > Scalar(0))
        H.noalias() += (es.eigenvalues()[i] * es.eigenvectors().col(i)) * es.eigenvectors().col(i).transpose();
    return Scalar(0.5) * (H + H.transpose());
  }
  // analytic: the twist and flip modes of each axis pair clamped in closed form; the scaling
  // block as `M A⁺ Mᵀ` (M = [vec(u_d v_dᵀ)]), where A⁺ = A when A is positive definite (its
  // Cholesky factorisation succeeds: no eigensolve), else A's eigenvalues clamped
  const detail::SnhModes<Scalar> md(m, F);
  const Scalar mu(m.mu), half(0.5);
  for (const auto& ijk : detail::snh_pairs) {
    const int i = ijk[0], j = ijk[1], k = ijk[2];
    const Scalar twist = mu + md.s * md.sigma[k], flip = mu - md.s * md.sigma[k];
    const Scalar lt = twist > Scalar(0) ? twist : Scalar(0), lf = flip > Scalar(0) ? flip : Scalar(0);
    // λt t tᵀ + λf f fᵀ with t, f = (a ∓ b)/√2: ½(λt + λf)(a aᵀ + b bᵀ) + ½(λf − λt)(a bᵀ + b aᵀ)
    const Vec9<Scalar>&a = md.uv[i][j], &b = md.uv[j][i];
    const Scalar c0 = half * (lt + lf), c1 = half * (lf - lt);
    H.noalias() += (c0 * a + c1 * b) * a.transpose() + (c0 * b + c1 * a) * b.transpose();
  }
  Mat3<Scalar> Ap = md.A;
  if (Eigen::LLT<Mat3<Scalar>>(md.A).info() != Eigen::Success) {
    Vec3<Scalar> a;
    Mat3<Scalar> Q;
    detail::symmetric_qr_eigen<Scalar, 3>(md.A, a, Q);
    for (int c = 0; c < 3; ++c) a[c] = a[c] > Scalar(0) ? a[c] : Scalar(0);
    Ap = Q * a.asDiagonal() * Q.transpose();
  }
  Eigen::Matrix<Scalar, 9, 3> M;
  for (int d = 0; d < 3; ++d) M.col(d) = md.uv[d][d];
  H.noalias() += (M * Ap) * M.transpose();
  return half * (H + H.transpose());
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
  const Scalar E = rest.volume * snh_energy_density(m, F);
  if (!detail::is_finite(E)) return Status::overflow;
  Vec12<Scalar> g = Vec12<Scalar>::Zero();  // (written only when asked for)
  Mat12<Scalar> H;
  if (gradient) {
    g = rest.volume * pull_back_stress(rest, snh_stress(m, F));
    if (!detail::all_finite(g)) return Status::overflow;
  }
  if (hessian) {
    H = rest.volume * pull_back_hessian(rest, snh_projected_hessian(m, F, how));
    if (!detail::all_finite(H)) return Status::overflow;
  }
  value = E;
  if (gradient) *gradient = g;
  if (hessian) *hessian = H;
  return Status::ok;
}

}  // namespace pce
