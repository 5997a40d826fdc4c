// SPDX-License-Identifier: MIT
/// @file
/// Exact rescaling by a power of two, so that products and squares of the rescaled values
/// neither overflow nor underflow (`docs/stability.md`): the frames rescale their edges by
/// it, the small eigensolvers (`core/jacobi.hpp`) their matrices.
#pragma once

#include <pce/core/types.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace pce::detail {

/// Exact rescaling by the power of two `2^-ex` nearest a reference size `big > 0`
/// (`big = mant·2^ex`, mant in [0.5, 1)): no rounding, and no overflow in products of
/// the rescaled values. One multiplication by a power of two is exact unless the result
/// is subnormal; only for exponents near the ends of the range do we fall back to `ldexp`
/// per coefficient.
/// The exponent `ex` of `big = mant·2^ex` (mant in [0.5, 1)) read from the bits of a normal
/// `float` or `double`, and the exact powers of two `2^-ex` and `2^ex`, when `ex` is moderate
/// (more than 64 from either end of the exponent range); false otherwise (subnormal, ∞, NaN,
/// or another type), and the caller uses `frexp`. The same as `frexp`/`ldexp`, without the
/// library calls.
template <class Scalar> PCE_HOST_DEVICE bool moderate_exponent(const Scalar& big, int& ex, Scalar& down, Scalar& up) {
  using Limits = std::numeric_limits<Scalar>;
  if constexpr (std::is_same_v<Scalar, double> || std::is_same_v<Scalar, float>) {
    using Bits = std::conditional_t<std::is_same_v<Scalar, double>, std::uint64_t, std::uint32_t>;
    constexpr int mant = Limits::digits - 1;        // stored mantissa bits: 52, 23
    constexpr int bias = Limits::max_exponent - 1;  // 1023, 127
    Bits b;
    std::memcpy(&b, &big, sizeof b);
    const int biased = static_cast<int>((b >> mant) & ((Bits(1) << (sizeof(Scalar) * 8 - 1 - mant)) - 1));
    ex = biased - bias + 1;
    if (!(ex > Limits::min_exponent + 64 && ex < Limits::max_exponent - 64)) return false;
    const Bits db = static_cast<Bits>(bias - ex) << mant, ub = static_cast<Bits>(bias + ex) << mant;
    std::memcpy(&down, &db, sizeof down);
    std::memcpy(&up, &ub, sizeof up);
    return true;
  } else {
    (void)big, (void)ex, (void)down, (void)up;
    return false;
  }
}

template <class Scalar> struct PowerOfTwoScale {
  int ex = 0;
  bool moderate;
  Scalar factor;   ///< 2^-ex when moderate, else 1
  Scalar inverse;  ///< 2^ex when moderate, else 1
  PCE_HOST_DEVICE explicit PowerOfTwoScale(const Scalar& big) {
    using std::frexp;
    using std::ldexp;
    moderate = moderate_exponent(big, ex, factor, inverse);
    if (moderate) return;
    frexp(big, &ex);
    moderate =
        ex > std::numeric_limits<Scalar>::min_exponent + 64 && ex < std::numeric_limits<Scalar>::max_exponent - 64;
    factor = moderate ? Scalar(ldexp(Scalar(1), -ex)) : Scalar(1);
    inverse = moderate ? Scalar(ldexp(Scalar(1), ex)) : Scalar(1);
  }
  /// v · 2^-ex, for any fixed-size Eigen vector or matrix
  template <class Derived>
  PCE_HOST_DEVICE typename Derived::PlainObject down(const Eigen::MatrixBase<Derived>& v) const {
    using std::ldexp;
    if (moderate) return v * factor;
    const int e = ex;
    return v.unaryExpr([e](const Scalar& c) { return Scalar(ldexp(c, -e)); });
  }
  /// s · 2^-ex
  PCE_HOST_DEVICE Scalar down(const Scalar& s) const {
    using std::ldexp;
    return moderate ? Scalar(s * factor) : Scalar(ldexp(s, -ex));
  }
  /// v · 2^ex
  PCE_HOST_DEVICE Scalar up(const Scalar& v) const {
    using std::ldexp;
    return moderate ? Scalar(v * inverse) : Scalar(ldexp(v, ex));
  }
};

}  // namespace pce::detail
