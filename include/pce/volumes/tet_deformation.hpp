// SPDX-License-Identifier: MIT
/// @file
/// A linear tetrahedron's deformation: the deformation gradient
///
///     F = Ds Dm⁻¹,   Ds = [x1 − x0, x2 − x0, x3 − x0],   Dm the same at rest,
///
/// constant over the element, its rest volume `V = det(Dm)/6`, and the constant linear map
/// `vec(F) = B x` (9×12, `vec` column by column) that the derivatives of a per-element energy
/// `V Ψ(F)` are pulled back through: `∇ = V Bᵀ vec(∂Ψ/∂F)`, `∇² = V Bᵀ (∂²Ψ/∂F²) B`
/// (Sifakis & Barbič, "FEM Simulation of 3D Deformable Solids", SIGGRAPH 2012 course, Sec. 4;
/// Kim & Eberle, "Dynamic Deformables", SIGGRAPH 2022 course, Sec. 4.2). `B` is never formed:
/// with `G` (4×3) the derivatives of F's columns by the vertices, `G.row(j) = Dm⁻¹.row(j − 1)`
/// for j ≥ 1 and `G.row(0) = −Σ_j G.row(j)`, `∂F/∂x_j = (·) G.row(j)`.
#pragma once

#include <pce/core/types.hpp>

#include <Eigen/LU>

#include <cmath>

namespace pce {

/// What a tetrahedron keeps of its rest shape.
template <class Scalar> struct TetRest {
  Eigen::Matrix<Scalar, 4, 3> G;  ///< ∂F/∂x_j = (·)·G.row(j): rows Dm⁻¹ (vertices 1–3) and minus their sum
  Scalar volume;                  ///< V = det(Dm)/6 > 0
};

/// The rest shape of the tetrahedron `X = (X0, X1, X2, X3)`: `invalid_input` for a
/// coordinate that is not finite or beyond `Constants::max_coordinate`, `degenerate` unless
/// `det(Dm) > 0` (a flat or inverted rest tetrahedron: X1 − X0, X2 − X0, X3 − X0 must be a
/// right-handed triple), or when Dm⁻¹ is not finite; `rest` is written only on `ok`.
template <class Scalar> Status tet_rest(const Vec12<Scalar>& X, TetRest<Scalar>& rest) {
  if (!detail::coordinates_valid(X)) return Status::invalid_input;
  Mat3<Scalar> Dm;
  for (int c = 0; c < 3; ++c) Dm.col(c) = X.template segment<3>(3 * (c + 1)) - X.template segment<3>(0);
  const Scalar det = Dm.determinant();
  if (!(det > Scalar(0))) return Status::degenerate;
  const Mat3<Scalar> inv = Dm.inverse();
  if (!detail::all_finite(inv)) return Status::degenerate;
  rest.G.template bottomRows<3>() = inv;
  rest.G.row(0) = -inv.colwise().sum();
  rest.volume = det / Scalar(6);
  return Status::ok;
}

/// `F = Ds Dm⁻¹ = Σ_j x_j G.row(j)` of the deformed tetrahedron `x`.
template <class Scalar> Mat3<Scalar> deformation_gradient(const TetRest<Scalar>& rest, const Vec12<Scalar>& x) {
  Mat3<Scalar> F = x.template segment<3>(0) * rest.G.row(0);
  for (int j = 1; j < 4; ++j) F.noalias() += x.template segment<3>(3 * j) * rest.G.row(j);
  return F;
}

/// `Bᵀ vec(P)` for a 3×3 `P` (a first Piola–Kirchhoff stress): vertex j gets `P G.row(j)ᵀ`.
template <class Scalar> Vec12<Scalar> pull_back_stress(const TetRest<Scalar>& rest, const Mat3<Scalar>& P) {
  Vec12<Scalar> g;
  for (int j = 0; j < 4; ++j) g.template segment<3>(3 * j) = P * rest.G.row(j).transpose();
  return g;
}

/// `scale · Bᵀ H B` for a symmetric 9×9 `H` on vec(F): block (j, l) is
/// `scale · Σ_c,d G(j, c) H_cd G(l, d)` (H_cd the 3×3 block of H for F's columns c and d).
/// For the vertices 1–3 (G's rows Dm⁻¹) in two steps: `T = scale · H (Dm⁻¹ ⊗ I)ᵀ`, whose
/// column block l − 1 is `Σ_d scale·G(l, d) (column block d of H)`, then the blocks j ≤ l
/// column by column, `Σ_c G(j, c) t_c` (t_c the entries 3c..3c + 2 of a column of T); the
/// diagonal blocks are symmetrised (`(M + Mᵀ)/2`) and the others mirrored. G's row 0 is minus
/// the sum of the others, so vertex 0's blocks are negated sums, `(0, l) = −Σ_{j≥1} (j, l)` for
/// l ≥ 1 and `(0, 0) = −Σ_{l≥1} (0, l)` (symmetrised), mirrored likewise: the result is
/// symmetric bit for bit.
template <class Scalar>
Mat12<Scalar> pull_back_hessian(const TetRest<Scalar>& rest, const Mat9<Scalar>& H, const Scalar& scale = Scalar(1)) {
  const Eigen::Matrix<Scalar, 4, 3>& G = rest.G;
  Mat9<Scalar> T;  // scale · H (Dm⁻¹ ⊗ I)ᵀ
  for (int l = 0; l < 3; ++l)
    T.template middleCols<3>(3 * l) = (scale * G(l + 1, 0)) * H.template middleCols<3>(0) +
                                      (scale * G(l + 1, 1)) * H.template middleCols<3>(3) +
                                      (scale * G(l + 1, 2)) * H.template middleCols<3>(6);
  Mat12<Scalar> out;
  for (int col = 0; col < 9; ++col) {  // blocks (j, l), 1 ≤ j ≤ l, column 3l + col % 3 of out
    const int l = col / 3 + 1;
    const auto t = T.col(col);
    for (int j = 1; j <= l; ++j)
      out.col(3 + col).template segment<3>(3 * j) =
          G(j, 0) * t.template segment<3>(0) + G(j, 1) * t.template segment<3>(3) + G(j, 2) * t.template segment<3>(6);
  }
  for (int j = 1; j < 4; ++j) {
    const Mat3<Scalar> b = out.template block<3, 3>(3 * j, 3 * j);
    out.template block<3, 3>(3 * j, 3 * j) = Scalar(0.5) * (b + b.transpose());
  }
  for (int l = 2; l < 4; ++l)
    for (int j = 1; j < l; ++j)
      out.template block<3, 3>(3 * l, 3 * j) = out.template block<3, 3>(3 * j, 3 * l).transpose();
  for (int l = 1; l < 4; ++l)  // vertex 0
    out.template block<3, 3>(0, 3 * l) =
        -(out.template block<3, 3>(3, 3 * l) + out.template block<3, 3>(6, 3 * l) + out.template block<3, 3>(9, 3 * l));
  const Mat3<Scalar> b00 =
      -(out.template block<3, 3>(0, 3) + out.template block<3, 3>(0, 6) + out.template block<3, 3>(0, 9));
  out.template block<3, 3>(0, 0) = Scalar(0.5) * (b00 + b00.transpose());
  for (int l = 1; l < 4; ++l) out.template block<3, 3>(3 * l, 0) = out.template block<3, 3>(0, 3 * l).transpose();
  return out;
}

}  // namespace pce
