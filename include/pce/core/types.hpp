// SPDX-License-Identifier: MIT
/// @file
/// Fixed-size Eigen aliases, the status every per-pair call returns, and the per-scalar
/// constants (one traits struct, as Sophus' `Constants<Scalar>`).
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <type_traits>

/// Forces a small per-pair function into its caller, so that a pair's values stay in registers
/// from the frame to the outputs (an out-of-line call stores them to the stack and reloads
/// them as wider packets, which stalls store forwarding).
#if defined(__GNUC__) || defined(__clang__)
#define PCE_ALWAYS_INLINE __attribute__((always_inline)) inline
#elif defined(_MSC_VER)
#define PCE_ALWAYS_INLINE __forceinline
#else
#define PCE_ALWAYS_INLINE inline
#endif

/// Marks a function callable from both host and device code when the including file is
/// compiled by a CUDA compiler (`__host__ __device__`), and nothing otherwise: every per-pair
/// function of the core carries it (`docs/cuda.md` lists the few that stay host-only).
#if defined(__CUDACC__)
#define PCE_HOST_DEVICE __host__ __device__
#else
#define PCE_HOST_DEVICE
#endif

namespace pce {

/// Column vector of N scalars.
template <class Scalar, int N> using VecN = Eigen::Matrix<Scalar, N, 1>;
/// N×N matrix.
template <class Scalar, int N> using MatN = Eigen::Matrix<Scalar, N, N>;
/// A point or direction in 3-space.
template <class Scalar> using Vec3 = VecN<Scalar, 3>;
/// The coordinates of a point-point pair (p, q).
template <class Scalar> using Vec6 = VecN<Scalar, 6>;
/// The coordinates of a point-edge pair (p, e0, e1), or a 9-dimensional frame vector.
template <class Scalar> using Vec9 = VecN<Scalar, 9>;
/// The coordinates of a vertex-face (p, t0, t1, t2) or edge-edge (ea0, ea1, eb0, eb1) pair.
template <class Scalar> using Vec12 = VecN<Scalar, 12>;
/// 3×3 matrix (a frame-space block).
template <class Scalar> using Mat3 = MatN<Scalar, 3>;
/// 6×6 matrix: a point-point Hessian, or a point-edge frame-space matrix.
template <class Scalar> using Mat6 = MatN<Scalar, 6>;
/// 9×9 matrix: a point-edge Hessian, or a plane kind's frame-space matrix.
template <class Scalar> using Mat9 = MatN<Scalar, 9>;
/// 12×12 matrix: the Hessian of a vertex-face or edge-edge pair.
template <class Scalar> using Mat12 = MatN<Scalar, 12>;
/// Coefficients of the reduced frame in the four vertices: `c_k = sum_j P(k, j) x_j`.
template <class Scalar> using Mat34 = Eigen::Matrix<Scalar, 3, 4>;

/// Outcome of a per-pair evaluation. On anything but `ok` nothing is written to the
/// caller's outputs.
enum class Status {
  ok = 0,
  invalid_input,  ///< a coordinate or parameter is NaN, Inf or beyond `Constants::max_coordinate`
  degenerate,     ///< the frame does not exist: zero-area triangle, parallel or zero-length edges;
                  ///< for the point kinds, distance exactly 0 (its direction is undefined)
  out_of_domain,  ///< the penalty is undefined at this length (log barrier at L <= 0)
  overflow,       ///< a result is not representable in the scalar type
};

/// Machine-readable name of a status, as `pce-probe` prints it.
PCE_HOST_DEVICE inline const char* to_string(Status s) {
  switch (s) {
    case Status::ok:
      return "ok";
    case Status::invalid_input:
      return "invalid_input";
    case Status::degenerate:
      return "degenerate";
    case Status::out_of_domain:
      return "out_of_domain";
    case Status::overflow:
      return "overflow";
  }
  return "unknown";
}

/// Per-scalar constants. Specialise for a custom scalar if the defaults do not fit.
template <class Scalar> struct Constants {
  /// Unit roundoff-sized epsilon of the type.
  PCE_HOST_DEVICE static Scalar epsilon() { return std::numeric_limits<Scalar>::epsilon(); }
  /// Largest accepted |coordinate|: inputs beyond it are `invalid_input` ("absurd
  /// magnitude"). Chosen so that squared differences of coordinates stay finite.
  PCE_HOST_DEVICE static Scalar max_coordinate() {
    using std::sqrt;
    return sqrt((std::numeric_limits<Scalar>::max)()) / Scalar(16);
  }
};

namespace detail {

template <class Scalar> PCE_HOST_DEVICE inline bool is_finite(const Scalar& v) {
  using std::isfinite;
  return isfinite(v);
}

/// Whether every argument is finite: for the built-in floating types one sum `Σ 0·vᵢ`, which is
/// 0 exactly when each vᵢ is finite (0·±∞ and 0·NaN are NaN), without a branch per value.
template <class Scalar, class... More>
PCE_HOST_DEVICE PCE_ALWAYS_INLINE bool finite_all(const Scalar& v, const More&... more) {
  if constexpr (std::is_floating_point_v<Scalar>)
    return ((Scalar(0) * v) + ... + (Scalar(0) * Scalar(more))) == Scalar(0);
  else
    return (is_finite(v) && ... && is_finite(Scalar(more)));
}

/// `invalid_input` unless every coordinate is finite and within `max_coordinate`.
template <class Derived> PCE_HOST_DEVICE PCE_ALWAYS_INLINE bool coordinates_valid(const Eigen::MatrixBase<Derived>& x) {
  using std::abs;
  using Scalar = typename Derived::Scalar;
  const Scalar lim = Constants<Scalar>::max_coordinate();
  if constexpr (std::is_floating_point_v<Scalar> && Derived::SizeAtCompileTime != Eigen::Dynamic) {
    // two vectorised reductions: Σ 0·xᵢ = 0 iff all are finite, then the largest |xᵢ|
    const auto a = x.derived().array();
    return (a * Scalar(0)).sum() == Scalar(0) && a.abs().maxCoeff() <= lim;
  } else {
    bool ok = true;  // |x| <= lim is false for NaN and ±∞
    for (Eigen::Index i = 0; i < x.size(); ++i) ok = ok & bool(abs(x[i]) <= lim);
    return ok;
  }
}

template <class Derived> PCE_HOST_DEVICE inline bool all_finite(const Eigen::MatrixBase<Derived>& m) {
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      if (!is_finite(m(i, j))) return false;
  return true;
}

/// +1 for v >= 0 (including +0 and -0), -1 otherwise: the side convention at l = 0.
template <class Scalar> PCE_HOST_DEVICE inline Scalar sign_nonneg(const Scalar& v) {
  return v < Scalar(0) ? Scalar(-1) : Scalar(1);
}

}  // namespace detail
}  // namespace pce
