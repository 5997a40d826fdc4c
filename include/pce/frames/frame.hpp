// SPDX-License-Identifier: MIT
/// @file
/// The reduced frame of a pair (Shi & Kim 2023, Sec. 4.1; supplement Sec. 1): three
/// mutually orthogonal edges `c = (e0, e1⊥, e2⊥)` built from the pair's edge vectors
/// `e0, e1, e2` by one Gram–Schmidt sweep,
///
///     e1⊥ = e1 − α e0,   e2⊥ = e2 − β e0 − γ e1,
///
/// and the linear map `c = J x` (α, β, γ held fixed) that every derivative is pulled back
/// through. `J = P ⊗ I3` with a 3×4 coefficient matrix `P`, so `Jᵀ M J` is a weighted sum
/// of 3×3 blocks (see `pullback`). The pair kinds live in `vertex_face.hpp` and
/// `edge_edge.hpp`; both reduce to this one struct.
#pragma once

#include <pce/core/scaling.hpp>
#include <pce/core/types.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <type_traits>

namespace pce {

/// Reduced frame of one pair. All vectors are in world coordinates.
template <class Scalar> struct Frame {
  /// Frame coefficients: `e0 = Σ P(0,j) x_j`, `e1⊥ = Σ P(1,j) x_j`, `e2⊥ = Σ P(2,j) x_j`.
  Mat34<Scalar> P;
  Vec3<Scalar> n;  ///< n̂ = (e0 × e1)/|e0 × e1|, the unit normal; e2⊥ = l n̂ (orthonormalised against ê0)
  /// m/|m| (m = e0 × e1) as computed, before n̂'s Gram–Schmidt pass: ∂l/∂e2⊥, the direction of
  /// the gradient, and the normal l, β and γ are computed with (it differs from n̂ by rounding).
  Vec3<Scalar> m_hat;
  Vec3<Scalar> t0;  ///< ê0 = e0/|e0|
  Vec3<Scalar> t1;  ///< ê1 = n̂ × ê0 = e1⊥/|e1⊥|; (ê0, ê1, n̂) is right-handed
  Scalar l;         ///< signed length l = e2·n̂ (paper Eq. 9 / supplement Eq. 9)
  Scalar a0;        ///< |e0|
  Scalar a1;        ///< |e1⊥| = |e0 × e1|/|e0|
  Scalar alpha;     ///< α = e0·e1/|e0|²
  Scalar beta;      ///< β = ((e2 × e1)·m)/|m|², m = e0 × e1
  Scalar gamma;     ///< γ = ((e0 × e2)·m)/|m|²
};

/// Frame-space Hessian (9×9 in the coordinates c = (e0, e1⊥, e2⊥)) stored as its only
/// possibly nonzero 3×3 blocks; the (0,1) block of every Hessian in this library is zero
/// (supplement Eq. 37), as are its transposes.
template <class Scalar> struct FrameBlocks {
  ///@{
  Mat3<Scalar> h00, h11, h22;  ///< diagonal blocks
  ///@}
  ///@{
  Mat3<Scalar> h02, h12;  ///< off-diagonal blocks; (2,0) and (2,1) are their transposes
  ///@}

  /// All five blocks zero.
  PCE_HOST_DEVICE static FrameBlocks Zero() {
    FrameBlocks b;
    b.h00.setZero();
    b.h11.setZero();
    b.h22.setZero();
    b.h02.setZero();
    b.h12.setZero();
    return b;
  }
  /// The dense 9×9 matrix.
  PCE_HOST_DEVICE Mat9<Scalar> dense() const {
    Mat9<Scalar> m = Mat9<Scalar>::Zero();
    m.template block<3, 3>(0, 0) = h00;
    m.template block<3, 3>(3, 3) = h11;
    m.template block<3, 3>(6, 6) = h22;
    m.template block<3, 3>(0, 6) = h02;
    m.template block<3, 3>(6, 0) = h02.transpose();
    m.template block<3, 3>(3, 6) = h12;
    m.template block<3, 3>(6, 3) = h12.transpose();
    return m;
  }
};

/// The frame Jacobian `J = ∂c/∂x` (9×12) with α, β, γ held fixed: `J = P ⊗ I3`.
template <class Scalar> PCE_HOST_DEVICE Eigen::Matrix<Scalar, 9, 12> frame_jacobian(const Frame<Scalar>& f) {
  Eigen::Matrix<Scalar, 9, 12> J = Eigen::Matrix<Scalar, 9, 12>::Zero();
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j) J.template block<3, 3>(3 * k, 3 * j).diagonal().setConstant(f.P(k, j));
  return J;
}

namespace detail {
/// `r ⊗ d`: point `j` gets `r[j] d` (a frame direction `d` in slot k pulled back to the
/// coordinates is `P.row(k) ⊗ d`, i.e. `Jᵀ` of that slot vector).
template <class Scalar, class Row>
PCE_HOST_DEVICE VecN<Scalar, 3 * Row::SizeAtCompileTime> kron(const Row& r, const Vec3<Scalar>& d) {
  constexpr int n = Row::SizeAtCompileTime;
  VecN<Scalar, 3 * n> v;
  for (int j = 0; j < n; ++j) v.template segment<3>(3 * j) = r[j] * d;
  return v;
}

}  // namespace detail

/// Pull a frame-space gradient `gc` (9) back to the 12 coordinates: `Jᵀ gc`.
template <class Scalar> PCE_HOST_DEVICE Vec12<Scalar> pullback(const Frame<Scalar>& f, const Vec9<Scalar>& gc) {
  Vec12<Scalar> g;
  for (int j = 0; j < 4; ++j)
    g.template segment<3>(3 * j) = f.P(0, j) * gc.template segment<3>(0) + f.P(1, j) * gc.template segment<3>(3) +
                                   f.P(2, j) * gc.template segment<3>(6);
  return g;
}

/// Pull a frame-space Hessian back to the 12 coordinates: `H = Jᵀ Hc J`, block (i, j):
/// `Σ_ab P(a,i) P(b,j) Hc(a,b)` over the five nonzero blocks. Symmetric by construction.
template <class Scalar> PCE_HOST_DEVICE Mat12<Scalar> pullback(const Frame<Scalar>& f, const FrameBlocks<Scalar>& hc) {
  Mat12<Scalar> H;
  for (int i = 0; i < 4; ++i) {
    const Scalar p0i = f.P(0, i), p1i = f.P(1, i), p2i = f.P(2, i);
    for (int j = i; j < 4; ++j) {
      const Scalar p0j = f.P(0, j), p1j = f.P(1, j), p2j = f.P(2, j);
      Mat3<Scalar> b = (p0i * p0j) * hc.h00 + (p1i * p1j) * hc.h11 + (p2i * p2j) * hc.h22 + (p0i * p2j) * hc.h02 +
                       (p2i * p0j) * hc.h02.transpose() + (p1i * p2j) * hc.h12 + (p2i * p1j) * hc.h12.transpose();
      H.template block<3, 3>(3 * i, 3 * j) = b;
      if (j != i) H.template block<3, 3>(3 * j, 3 * i) = b.transpose();
    }
  }
  return H;
}

namespace detail {

/// `a × b` and `a·b` on three plain values (`T` is a scalar or `Lanes<Scalar>`), in one
/// fixed order of operations, so that a pair evaluated alone and in a batch give the same bits.
template <class T> PCE_HOST_DEVICE PCE_ALWAYS_INLINE void cross3(const T* a, const T* b, T* c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}
template <class T> PCE_HOST_DEVICE PCE_ALWAYS_INLINE T dot3(const T* a, const T* b) {
  return (a[0] * b[0] + a[1] * b[1]) + a[2] * b[2];
}

/// The frame's quantities as plain values of `T` (a scalar, or `Lanes<Scalar>` for one pair per
/// lane), in the coordinates rescaled by `PowerOfTwoScale`: what `frame_arithmetic` computes.
template <class T> struct FrameArithmetic {
  T m_hat[3];  ///< m/|m|
  T n[3];      ///< n̂ after one Gram–Schmidt pass against ê0 (see `make_frame`)
  T t0[3];     ///< ê0
  T t1[3];     ///< n̂ × ê0
  T ls;        ///< the signed length, rescaled
  T a0s, a1s;  ///< |e0| and |e1⊥|, rescaled
  T mm, mn;    ///< |m|² and |m| (m = e0 × e1), rescaled (0: degenerate)
  T a00;       ///< |e0|², rescaled (0: degenerate)
  T nb2;       ///< |m − (m·ê0)ê0|², the squared norm n̂ had before its normalisation, times |m|²
  T alpha, beta, gamma;
};

/// The arithmetic of the frame from the rescaled edge vectors `E[k]`, without a branch
/// (`docs/stability.md`): β and γ from `m = e0 × e1` rather than the Gram determinant,
/// `l = e2⊥·n̂` rather than `e2·n̂`. Written for latency, since a pair is a chain of dependent
/// operations: 1/|m|² and √|m|² are taken side by side (1/|m| = √|m|²·(1/|m|²)), β, γ and α
/// use the squared norms, and n̂ is orthogonalised against e0 before it is normalised. The
/// callers check the results (`make_frame`); divisions by a zero |m| or |e0| give non-finite
/// values they refuse. With `Basis = false` the orthonormal basis (`n`, `t0`, `t1`) and the
/// lengths `a0s`, `a1s` are left unset and their square roots untaken (what `value_gradient`
/// needs); everything else is the same arithmetic, bit for bit.
template <bool Basis = true, class T>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE void frame_arithmetic(const T (&E)[3][3], FrameArithmetic<T>& f) {
  using std::sqrt;
  T m[3], c21[3], c02[3];
  cross3(E[0], E[1], m);
  cross3(E[2], E[1], c21);
  cross3(E[0], E[2], c02);
  const T mm = dot3(m, m), a00 = dot3(E[0], E[0]);
  f.mm = mm;
  f.a00 = a00;
  const T rmm = T(1) / mm, ra00 = T(1) / a00;
  f.mn = sqrt(mm);
  const T rmn = f.mn * rmm;
  f.beta = dot3(c21, m) * rmm;
  f.gamma = dot3(c02, m) * rmm;
  f.alpha = dot3(E[0], E[1]) * ra00;
  T e2p[3];
  for (int i = 0; i < 3; ++i) e2p[i] = (E[2][i] - f.beta * E[0][i]) - f.gamma * E[1][i];
  f.ls = dot3(e2p, m) * rmn;
  for (int i = 0; i < 3; ++i) f.m_hat[i] = m[i] * rmn;
  // n̂ ∝ m − (m·e0/|e0|²) e0, of norm nn relative to |m|
  const T me = dot3(m, E[0]) * ra00;
  T nb[3];
  for (int i = 0; i < 3; ++i) nb[i] = m[i] - me * E[0][i];
  const T nb2 = dot3(nb, nb);
  f.nb2 = nb2;
  if constexpr (Basis) {
    f.a0s = sqrt(a00);
    const T ra0 = f.a0s * ra00;
    for (int i = 0; i < 3; ++i) f.t0[i] = E[0][i] * ra0;
    const T rnb = sqrt(nb2) * (T(1) / nb2);  // 1/|nb|, the square root beside the division
    for (int i = 0; i < 3; ++i) f.n[i] = nb[i] * rnb;
    cross3(f.n, f.t0, f.t1);
    f.a1s = f.mn * ra0;
  }
}

/// Row `k` of the frame coefficients `P` from the edge map `D` (entries 0, ±1): `P.row(0) = D.row(0)`,
/// `P.row(1) = D.row(1) − α D.row(0)`, `P.row(2) = D.row(2) − β D.row(0) − γ D.row(1)`.
template <class T, class Dmat>
PCE_HOST_DEVICE T frame_coefficient(const Dmat& D, int k, int j, const T& alpha, const T& beta, const T& gamma) {
  using S = typename Dmat::Scalar;
  const T d0 = T(S(D(0, j))), d1 = T(S(D(1, j))), d2 = T(S(D(2, j)));
  if (k == 0) return d0;
  if (k == 1) return d1 - alpha * d0;
  return (d2 - beta * d0) - gamma * d1;
}

/// Whether a pair whose largest edge coordinate is `big` needs no rescaling: `big` within
/// 2^±(max_exponent/8) (2^±128 in double, 2^±16 in float). Then the frame's products of up to
/// four edge coordinates, and those with the third edge (at most `2 max_coordinate`), neither
/// overflow nor underflow for any triangle or edge pair less degenerate than sin θ ≈ 2^-250
/// (double), 2^-30 (float); rescaling would not change their bits. Skipping it takes a
/// multiplication and the exponent's extraction off every pair's critical path.
template <class Scalar> PCE_HOST_DEVICE PCE_ALWAYS_INLINE Scalar unit_scale_bound() {
  if constexpr (std::is_same_v<Scalar, double>)
    return 0x1p128;
  else if constexpr (std::is_same_v<Scalar, float>)
    return 0x1p16f;
  else {
    using std::ldexp;
    return ldexp(Scalar(1), std::numeric_limits<Scalar>::max_exponent / 8);
  }
}
template <class Scalar> PCE_HOST_DEVICE PCE_ALWAYS_INLINE bool unit_scale(const Scalar& big) {
  const Scalar hi = unit_scale_bound<Scalar>();
  return big >= Scalar(1) / hi && big <= hi;
}

/// What the gradient of a plane kind needs of its frame (`value_gradient`): l, ∂l/∂e2⊥ and the
/// third row of `P`.
template <class Scalar> struct GradientFrame {
  Scalar m_hat[3];  ///< as `Frame::m_hat`
  Scalar p2[4];     ///< `Frame::P.row(2)`
  Scalar l;         ///< as `Frame::l`
};

/// Build the frame from the pair's edge vectors `e[k]` and the constant map `D` (rows: e0, e1,
/// e2 as combinations of the four vertices): an exact power-of-two rescaling unless the edges
/// are of moderate size (`unit_scale`), then `frame_arithmetic`, then the checks. Returns
/// `degenerate` when `e0 × e1` vanishes (in the rescaled coordinates), `overflow` when the
/// third edge is beyond the scalar's range relative to the primitive; `f` is written only on
/// `ok`. `Out` is `Frame` or `GradientFrame`: both run the same arithmetic and checks, so they
/// agree on the status and on what both hold, bit for bit. A `GradientFrame` skips the basis
/// (`frame_arithmetic<false>`), and builds the full frame only for the rare pair whose normal
/// needs a second Gram–Schmidt pass, whose outcome decides the status.
template <class Scalar, class Out>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE Status make_frame(const Scalar (&e)[3][3], const Mat34<Scalar>& D, Out& f) {
  using std::abs;
  using std::sqrt;
  constexpr bool full = std::is_same_v<Out, Frame<Scalar>>;
  Scalar big = Scalar(0);
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 3; ++i) big = abs(e[k][i]) > big ? Scalar(abs(e[k][i])) : big;
  if (!(big > Scalar(0))) return Status::degenerate;
  FrameArithmetic<Scalar> a;
  const bool unit = unit_scale(big);
  const PowerOfTwoScale<Scalar> sc(unit ? Scalar(1) : big);
  if (unit) {
    frame_arithmetic<full>(e, a);
  } else {
    Scalar E[3][3];
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) E[k][i] = sc.down(e[k][i]);
    frame_arithmetic<full>(E, a);
  }
  // (|m|² > 0 and |e0|² > 0, i.e. |m| > 0 and |e0| > 0, without waiting for the square roots)
  if (!(a.mm > Scalar(0)) || !(a.a00 > Scalar(0))) return Status::degenerate;
  const Scalar l = unit ? a.ls : sc.up(a.ls);
  // The third edge is rescaled by the primitive's scale; a vertex (or edge) farther away
  // than the scalar's range allows relative to a tiny primitive overflows here (found by
  // pce-fuzz: a 1e-33 triangle with its vertex at 1e6, in float), and so can the sum
  // beta + gamma in the third row of P (found next: a 1e-22 triangle, vertex at 3.6e16).
  // (The first two rows of P are finite whenever α is: |α| ≤ |e1|/|e0| is far below the range.)
  if (!finite_all(a.alpha, a.beta, a.gamma, l)) return Status::overflow;
  Scalar p2[4];
  for (int j = 0; j < 4; ++j) p2[j] = frame_coefficient(D, 2, j, a.alpha, a.beta, a.gamma);
  if (!finite_all(p2[0], p2[1], p2[2], p2[3])) return Status::overflow;

  // The stored basis (t̂0, t̂1, n̂) must be orthonormal to rounding: the Hessians and the
  // exact projection use it as an orthonormal basis. n̂ = m/|m| is orthogonal to t̂0 only to
  // ε/sin θ (the rounding of m), O(1) off for angles below ε (found by pce-fuzz: exact and
  // numerical then differ by up to 100 %). Gram-Schmidt against t̂0 (in `frame_arithmetic`),
  // and a second time if the first lost over half the norm ("twice is enough", Parlett, The
  // Symmetric Eigenvalue Problem, Sec. 6.9); it moves n̂ by no more than its own error, and
  // α, β, γ, l above keep the plain m/|m|.
  if (!(a.nb2 > Scalar(0))) return Status::degenerate;  // m ∥ e0: only for m of pure rounding
  if constexpr (!full) {
    // The second Gram–Schmidt pass changes n̂ and ê1 only, but it decides whether the pair is
    // degenerate, and it needs the basis the lean arithmetic did not build: for nearly
    // parallel edges only, the full frame is built for its status.
    if (!(a.nb2 > Scalar(0.25) * a.mm)) {
      Frame<Scalar> full_frame;
      const Status s = make_frame<Scalar>(e, D, full_frame);
      if (s != Status::ok) return s;
    }
    f.l = l;
    for (int i = 0; i < 3; ++i) f.m_hat[i] = a.m_hat[i];
    for (int j = 0; j < 4; ++j) f.p2[j] = p2[j];
    return Status::ok;
  } else {
    const Vec3<Scalar> t0(a.t0[0], a.t0[1], a.t0[2]);
    Vec3<Scalar> nb(a.n[0], a.n[1], a.n[2]);
    bool second = false;
    if (!(a.nb2 > Scalar(0.25) * a.mm)) {
      nb -= nb.dot(t0) * t0;
      const Scalar nn = sqrt(nb.squaredNorm());
      if (!(nn > Scalar(0))) return Status::degenerate;
      nb /= nn;
      second = true;
    }
    f.l = l;
    f.m_hat = Vec3<Scalar>(a.m_hat[0], a.m_hat[1], a.m_hat[2]);
    f.alpha = a.alpha;
    f.beta = a.beta;
    f.gamma = a.gamma;
    f.n = nb;
    f.t0 = t0;
    f.t1 = second ? Vec3<Scalar>(nb.cross(t0)) : Vec3<Scalar>(a.t1[0], a.t1[1], a.t1[2]);
    f.a0 = unit ? a.a0s : sc.up(a.a0s);
    f.a1 = unit ? a.a1s : sc.up(a.a1s);
    for (int j = 0; j < 4; ++j) {
      f.P(0, j) = frame_coefficient(D, 0, j, a.alpha, a.beta, a.gamma);
      f.P(1, j) = frame_coefficient(D, 1, j, a.alpha, a.beta, a.gamma);
      f.P(2, j) = p2[j];
    }
    return Status::ok;
  }
}

/// The edge vectors `e[k] = x_head(k) − x_tail(k)` of the rows of `D` (entries 0, ±1), from the
/// coordinates `coordinate(c)`, c = 0 … 11 (scalars, or `Lanes` of several pairs).
template <class Scalar, class Coordinate, class T>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE void edge_vectors(const Mat34<Scalar>& D, Coordinate coordinate, T (&e)[3][3]) {
  for (int k = 0; k < 3; ++k) {
    int head = 0, tail = 0;
    for (int j = 0; j < 4; ++j) {
      if (D(k, j) > Scalar(0)) head = j;
      if (D(k, j) < Scalar(0)) tail = j;
    }
    for (int i = 0; i < 3; ++i) e[k][i] = coordinate(3 * head + i) - coordinate(3 * tail + i);
  }
}

/// `invalid_input` unless every coordinate is finite and within `max_coordinate`.
template <class Scalar> PCE_HOST_DEVICE Status check_coordinates(const Vec12<Scalar>& x) {
  return coordinates_valid(x) ? Status::ok : Status::invalid_input;
}

/// The frame of a pair whose edge vectors are `e_k = x_head(k) − x_tail(k)`, the rows of `D`
/// (entries 0, ±1: each e_k is one exact-rounding difference of two vertices): checks the
/// coordinates, then `make_frame`. `f` is written only on `ok`.
template <class Scalar, class Out>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE Status frame_from_vertices(const Vec12<Scalar>& x, const Mat34<Scalar>& D, Out& f) {
  const Status s = check_coordinates(x);
  if (s != Status::ok) return s;
  Scalar e[3][3];
  edge_vectors(
      D, [&x](int c) { return x[c]; }, e);
  return make_frame<Scalar>(e, D, f);
}

}  // namespace detail
}  // namespace pce
