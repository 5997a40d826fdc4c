// SPDX-License-Identifier: MIT
/// @file
/// Batched evaluation: `evaluate` (or closest-feature evaluation) of `count` pairs held in
/// one array, each output written into a caller-owned row-major array. Row `i` of every
/// output is what the single-pair functions give for pair `i`, bit for bit: the loop calls
/// `pair_energy` (or `closest_feature_energy`) and then only the functions whose outputs
/// were asked for. Serial; callers thread it by handing disjoint row ranges to threads (the
/// Python module does). No heap allocation.
#pragma once

#include <pce/energy/closest_feature.hpp>
#include <pce/energy/pair_energy.hpp>
#include <pce/energy/point_edge_energy.hpp>
#include <pce/energy/point_point_energy.hpp>

#include <cstddef>
#include <limits>
#include <type_traits>

namespace pce {

/// Where `evaluate_batch` and `closest_feature_batch` write, row `i` at offset `i × width`.
/// A null pointer skips that output and the work only it needs. `D` is the kind's
/// coordinate count (12, 9, 6; 12 for closest features), `F` its frame-space count (9, 6, 3;
/// 9 for closest features).
template <class Scalar> struct BatchOutput {
  Status* status = nullptr;       ///< n: the pair's status (`ok` or why not)
  Scalar* length = nullptr;       ///< n: L
  Scalar* value = nullptr;        ///< n: E = ψ(L)
  Scalar* gradient = nullptr;     ///< n × D: ∇E
  Scalar* hessian = nullptr;      ///< n × D × D, row-major: the exact ∇²E
  Scalar* projected = nullptr;    ///< n × D × D, row-major: `projected_hessian` by the strategy (`none`: ∇²E)
  Scalar* eigenvalues = nullptr;  ///< n × F: frame-space eigenvalues, ascending (closest features: the
                                  ///< evaluated kind's 9, 6 or 3, then NaN)
  Feature* feature = nullptr;     ///< n: the kind evaluated (closest features only; rows not ok untouched)
};

namespace detail {

/// NaN in row `i` of every float output (a row that is not ok).
template <class Scalar> void batch_nan_row(const BatchOutput<Scalar>& out, std::size_t i, int dofs, int frame_dofs) {
  const Scalar nan = std::numeric_limits<Scalar>::quiet_NaN();
  const auto fill = [&](Scalar* p, std::size_t width) {
    if (p)
      for (std::size_t j = 0; j < width; ++j) p[i * width + j] = nan;
  };
  const auto d = static_cast<std::size_t>(dofs);
  fill(out.length, 1);
  fill(out.value, 1);
  fill(out.gradient, d);
  fill(out.hessian, d * d);
  fill(out.projected, d * d);
  fill(out.eigenvalues, static_cast<std::size_t>(frame_dofs));
}

/// Whether every entry of `m` is finite. For the built-in floating types as one vectorised
/// sum, Σ 0·mᵢⱼ, which is 0 exactly when every entry is finite (0·±∞ and 0·NaN are NaN); it
/// costs about half of Eigen's `allFinite` per pair. Entry by entry for the other types.
template <class Derived> bool batch_finite(const Eigen::MatrixBase<Derived>& m) {
  using Scalar = typename Derived::Scalar;
  if constexpr (std::is_floating_point_v<Scalar>)
    return (m.array() * Scalar(0)).sum() == Scalar(0);
  else
    return all_finite(m);
}

/// The requested outputs of one evaluated pair, checked finite before anything is written
/// (as `evaluate` checks): `overflow` and nothing written otherwise. `Energy` is any type
/// with the `energy_gradient` / `energy_hessian` / `projected_hessian` overloads;
/// `eigenvalues(e, v)` fills the first `FrameDofs` entries of `v` and returns how many are real.
template <int Dofs, int FrameDofs, class Scalar, class Energy, class Eigenvalues>
Status batch_store(const Energy& e, const Scalar& length, const Scalar& value, Projection strategy,
                   const BatchOutput<Scalar>& out, std::size_t i, Eigenvalues eigenvalues) {
  using RowMajor = Eigen::Matrix<Scalar, Dofs, Dofs, Eigen::RowMajor>;
  VecN<Scalar, Dofs> g;
  MatN<Scalar, Dofs> H, P;
  VecN<Scalar, FrameDofs> lambda;
  int real = FrameDofs;
  bool finite = is_finite(length) && is_finite(value);
  if (out.gradient) finite = batch_finite(g = energy_gradient(e)) && finite;
  if (out.hessian || (out.projected && strategy == Projection::none))
    finite = batch_finite(H = energy_hessian(e)) && finite;
  if (out.projected && strategy != Projection::none)
    finite = batch_finite(P = projected_hessian(e, strategy)) && finite;
  if (out.eigenvalues) {
    real = eigenvalues(e, lambda);
    finite = batch_finite(lambda.head(real)) && finite;
  }
  if (!finite) return Status::overflow;
  const auto d = static_cast<std::size_t>(Dofs);
  if (out.length) out.length[i] = length;
  if (out.value) out.value[i] = value;
  if (out.gradient) Eigen::Map<VecN<Scalar, Dofs>>(out.gradient + i * d) = g;
  if (out.hessian) Eigen::Map<RowMajor>(out.hessian + i * d * d) = H;
  if (out.projected) Eigen::Map<RowMajor>(out.projected + i * d * d) = strategy == Projection::none ? H : P;
  if (out.eigenvalues) {
    for (int j = real; j < FrameDofs; ++j) lambda[j] = std::numeric_limits<Scalar>::quiet_NaN();
    Eigen::Map<VecN<Scalar, FrameDofs>>(out.eigenvalues + i * static_cast<std::size_t>(FrameDofs)) = lambda;
  }
  return Status::ok;
}

}  // namespace detail

/// `evaluate<Pair>` for `count` pairs, pair i's D = `Pair::dofs` coordinates starting at
/// x + i·D, into `out`: row i of each requested output holds pair i's, or NaN where its
/// status is not ok. A pair whose requested outputs are not all finite (ψ included) is
/// `overflow`.
template <class Pair, class Scalar, class Length, class Penalty>
void evaluate_batch(const Scalar* x, std::size_t count, const Length& length, const Penalty& penalty,
                    Projection strategy, const BatchOutput<Scalar>& out) {
  constexpr int D = Pair::dofs, F = Pair::frame_dofs;
  const auto eigenvalues = [](const auto& e, VecN<Scalar, Pair::frame_dofs>& v) {
    v = energy_eigensystem(e).values;
    return Pair::frame_dofs;
  };
  for (std::size_t i = 0; i < count; ++i) {
    const VecN<Scalar, D> xi = Eigen::Map<const VecN<Scalar, D>>(x + i * static_cast<std::size_t>(D));
    typename Pair::template Energy<Scalar> e;
    Status s = pair_energy<Pair>(xi, length, penalty, e);
    if (s == Status::ok) s = detail::batch_store<D, F>(e, e.length, e.psi.value, strategy, out, i, eigenvalues);
    if (s != Status::ok) detail::batch_nan_row(out, i, D, F);
    if (out.status) out.status[i] = s;
  }
}

/// `closest_feature_energy<Pair>` (`VertexFace` or `EdgeEdge`; unsigned length) for `count`
/// pairs, pair i's 12 coordinates starting at x + 12i, into `out`, with the kind evaluated
/// in `out.feature` and the eigenvalues of that kind (9, 6 or 3, then NaN) in
/// `out.eigenvalues` (width 9).
template <class Pair, class Scalar, class Penalty>
void closest_feature_batch(const Scalar* x, std::size_t count, const Penalty& penalty, Projection strategy,
                           const BatchOutput<Scalar>& out) {
  const auto eigenvalues = [](const ClosestFeatureEnergy<Scalar>& e, Vec9<Scalar>& v) {
    const FeatureEigenvalues<Scalar> r = feature_eigenvalues(e);
    v = r.values;
    return r.count;
  };
  for (std::size_t i = 0; i < count; ++i) {
    const Vec12<Scalar> xi = Eigen::Map<const Vec12<Scalar>>(x + i * 12);
    ClosestFeatureEnergy<Scalar> e;
    Status s = closest_feature_energy<Pair>(xi, UnsignedLength{}, penalty, e);
    if (s == Status::ok) s = detail::batch_store<12, 9>(e, e.length, e.psi.value, strategy, out, i, eigenvalues);
    if (s != Status::ok) detail::batch_nan_row(out, i, 12, 9);
    if (s == Status::ok && out.feature) out.feature[i] = e.feature;
    if (out.status) out.status[i] = s;
  }
}

}  // namespace pce
