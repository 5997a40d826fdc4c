// SPDX-License-Identifier: MIT
/// @file
/// Lagged smoothed Coulomb friction of one contact (Li et al., "Incremental Potential
/// Contact", ACM TOG 39(4), 2020, Sec. 5): an incremental potential whose gradient is the
/// friction force of a contact with a frozen normal force λ, a frozen tangent basis T and
/// frozen closest-point weights w.
///
/// A contact of `N` vertices (4 for a vertex-face or edge-edge pair, 1 for a vertex on a
/// kinematic obstacle) moves its closest points apart by the relative displacement
///
///     r(Δx) = Σⱼ wⱼ Δxⱼ − o,        u = Tᵀ r ∈ ℝ²,   y = |u|,
///
/// over a time step, Δxⱼ = xⱼ − xⱼⁿ the vertex displacements since the step's start and o
/// the other body's surface displacement at the contact (a moving obstacle; 0 for pairs).
/// The potential is D(Δx) = μλ f₀(y), with the mollifier (ε = ε_v h, the slip velocity times
/// the step: a length)
///
///     f₁(y) = 2y/ε − y²/ε²  for y < ε,  1 beyond;
///     f₀(y) = ε/3 + y²/ε − y³/(3ε²)  for y < ε,  y beyond  (f₀′ = f₁),
///
/// so that −∇D = −μλ f₁(y) T û wⱼ is Coulomb's force μλ opposing the slip û = u/y once the
/// slip speed y/h exceeds ε_v, and a stiff spring (2μλ/ε) below it (static friction, with
/// a creep of at most ε_v). f₀ is C² (f₁′(ε) = 0 from both sides).
///
/// Derivatives (w ⊗ T the 3N×2 map from Δx to u):
///
///     ∇D  = μλ (f₁(y)/y) (w ⊗ T) u,
///     ∇²D = μλ (w ⊗ T) [ f₁′(y) ûûᵀ + (f₁(y)/y)(I − ûûᵀ) ] (w ⊗ T)ᵀ.
///
/// The 2×2 block's eigenpairs are (f₁′(y), û) and (f₁(y)/y, û⊥): with this f₁ both are ≥ 0
/// (f₁′ = 2(ε − y)/ε² below ε, 0 beyond), so the exact Hessian is already positive
/// semidefinite; `friction_hessian` still clamps the eigenvalues at 0 (the standard
/// projection of the tangent block, IPC Sec. 5). At y = 0 both are 2/ε and the block is
/// (2/ε) I, its limit from every direction.
#pragma once

#include <pce/core/types.hpp>
#include <pce/energy/closest_feature.hpp>
#include <pce/frames/frame.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace pce {

/// f₀(y), f₁(y)/y and f₁′(y) of the friction mollifier with ε = ε_v h (see the file comment).
template <class Scalar> struct FrictionMollifier {
  Scalar f0;         ///< f₀(y): ε/3 + y²/ε − y³/(3ε²) below ε, y beyond
  Scalar f1_over_y;  ///< f₁(y)/y: 2/ε − y/ε² below ε, 1/y beyond (2/ε at y = 0)
  Scalar df1;        ///< f₁′(y): 2/ε − 2y/ε² below ε, 0 beyond
};

/// The mollifier at slip y ≥ 0 for ε > 0 (IPC Sec. 5, f₀ with f₀′ = f₁).
template <class Scalar>
PCE_HOST_DEVICE FrictionMollifier<Scalar> friction_mollifier(const Scalar& y, const Scalar& eps) {
  FrictionMollifier<Scalar> m;
  if (y >= eps) {
    m.f0 = y;
    m.f1_over_y = Scalar(1) / y;
    m.df1 = Scalar(0);
  } else {
    const Scalar s = y / eps;
    m.f0 = eps * (Scalar(1) / Scalar(3) + s * s - s * s * s / Scalar(3));
    m.f1_over_y = (Scalar(2) - s) / eps;
    m.df1 = Scalar(2) * (Scalar(1) - s) / eps;
  }
  return m;
}

/// The frozen quantities of one contact's friction: closest-point weights w, tangent
/// basis T, the other surface's displacement o, μλ and ε = ε_v h (see the file comment).
template <class Scalar, int N> struct LaggedFriction {
  Eigen::Matrix<Scalar, N, 1> weights;         ///< wⱼ: r = Σⱼ wⱼ Δxⱼ − o (first primitive +, second −)
  Eigen::Matrix<Scalar, 3, 2> basis;           ///< T: two orthonormal columns orthogonal to the contact normal
  Vec3<Scalar> offset = Vec3<Scalar>::Zero();  ///< o: the other body's surface displacement over the step
  Scalar mu_lambda = Scalar(0);                ///< μλ ≥ 0, the Coulomb force bound (N)
  Scalar static_slip = Scalar(1);              ///< ε = ε_v h > 0 (m): below this slip the contact sticks
};

/// An orthonormal basis T (3×2) of the plane orthogonal to the unit vector `n`: the axis
/// least aligned with n, made orthogonal to it, then n × that; a function of n alone.
template <class Scalar> PCE_HOST_DEVICE Eigen::Matrix<Scalar, 3, 2> tangent_basis(const Vec3<Scalar>& n) {
  using std::abs;
  Vec3<Scalar> a = Vec3<Scalar>::Zero();
  if (abs(n.x()) <= abs(n.y()) && abs(n.x()) <= abs(n.z()))
    a.x() = Scalar(1);
  else if (abs(n.y()) <= abs(n.z()))
    a.y() = Scalar(1);
  else
    a.z() = Scalar(1);
  Eigen::Matrix<Scalar, 3, 2> T;
  T.col(0) = (a - a.dot(n) * n).normalized();
  T.col(1) = n.cross(T.col(0));
  return T;
}

/// The tangential slip u = Tᵀ (Σⱼ wⱼ Δxⱼ − o) of displacements `dx` (3N) since the step's start.
template <class Scalar, int N>
PCE_HOST_DEVICE Eigen::Matrix<Scalar, 2, 1> friction_slip(const LaggedFriction<Scalar, N>& f,
                                                          const Eigen::Matrix<Scalar, 3 * N, 1>& dx) {
  Vec3<Scalar> r = -f.offset;
  for (int j = 0; j < N; ++j) r += f.weights[j] * dx.template segment<3>(3 * j);
  return f.basis.transpose() * r;
}

/// D = μλ f₀(|u|), the friction potential of displacements `dx` since the step's start.
template <class Scalar, int N>
PCE_HOST_DEVICE Scalar friction_energy(const LaggedFriction<Scalar, N>& f, const Eigen::Matrix<Scalar, 3 * N, 1>& dx) {
  return f.mu_lambda * friction_mollifier(friction_slip(f, dx).norm(), f.static_slip).f0;
}

/// ∇D = μλ (f₁(y)/y) (w ⊗ T) u (3N).
template <class Scalar, int N>
PCE_HOST_DEVICE Eigen::Matrix<Scalar, 3 * N, 1> friction_gradient(const LaggedFriction<Scalar, N>& f,
                                                                  const Eigen::Matrix<Scalar, 3 * N, 1>& dx) {
  const Eigen::Matrix<Scalar, 2, 1> u = friction_slip(f, dx);
  const Vec3<Scalar> t = f.mu_lambda * friction_mollifier(u.norm(), f.static_slip).f1_over_y * (f.basis * u);
  Eigen::Matrix<Scalar, 3 * N, 1> g;
  for (int j = 0; j < N; ++j) g.template segment<3>(3 * j) = f.weights[j] * t;
  return g;
}

/// The tangent block's PSD matrix μλ T [max(f₁′, 0) ûûᵀ + (f₁/y)(I − ûûᵀ)] Tᵀ (3×3; (2μλ/ε) T Tᵀ
/// at y = 0); the Hessian is (w wᵀ) ⊗ this.
template <class Scalar, int N>
PCE_HOST_DEVICE Mat3<Scalar> friction_tangent_block(const LaggedFriction<Scalar, N>& f,
                                                    const Eigen::Matrix<Scalar, 3 * N, 1>& dx) {
  using std::max;
  const Eigen::Matrix<Scalar, 2, 1> u = friction_slip(f, dx);
  const Scalar y = u.norm();
  const FrictionMollifier<Scalar> m = friction_mollifier(y, f.static_slip);
  Eigen::Matrix<Scalar, 2, 2> B = m.f1_over_y * Eigen::Matrix<Scalar, 2, 2>::Identity();
  if (y > Scalar(0)) {
    const Eigen::Matrix<Scalar, 2, 1> uh = u / y;
    B += (max(m.df1, Scalar(0)) - m.f1_over_y) * (uh * uh.transpose());
  }
  return f.mu_lambda * (f.basis * B * f.basis.transpose());
}

/// The isotropic block μλ (f₁(y)/y) T Tᵀ (3×3), which is ⪰ `friction_tangent_block` (f₁ is
/// concave with f₁(0) = 0, so f₁′ ≤ f₁/y). f₁(y)/y does not increase with y, so f₀(|u|) is
/// concave in |u|² and lies below its tangent quadratic there,
///     D(u′) ≤ D(u) + μλ (f₁(y)/y) [uᵀ(u′ − u) + ½ |u′ − u|²]
/// (the iteratively reweighted bound of Weiszfeld's method): a solver that moves one vertex
/// at a time with this block (w_j² times it for vertex j) never overshoots a friction
/// contact's slip past where D's own minimum along the move lies, whereas the Hessian's
/// block, flat along a sliding contact's slip (f₁′ = 0 beyond ε), sends a lone vertex as far
/// as its other terms let it. At y = 0 it is the Hessian's (2μλ/ε) T Tᵀ.
template <class Scalar, int N>
PCE_HOST_DEVICE Mat3<Scalar> friction_majorizer_block(const LaggedFriction<Scalar, N>& f,
                                                      const Eigen::Matrix<Scalar, 3 * N, 1>& dx) {
  const Scalar y = friction_slip(f, dx).norm();
  return (f.mu_lambda * friction_mollifier(y, f.static_slip).f1_over_y) * (f.basis * f.basis.transpose());
}

/// The tangential friction force, in the basis T, that Newton's quadratic model of D about
/// displacements `dx` assigns after a further step `ddx` (both 3N):
///
///     φ = μλ [ (f₁(y)/y) u + (max(f₁′, 0) ûûᵀ + (f₁/y)(I − ûûᵀ)) Δu ],   Δu = Tᵀ Σⱼ wⱼ ddxⱼ,
///
/// the gradient's tangential force at u plus the Hessian's tangent block times the slip of
/// the step (the model `friction_gradient` + `friction_hessian` · ddx, in the 2D slip
/// coordinates). Coulomb's law bounds the true force by μλ (|f₁| ≤ 1); |φ| > μλ means the
/// model's static spring (2μλ/ε at u = 0) was asked for more than friction can hold, i.e. the
/// contact must slide beyond what the step shows.
template <class Scalar, int N>
PCE_HOST_DEVICE Eigen::Matrix<Scalar, 2, 1> friction_model_force(const LaggedFriction<Scalar, N>& f,
                                                                 const Eigen::Matrix<Scalar, 3 * N, 1>& dx,
                                                                 const Eigen::Matrix<Scalar, 3 * N, 1>& ddx) {
  using std::max;
  const Eigen::Matrix<Scalar, 2, 1> u = friction_slip(f, dx);
  Vec3<Scalar> dr = Vec3<Scalar>::Zero();
  for (int j = 0; j < N; ++j) dr += f.weights[j] * ddx.template segment<3>(3 * j);
  const Eigen::Matrix<Scalar, 2, 1> du = f.basis.transpose() * dr;
  const Scalar y = u.norm();
  const FrictionMollifier<Scalar> m = friction_mollifier(y, f.static_slip);
  Eigen::Matrix<Scalar, 2, 1> phi = m.f1_over_y * (u + du);
  if (y > Scalar(0)) {
    const Eigen::Matrix<Scalar, 2, 1> uh = u / y;
    phi += (max(m.df1, Scalar(0)) - m.f1_over_y) * uh.dot(du) * uh;
  }
  return f.mu_lambda * phi;
}

/// The tangential friction force at displacements `dx`, in the basis T (Coulomb's force
/// once sliding, the static spring below ε):
///
///     F = μλ (f₁(y)/y) u,   |F| = μλ f₁(y) ≤ μλ,
///
/// the gradient ∇D = (w ⊗ T) F in the slip coordinates. `friction_model_force(f, dx, ddx)`
/// minus this at dx + ddx is the error of Newton's quadratic model of D over the step ddx.
template <class Scalar, int N>
PCE_HOST_DEVICE Eigen::Matrix<Scalar, 2, 1> friction_force(const LaggedFriction<Scalar, N>& f,
                                                           const Eigen::Matrix<Scalar, 3 * N, 1>& dx) {
  const Eigen::Matrix<Scalar, 2, 1> u = friction_slip(f, dx);
  return f.mu_lambda * friction_mollifier(u.norm(), f.static_slip).f1_over_y * u;
}

/// ∇²D, positive semidefinite: (w wᵀ) ⊗ `friction_tangent_block` (3N×3N).
template <class Scalar, int N>
PCE_HOST_DEVICE Eigen::Matrix<Scalar, 3 * N, 3 * N> friction_hessian(const LaggedFriction<Scalar, N>& f,
                                                                     const Eigen::Matrix<Scalar, 3 * N, 1>& dx) {
  const Mat3<Scalar> K = friction_tangent_block(f, dx);
  Eigen::Matrix<Scalar, 3 * N, 3 * N> H;
  for (int j = 0; j < N; ++j)
    for (int k = 0; k < N; ++k) H.template block<3, 3>(3 * j, 3 * k) = (f.weights[j] * f.weights[k]) * K;
  return H;
}

/// The closest-point weights and unit normal of a plane-mode pair from its frame: w = the
/// frame's third row P(2,·) (e2⊥ = Σⱼ P(2,j) xⱼ = l n̂ joins the closest points of the plane
/// or line distance), n = n̂.
template <class Scalar>
PCE_HOST_DEVICE void friction_geometry(const Frame<Scalar>& frame, VecN<Scalar, 4>& w, Vec3<Scalar>& n) {
  w = frame.P.row(2).transpose();
  n = frame.n;
}

/// The closest-point weights w (Σⱼ wⱼ xⱼ = the vector between the closest points) and the
/// unit normal (that vector, normalised) of a closest-feature evaluation `ce` of the pair
/// `x`: the frame's for the plane kinds, (1, −(1 − s), −s) on (p, e0, e1) for point-edge
/// with s the foot's parameter, (1, −1) on (p, q) for point-point. Returns false when the
/// closest points coincide (no normal).
template <class Scalar> PCE_HOST_DEVICE bool friction_geometry(const ClosestFeatureEnergy<Scalar>& ce,
                                                               const Vec12<Scalar>& x, VecN<Scalar, 4>& w,
                                                               Vec3<Scalar>& n) {
  using std::clamp;
  w.setZero();
  switch (ce.feature) {
    case Feature::point_plane:
    case Feature::line_line:
      friction_geometry(ce.plane.frame, w, n);
      return true;
    case Feature::point_edge: {
      const Vec3<Scalar> p = x.template segment<3>(3 * ce.points[0]), a = x.template segment<3>(3 * ce.points[1]),
                         b = x.template segment<3>(3 * ce.points[2]);
      const Vec3<Scalar> e = b - a;
      const Scalar ee = e.squaredNorm();
      const Scalar s = ee > Scalar(0) ? clamp(Scalar((p - a).dot(e) / ee), Scalar(0), Scalar(1)) : Scalar(0);
      w[ce.points[0]] = Scalar(1);
      w[ce.points[1]] = -(Scalar(1) - s);
      w[ce.points[2]] = -s;
      break;
    }
    case Feature::point_point:
      w[ce.points[0]] = Scalar(1);
      w[ce.points[1]] = Scalar(-1);
      break;
  }
  Vec3<Scalar> d = Vec3<Scalar>::Zero();
  for (int j = 0; j < 4; ++j) d += w[j] * x.template segment<3>(3 * j);
  const Scalar len = d.norm();
  if (!(len > Scalar(0))) return false;
  n = d / len;
  return true;
}

}  // namespace pce
