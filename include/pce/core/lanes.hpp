// SPDX-License-Identifier: MIT
/// @file
/// A small SIMD layer for evaluating several pairs at once, one pair per lane: `Lanes<Scalar>`
/// holds one Eigen packet (`Eigen::internal::packet_traits<Scalar>::type`: 2 doubles or 4
/// floats with SSE2, 4 and 8 with AVX, 8 and 16 with AVX-512) and gives it the arithmetic of a
/// scalar (`+ − × ÷`, `sqrt`, `abs`, comparisons into a `LaneMask`, `select`). The kernels that
/// batches share with the single-pair functions (`frames/frame.hpp`, `energy/pair_energy.hpp`)
/// are templates on a type `T` that is either `Scalar` or `Lanes<Scalar>`, so both run the same
/// sequence of IEEE operations and give the same bits. The free functions `select`, `any` and
/// `all` have scalar overloads for that purpose. Without vectorisation (`EIGEN_DONT_VECTORIZE`,
/// or a scalar type Eigen has no packet for) `lanes_width<Scalar>` is 1 and the batches run the
/// scalar path.
#pragma once

#include <pce/core/types.hpp>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <type_traits>

// Eigen's packet types carry alignment attributes that GCC drops (and warns about) when they
// are template arguments; Eigen silences the same warning in its own headers.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"
#endif

namespace pce {

/// Lanes per packet for `Scalar`: 1 when Eigen has no packet for it.
template <class Scalar> inline constexpr int lanes_width =
    Eigen::internal::unpacket_traits<typename Eigen::internal::packet_traits<Scalar>::type>::size;

/// The result of comparing two `Lanes`: all bits set in the lanes where it holds.
template <class Scalar> struct LaneMask {
  /// Eigen's packet of `Scalar`.
  using Packet = typename Eigen::internal::packet_traits<Scalar>::type;
  Packet p;  ///< all ones (true) or all zeros (false) per lane
};

/// One packet of `Scalar`s, one per pair, with a scalar's arithmetic.
template <class Scalar> struct Lanes {
  /// Eigen's packet of `Scalar`.
  using Packet = typename Eigen::internal::packet_traits<Scalar>::type;
  static constexpr int size = lanes_width<Scalar>;  ///< number of lanes
  Packet p;                                         ///< the lanes

  Lanes() = default;
  /// Every lane `v`.
  PCE_HOST_DEVICE Lanes(const Scalar& v) : p(Eigen::internal::pset1<Packet>(v)) {}  // NOLINT: implicit like a scalar
  /// From a packet.
  PCE_HOST_DEVICE explicit Lanes(const Packet& q) : p(q) {}
  /// Lane `i` of every one of `size` consecutive records of `stride` scalars: `src[i·stride]`.
  PCE_HOST_DEVICE static Lanes gather(const Scalar* src, std::ptrdiff_t stride) {
    alignas(64) Scalar v[size];
    for (int i = 0; i < size; ++i) v[i] = src[i * stride];
    return Lanes(Eigen::internal::pload<Packet>(v));
  }
  /// The lanes, stored to `dst[0 .. size)`.
  PCE_HOST_DEVICE void store(Scalar* dst) const { Eigen::internal::pstoreu(dst, p); }
  /// Lane `i`.
  PCE_HOST_DEVICE Scalar operator[](int i) const {
    alignas(64) Scalar v[size];
    Eigen::internal::pstore(v, p);
    return v[i];
  }

  ///@{
  /// Lane-wise arithmetic, as the scalar operators (Eigen's `padd`, `psub`, `pmul`, `pdiv`).
  PCE_HOST_DEVICE friend Lanes operator+(const Lanes& a, const Lanes& b) {
    return Lanes(Eigen::internal::padd(a.p, b.p));
  }
  PCE_HOST_DEVICE friend Lanes operator-(const Lanes& a, const Lanes& b) {
    return Lanes(Eigen::internal::psub(a.p, b.p));
  }
  PCE_HOST_DEVICE friend Lanes operator*(const Lanes& a, const Lanes& b) {
    return Lanes(Eigen::internal::pmul(a.p, b.p));
  }
  PCE_HOST_DEVICE friend Lanes operator/(const Lanes& a, const Lanes& b) {
    return Lanes(Eigen::internal::pdiv(a.p, b.p));
  }
  /// −a per lane, the sign bit flipped as the scalar minus does (Eigen's AVX `pnegate` is
  /// `0 − a`, which gives +0 for +0)
  PCE_HOST_DEVICE friend Lanes operator-(const Lanes& a) {
    return Lanes(Eigen::internal::pxor(a.p, Eigen::internal::pset1<Packet>(Scalar(-0.0))));
  }
  PCE_HOST_DEVICE Lanes& operator+=(const Lanes& b) { return *this = *this + b; }
  PCE_HOST_DEVICE Lanes& operator-=(const Lanes& b) { return *this = *this - b; }
  PCE_HOST_DEVICE Lanes& operator*=(const Lanes& b) { return *this = *this * b; }
  PCE_HOST_DEVICE Lanes& operator/=(const Lanes& b) { return *this = *this / b; }
  ///@}
  /// Correctly rounded square root per lane (as `std::sqrt`). Eigen's packet square root is the
  /// hardware's for SSE and AVX doubles; for floats and AVX-512 doubles under `EIGEN_FAST_MATH`
  /// (Eigen's default) it is a reciprocal square-root estimate refined by a Newton step, within
  /// an ulp but not always `std::sqrt`'s result, so those are rooted lane by lane.
  PCE_HOST_DEVICE friend Lanes sqrt(const Lanes& a) {
#if EIGEN_FAST_MATH
    if constexpr (!(std::is_same_v<Scalar, double> && size <= 4)) {
      alignas(64) Scalar v[size];
      Eigen::internal::pstore(v, a.p);
      for (int i = 0; i < size; ++i) v[i] = std::sqrt(v[i]);
      return Lanes(Eigen::internal::pload<Packet>(v));
    }
#endif
    return Lanes(Eigen::internal::psqrt(a.p));
  }
  /// |a| per lane.
  PCE_HOST_DEVICE friend Lanes abs(const Lanes& a) { return Lanes(Eigen::internal::pabs(a.p)); }

  ///@{
  /// Lane-wise comparison into a `LaneMask` (false in a lane where either is NaN, but `!=`).
  PCE_HOST_DEVICE friend LaneMask<Scalar> operator<(const Lanes& a, const Lanes& b) {
    return {Eigen::internal::pcmp_lt(a.p, b.p)};
  }
  PCE_HOST_DEVICE friend LaneMask<Scalar> operator<=(const Lanes& a, const Lanes& b) {
    return {Eigen::internal::pcmp_le(a.p, b.p)};
  }
  PCE_HOST_DEVICE friend LaneMask<Scalar> operator>(const Lanes& a, const Lanes& b) {
    return {Eigen::internal::pcmp_lt(b.p, a.p)};
  }
  PCE_HOST_DEVICE friend LaneMask<Scalar> operator>=(const Lanes& a, const Lanes& b) {
    return {Eigen::internal::pcmp_le(b.p, a.p)};
  }
  PCE_HOST_DEVICE friend LaneMask<Scalar> operator==(const Lanes& a, const Lanes& b) {
    return {Eigen::internal::pcmp_eq(a.p, b.p)};
  }
  PCE_HOST_DEVICE friend LaneMask<Scalar> operator!=(const Lanes& a, const Lanes& b) { return !(a == b); }
  ///@}
};

///@{
/// Lane-wise not, and, or.
template <class Scalar> PCE_HOST_DEVICE LaneMask<Scalar> operator!(const LaneMask<Scalar>& m) {
  using P = typename LaneMask<Scalar>::Packet;
  return {Eigen::internal::pandnot(Eigen::internal::ptrue(P()), m.p)};
}
template <class Scalar>
PCE_HOST_DEVICE LaneMask<Scalar> operator&&(const LaneMask<Scalar>& a, const LaneMask<Scalar>& b) {
  return {Eigen::internal::pand(a.p, b.p)};
}
template <class Scalar>
PCE_HOST_DEVICE LaneMask<Scalar> operator||(const LaneMask<Scalar>& a, const LaneMask<Scalar>& b) {
  return {Eigen::internal::por(a.p, b.p)};
}
///@}

/// Per lane: `a` where `m` holds, else `b`.
template <class Scalar>
PCE_HOST_DEVICE Lanes<Scalar> select(const LaneMask<Scalar>& m, const Lanes<Scalar>& a, const Lanes<Scalar>& b) {
  return Lanes<Scalar>(Eigen::internal::pselect(m.p, a.p, b.p));
}
/// The scalar `select`: `m ? a : b`.
template <class Scalar> PCE_HOST_DEVICE Scalar select(bool m, const Scalar& a, const Scalar& b) { return m ? a : b; }

namespace detail {
/// The lanes of a mask as bits, lane i in bit i.
template <class Scalar> PCE_HOST_DEVICE unsigned mask_bits(const LaneMask<Scalar>& m) {
  constexpr int n = lanes_width<Scalar>;
  alignas(64) Scalar v[n];
  Eigen::internal::pstore(v, m.p);
  unsigned bits = 0;
  for (int i = 0; i < n; ++i) {
    unsigned char b[sizeof(Scalar)];
    std::memcpy(b, &v[i], sizeof(Scalar));
    if (b[0] != 0) bits |= 1u << i;  // a true lane has every bit set
  }
  return bits;
}
}  // namespace detail

/// Transposing store: `W = lanes_width<Scalar>` packets `v[k]` (entry k of W pairs, one per
/// lane) written as W rows, `dst[p][k] = lane p of v[k]` (through Eigen's in-register
/// `ptranspose`).
template <class Scalar> PCE_HOST_DEVICE void store_transposed(const Lanes<Scalar>* v, Scalar* const* dst) {
  constexpr int n = lanes_width<Scalar>;
  Eigen::internal::PacketBlock<typename Lanes<Scalar>::Packet, n> block;
  for (int k = 0; k < n; ++k) block.packet[k] = v[k].p;
  Eigen::internal::ptranspose(block);
  for (int p = 0; p < n; ++p) Eigen::internal::pstoreu(dst[p], block.packet[p]);
}

///@{
/// Whether `m` holds in some lane / in every lane.
template <class Scalar> PCE_HOST_DEVICE bool any(const LaneMask<Scalar>& m) { return detail::mask_bits(m) != 0; }
template <class Scalar> PCE_HOST_DEVICE bool all(const LaneMask<Scalar>& m) {
  return detail::mask_bits(m) == (1u << lanes_width<Scalar>)-1u;
}
///@}
///@{
/// The scalar `any` and `all`: `m`.
PCE_HOST_DEVICE inline bool any(bool m) { return m; }
PCE_HOST_DEVICE inline bool all(bool m) { return m; }
///@}

}  // namespace pce

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
