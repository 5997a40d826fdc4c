// SPDX-License-Identifier: MIT
/// @file
/// Batched evaluation: `evaluate` (or closest-feature evaluation) of `count` pairs held in
/// one array, each output written into a caller-owned row-major array. Row `i` of every
/// output is what the single-pair functions give for pair `i`, bit for bit.
///
/// For the plane kinds, when the outputs are among the length, value, gradient, exact Hessian
/// and a projection by `analytic`, `abs` or `none`, the pairs go through a packet at a time,
/// one per SIMD lane (`core/lanes.hpp`: 2 doubles or 4 floats with SSE2): the frame, the
/// gradient and the Hessians run the same templated arithmetic as the single-pair functions
/// (`frames/frame.hpp`, `energy/plane_assembly.hpp`), and ψ is the penalty's own scalar code,
/// lane by lane, so the bits are the same. (Compiled with floating-point contraction into FMAs,
/// e.g. `-march=native` with GCC's default `-ffp-contract=fast`, the two may contract
/// differently and agree to rounding only.) A lane that the single-pair path would rescale, or
/// orthogonalise twice, or that is not `ok`, is evaluated again by the single-pair functions.
/// Otherwise the loop calls `pair_energy` (or `closest_feature_energy`) and then only the
/// functions whose outputs were asked for. Serial; callers thread it by handing disjoint row
/// ranges to threads (the Python module does). No heap allocation.
#pragma once

#include <pce/core/lanes.hpp>
#include <pce/energy/closest_feature.hpp>
#include <pce/energy/pair_energy.hpp>
#include <pce/energy/plane_assembly.hpp>
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
template <class Scalar>
PCE_HOST_DEVICE void batch_nan_row(const BatchOutput<Scalar>& out, std::size_t i, int dofs, int frame_dofs) {
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
template <class Derived> PCE_HOST_DEVICE bool batch_finite(const Eigen::MatrixBase<Derived>& m) {
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
PCE_HOST_DEVICE Status batch_store(const Energy& e, const Scalar& length, const Scalar& value, Projection strategy,
                                   const BatchOutput<Scalar>& out, std::size_t i, Eigenvalues eigenvalues) {
  using RowMajor = Eigen::Matrix<Scalar, Dofs, Dofs, Eigen::RowMajor>;
  VecN<Scalar, Dofs> g = VecN<Scalar, Dofs>::Zero();  // (zeroed: GCC cannot tell it is stored only if computed)
  MatN<Scalar, Dofs> H, P;
  VecN<Scalar, FrameDofs> lambda = VecN<Scalar, FrameDofs>::Zero();
  int real = FrameDofs;
  // the requests as local flags, so that the compiler sees each output stored only if computed
  const bool want_g = out.gradient != nullptr, want_l = out.eigenvalues != nullptr;
  const bool want_h = out.hessian != nullptr || (out.projected != nullptr && strategy == Projection::none);
  const bool want_p = out.projected != nullptr && strategy != Projection::none;
  bool finite = is_finite(length) && is_finite(value);
  if (want_g) finite = batch_finite(g = energy_gradient(e)) && finite;
  if (want_h) finite = batch_finite(H = energy_hessian(e)) && finite;
  if (want_p) finite = batch_finite(P = projected_hessian(e, strategy)) && finite;
  if (want_l) {
    real = eigenvalues(e, lambda);
    finite = batch_finite(lambda.head(real)) && finite;
  }
  if (!finite) return Status::overflow;
  const auto d = static_cast<std::size_t>(Dofs);
  if (out.length) out.length[i] = length;
  if (out.value) out.value[i] = value;
  if (want_g) Eigen::Map<VecN<Scalar, Dofs>>(out.gradient + i * d) = g;
  if (want_h && out.hessian) Eigen::Map<RowMajor>(out.hessian + i * d * d) = H;
  if (want_h && out.projected) Eigen::Map<RowMajor>(out.projected + i * d * d) = H;
  if (want_p) Eigen::Map<RowMajor>(out.projected + i * d * d) = P;
  if (want_l) {
    for (int j = real; j < FrameDofs; ++j) lambda[j] = std::numeric_limits<Scalar>::quiet_NaN();
    Eigen::Map<VecN<Scalar, FrameDofs>>(out.eigenvalues + i * static_cast<std::size_t>(FrameDofs)) = lambda;
  }
  return Status::ok;
}

/// Row `i` of `evaluate_batch` by the single-pair functions.
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE void batch_row(const Scalar* x, std::size_t i, const Length& length, const Penalty& penalty,
                               Projection strategy, const BatchOutput<Scalar>& out) {
  constexpr int D = Pair::dofs, F = Pair::frame_dofs;
  const auto eigenvalues = [](const auto& e, VecN<Scalar, Pair::frame_dofs>& v) {
    v = energy_eigensystem(e).values;
    return Pair::frame_dofs;
  };
  const VecN<Scalar, D> xi = Eigen::Map<const VecN<Scalar, D>>(x + i * static_cast<std::size_t>(D));
  typename Pair::template Energy<Scalar> e;
  Status s = pair_energy<Pair>(xi, length, penalty, e);
  if (s == Status::ok) s = batch_store<D, F>(e, e.length, e.psi.value, strategy, out, i, eigenvalues);
  if (s != Status::ok) batch_nan_row(out, i, D, F);
  if (out.status) out.status[i] = s;
}

/// Whether `evaluate_batch` evaluates these pairs a packet at a time (`evaluate_lanes`): the plane
/// kinds, a scalar Eigen vectorises, valid penalty parameters, and outputs the lanes compute (not
/// the eigenvalues; a projection only by `analytic`, `abs` or `none`).
template <class Pair, class Scalar, class Penalty>
PCE_HOST_DEVICE bool batch_vectorises(const Penalty& penalty, Projection strategy, const BatchOutput<Scalar>& out) {
  if constexpr (!(std::is_same_v<Pair, VertexFace> || std::is_same_v<Pair, EdgeEdge>) ||
                !std::is_floating_point_v<Scalar> || lanes_width<Scalar> < 2) {
    (void)penalty, (void)strategy, (void)out;
    return false;
  } else {
    if (!penalty_valid(penalty) || out.eigenvalues) return false;
    return !out.projected || strategy == Projection::analytic || strategy == Projection::abs ||
           strategy == Projection::none;
  }
}

/// Index of entry (r, c) of a symmetric 12×12 matrix in `UpperTriangle12`.
PCE_HOST_DEVICE constexpr int upper_index(int r, int c) {
  const int lo = r < c ? r : c, hi = r < c ? c : r;
  return lo * 12 - lo * (lo - 1) / 2 + (hi - lo);
}

/// Pairs `first … first + W − 1` (W = `lanes_width<Scalar>`), one per lane of `Lanes<Scalar>`,
/// through the same arithmetic as the single-pair functions (`frame_arithmetic`, the penalty
/// lane by lane, `plane_exact_hessian`, `plane_filtered_hessian`). A lane is finished here only
/// if its single-pair evaluation would take the same path and end `ok`: valid coordinates,
/// edges of moderate size (no rescaling), a frame with one Gram–Schmidt pass, ψ defined and
/// finite, finite outputs. Returns the bits of the lanes it left for the scalar path.
/// Without `Basis` (no Hessian asked for) the frame's orthonormal basis is not built.
template <class Pair, bool Basis, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE unsigned evaluate_lanes(const Scalar* x, std::size_t first, const Length& length,
                                        const Penalty& penalty, Projection strategy, const BatchOutput<Scalar>& out) {
  using T = Lanes<Scalar>;
  constexpr int W = lanes_width<Scalar>;
  constexpr unsigned every = (1u << W) - 1u;
  const T zero(Scalar(0));
  T X[12];
  for (int c = 0; c < 12; ++c) X[c] = T::gather(x + first * 12 + c, 12);
  const T lim(Constants<Scalar>::max_coordinate());
  auto ok = abs(X[0]) <= lim;
  for (int c = 1; c < 12; ++c) ok = ok && (abs(X[c]) <= lim);
  const Mat34<Scalar> D = Pair::template edge_map<Scalar>();
  T e[3][3];
  edge_vectors(
      D, [&X](int c) { return X[c]; }, e);
  T big = zero;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 3; ++i) big = select(abs(e[k][i]) > big, abs(e[k][i]), big);
  const Scalar bound = unit_scale_bound<Scalar>();
  ok = ok && (big > zero) && (big >= T(Scalar(1) / bound)) && (big <= T(bound));
  FrameArithmetic<T> a;
  frame_arithmetic<Basis>(e, a);
  PlaneValues<T> f;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j) f.P[k][j] = frame_coefficient(D, k, j, a.alpha, a.beta, a.gamma);
  ok = ok && (a.mm > zero) && (a.a00 > zero) && (a.nb2 > zero) && (a.nb2 > T(Scalar(0.25)) * a.mm);
  T z = ((zero * a.alpha + zero * a.beta) + (zero * a.gamma + zero * a.ls));
  for (int j = 0; j < 4; ++j) z = z + zero * f.P[2][j];
  ok = ok && (z == zero);
  if constexpr (Basis) {
    for (int i = 0; i < 3; ++i) f.n[i] = a.n[i], f.t[0][i] = a.t0[i], f.t[1][i] = a.t1[i];
    f.a[0] = a.a0s;
    f.a[1] = a.a1s;
  }
  f.l = a.ls;
  T sigma;
  if constexpr (is_signed_length<Length>())
    sigma = T(length.side == Side::negative ? Scalar(-1) : Scalar(1));
  else
    sigma = select(f.l < zero, T(Scalar(-1)), T(Scalar(1)));
  const T L = sigma * f.l;
  // ψ lane by lane, by the penalty's own scalar code (user penalties need nothing more)
  unsigned bits = mask_bits(ok);
  alignas(64) Scalar Ls[W], pv[W], p1[W], p2[W];
  L.store(Ls);
  for (int i = 0; i < W; ++i) {
    pv[i] = p1[i] = p2[i] = Scalar(0);
    PenaltyDerivatives<Scalar> psi;
    if (!((bits >> i) & 1u) || evaluate_penalty(penalty, Ls[i], psi) != Status::ok) {
      bits &= ~(1u << i);
      continue;
    }
    pv[i] = psi.value, p1[i] = psi.first, p2[i] = psi.second;
  }
  if (bits == 0) return every;
  const T value = T::gather(pv, 1), psi2 = T::gather(p2, 1);
  const T c1 = sigma * T::gather(p1, 1);
  // Finiteness: a sum of the entries is finite whenever each is; a finite sum that overflows
  // only sends the lane to the scalar path, which decides. Four independent sums.
  const auto add_all = [&zero](const T* v, int n) {
    T s0 = zero, s1 = zero, s2 = zero, s3 = zero;
    int i = 0;
    for (; i + 4 <= n; i += 4) s0 = s0 + v[i], s1 = s1 + v[i + 1], s2 = s2 + v[i + 2], s3 = s3 + v[i + 3];
    for (; i < n; ++i) s0 = s0 + v[i];
    return (s0 + s1) + (s2 + s3);
  };
  T fin = L + value;
  T g[12];
  if (out.gradient) {
    for (int j = 0; j < 4; ++j) {
      const T cj = c1 * f.P[2][j];
      for (int i = 0; i < 3; ++i) g[3 * j + i] = cj * a.m_hat[i];
    }
    fin = fin + add_all(g, 12);
  }
  const bool want_h = Basis && (out.hessian || (out.projected && strategy == Projection::none));
  const bool want_p = Basis && out.projected && strategy != Projection::none;
  UpperTriangle12<T> H, Pr;
  if (want_h) {
    plane_exact_hessian(f, c1, psi2, H);
    fin = fin + add_all(H.h, 78);
  }
  if (want_p) {
    plane_filtered_hessian(f, c1, psi2, strategy == Projection::abs, T(family_big_t<Scalar>()), Pr);
    fin = fin + add_all(Pr.h, 78);
  }
  bits &= mask_bits(zero * fin == zero);
  // Every lane's rows are written; those of the lanes left to the scalar path are written
  // again there (outputs or NaN), so nothing of them stays.
  const auto lane_rows = [&](Scalar* dst, std::size_t width, std::size_t offset, Scalar*(&ptr)[W]) {
    for (int p = 0; p < W; ++p) ptr[p] = dst + (first + static_cast<std::size_t>(p)) * width + offset;
  };
  const auto matrix_rows = [&](const UpperTriangle12<T>& tri, Scalar* dst) {
    if constexpr (12 % W == 0) {
      for (int r = 0; r < 12; ++r)
        for (int c0 = 0; c0 < 12; c0 += W) {
          T v[W];
          for (int k = 0; k < W; ++k) v[k] = tri.h[upper_index(r, c0 + k)];
          Scalar* ptr[W];
          lane_rows(dst, 144, static_cast<std::size_t>(12) * static_cast<std::size_t>(r) + static_cast<std::size_t>(c0),
                    ptr);
          store_transposed(v, ptr);
        }
    } else {
      alignas(64) Scalar tmp[78][W];
      for (int idx = 0; idx < 78; ++idx) tri.h[idx].store(tmp[idx]);
      for (int p = 0; p < W; ++p) {
        Scalar* row = dst + (first + static_cast<std::size_t>(p)) * 144;
        int idx = 0;
        for (int r = 0; r < 12; ++r)
          for (int c = r; c < 12; ++c, ++idx) row[12 * r + c] = row[12 * c + r] = tmp[idx][p];
      }
    }
  };
  if (out.length) L.store(out.length + first);
  if (out.value) value.store(out.value + first);
  if (out.gradient) {
    if constexpr (12 % W == 0) {
      for (int c0 = 0; c0 < 12; c0 += W) {
        Scalar* ptr[W];
        lane_rows(out.gradient, 12, static_cast<std::size_t>(c0), ptr);
        store_transposed(g + c0, ptr);
      }
    } else {
      alignas(64) Scalar tmp[12][W];
      for (int c = 0; c < 12; ++c) g[c].store(tmp[c]);
      for (int p = 0; p < W; ++p)
        for (int c = 0; c < 12; ++c) out.gradient[(first + static_cast<std::size_t>(p)) * 12 + c] = tmp[c][p];
    }
  }
  if constexpr (Basis) {
    if (out.hessian) matrix_rows(H, out.hessian);
    if (out.projected) matrix_rows(want_p ? Pr : H, out.projected);
  }
  if (out.status)
    for (int p = 0; p < W; ++p) out.status[first + static_cast<std::size_t>(p)] = Status::ok;
  return every & ~bits;
}

}  // namespace detail

/// `evaluate<Pair>` for `count` pairs, pair i's D = `Pair::dofs` coordinates starting at
/// x + i·D, into `out`: row i of each requested output holds pair i's, or NaN where its
/// status is not ok. A pair whose requested outputs are not all finite (ψ included) is
/// `overflow`.
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE void evaluate_batch(const Scalar* x, std::size_t count, const Length& length, const Penalty& penalty,
                                    Projection strategy, const BatchOutput<Scalar>& out) {
  std::size_t i = 0;
  if constexpr (std::is_same_v<Pair, VertexFace> || std::is_same_v<Pair, EdgeEdge>) {
    constexpr std::size_t W = static_cast<std::size_t>(lanes_width<Scalar>);
    if (detail::batch_vectorises<Pair>(penalty, strategy, out))
      for (; i + W <= count; i += W) {
        const unsigned left = (out.hessian || out.projected)
                                  ? detail::evaluate_lanes<Pair, true>(x, i, length, penalty, strategy, out)
                                  : detail::evaluate_lanes<Pair, false>(x, i, length, penalty, strategy, out);
        for (std::size_t k = 0; k < W; ++k)
          if ((left >> k) & 1u) detail::batch_row<Pair>(x, i + k, length, penalty, strategy, out);
      }
  }
  for (; i < count; ++i) detail::batch_row<Pair>(x, i, length, penalty, strategy, out);
}

/// Row `i` of `evaluate_batch<Pair>`, alone: what one thread of a device kernel evaluates
/// (`docs/cuda.md`). On the host the same bits as the row of `evaluate_batch`; in device code
/// `Projection::numerical` runs as `exact` (`with_projection`).
template <class Pair, class Scalar, class Length, class Penalty>
PCE_HOST_DEVICE void evaluate_batch_row(const Scalar* x, std::size_t i, const Length& length, const Penalty& penalty,
                                        Projection strategy, const BatchOutput<Scalar>& out) {
  detail::batch_row<Pair>(x, i, length, penalty, strategy, out);
}

/// `closest_feature_energy<Pair>` (`VertexFace` or `EdgeEdge`; unsigned length) for `count`
/// pairs, pair i's 12 coordinates starting at x + 12i, into `out`, with the kind evaluated
/// in `out.feature` and the eigenvalues of that kind (9, 6 or 3, then NaN) in
/// `out.eigenvalues` (width 9).
template <class Pair, class Scalar, class Penalty>
PCE_HOST_DEVICE void closest_feature_batch(const Scalar* x, std::size_t count, const Penalty& penalty,
                                           Projection strategy, const BatchOutput<Scalar>& out) {
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
