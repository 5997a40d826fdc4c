// SPDX-License-Identifier: MIT
/// @file
/// Exact rescaling by a power of two, so that products and squares of the rescaled values
/// neither overflow nor underflow (`docs/stability.md`): the frames rescale their edges by
/// it, the small eigensolvers (`core/jacobi.hpp`) their matrices.
#pragma once

#include <pce/core/types.hpp>

#include <cmath>
#include <limits>

namespace pce::detail {

/// Exact rescaling by the power of two `2^-ex` nearest a reference size `big > 0`
/// (`big = mant·2^ex`, mant in [0.5, 1)): no rounding, and no overflow in products of
/// the rescaled values. One multiplication by a power of two is exact unless the result
/// is subnormal; only for exponents near the ends of the range do we fall back to `ldexp`
/// per coefficient.
template <class Scalar> struct PowerOfTwoScale {
  int ex = 0;
  bool moderate;
  Scalar factor;
  explicit PowerOfTwoScale(const Scalar& big) {
    using std::frexp;
    using std::ldexp;
    frexp(big, &ex);
    moderate =
        ex > std::numeric_limits<Scalar>::min_exponent + 64 && ex < std::numeric_limits<Scalar>::max_exponent - 64;
    factor = moderate ? Scalar(ldexp(Scalar(1), -ex)) : Scalar(1);
  }
  /// v · 2^-ex, for any fixed-size Eigen vector or matrix
  template <class Derived> typename Derived::PlainObject down(const Eigen::MatrixBase<Derived>& v) const {
    using std::ldexp;
    if (moderate) return v * factor;
    const int e = ex;
    return v.unaryExpr([e](const Scalar& c) { return Scalar(ldexp(c, -e)); });
  }
  /// s · 2^-ex
  Scalar down(const Scalar& s) const {
    using std::ldexp;
    return moderate ? Scalar(s * factor) : Scalar(ldexp(s, -ex));
  }
  /// v · 2^ex
  Scalar up(const Scalar& v) const {
    using std::ldexp;
    return moderate ? Scalar(v * ldexp(Scalar(1), ex)) : Scalar(ldexp(v, ex));
  }
};

}  // namespace pce::detail
