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

#include <pce/core/types.hpp>
#include <pce/volumes/tet_deformation.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <cmath>

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

/// The rotation-variant SVD `F = U diag(sigma) Vᵀ`: U and V rotations; the smallest singular
/// value carries det F's sign.
template <class Scalar>
void rotation_variant_svd(const Mat3<Scalar>& F, Mat3<Scalar>& U, Vec3<Scalar>& sigma, Mat3<Scalar>& V) {
  const Eigen::JacobiSVD<Mat3<Scalar>, Eigen::NoQRPreconditioner> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  U = svd.matrixU();
  V = svd.matrixV();
  sigma = svd.singularValues();
  if (U.determinant() < Scalar(0)) U.col(2) = -U.col(2), sigma[2] = -sigma[2];
  if (V.determinant() < Scalar(0)) V.col(2) = -V.col(2), sigma[2] = -sigma[2];
}

/// The closed-form eigensystem of `snh_hessian(m, F)` (see the file comment): one 3×3 SVD
/// and one 3×3 symmetric eigenproblem, no 9×9 solve.
template <class Scalar> SnhEigensystem<Scalar> snh_eigensystem(const StableNeoHookean& m, const Mat3<Scalar>& F) {
  using std::sqrt;
  Mat3<Scalar> U, V;
  Vec3<Scalar> sg;
  rotation_variant_svd(F, U, sg, V);
  const Scalar mu(m.mu), lambda(m.lambda), J = sg[0] * sg[1] * sg[2];
  const Scalar s = lambda * (J - Scalar(1)) - mu, kappa = lambda * (Scalar(2) * J - Scalar(1)) - mu;
  const Scalar r = Scalar(1) / sqrt(Scalar(2));
  SnhEigensystem<Scalar> e;
  constexpr int pairs[3][3] = {{0, 1, 2}, {0, 2, 1}, {1, 2, 0}};
  for (int p = 0; p < 3; ++p) {
    const int i = pairs[p][0], j = pairs[p][1], k = pairs[p][2];
    const Vec9<Scalar> a = detail::vec_outer<Scalar>(U.col(i), V.col(j)),
                       b = detail::vec_outer<Scalar>(U.col(j), V.col(i));
    e.values[p] = mu + s * sg[k];
    e.vectors.col(p) = r * (a - b);
    e.values[3 + p] = mu - s * sg[k];
    e.vectors.col(3 + p) = r * (a + b);
  }
  Mat3<Scalar> A;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    A(i, i) = mu + lambda * (sg[j] * sg[k]) * (sg[j] * sg[k]);
    A(j, k) = A(k, j) = sg[i] * kappa;
  }
  // A by Eigen's 3×3 tridiagonal QR: its closed form (`computeDirect`, Cardano) loses
  // digits in the eigenvectors of nearly repeated eigenvalues, which here made the analytic
  // projection differ from the numerical one by up to 3700 ε‖H‖ (48 ε‖H‖ with QR)
  const Eigen::SelfAdjointEigenSolver<Mat3<Scalar>> es(A);
  for (int c = 0; c < 3; ++c) {
    e.values[6 + c] = es.eigenvalues()[c];
    Vec9<Scalar> q = Vec9<Scalar>::Zero();
    for (int d = 0; d < 3; ++d) q += es.eigenvectors()(d, c) * detail::vec_outer<Scalar>(U.col(d), V.col(d));
    e.vectors.col(6 + c) = q;
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
  Vec9<Scalar> values;
  Mat9<Scalar> vectors;
  if (how == VolumeProjection::analytic) {
    const SnhEigensystem<Scalar> e = snh_eigensystem(m, F);
    values = e.values, vectors = e.vectors;
  } else {
    const Eigen::SelfAdjointEigenSolver<Mat9<Scalar>> es(snh_hessian(m, F));
    values = es.eigenvalues(), vectors = es.eigenvectors();
  }
  Mat9<Scalar> H = Mat9<Scalar>::Zero();
  for (int i = 0; i < 9; ++i)
    if (values[i] > Scalar(0)) H.noalias() += (values[i] * vectors.col(i)) * vectors.col(i).transpose();
  return Scalar(0.5) * (H + H.transpose());
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
  Vec12<Scalar> g;
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
