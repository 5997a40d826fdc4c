// SPDX-License-Identifier: MIT
/// @file
/// What the parts of the fuzz body share (`fuzz_pair.cpp`: what does not depend on the
/// scalar type; `fuzz_plane.hpp`: decoding, the plane kinds, the generic projection checks;
/// `fuzz_points.hpp`: the point kinds; `fuzz_closest.hpp`: closest-feature evaluation):
/// the byte reader, the case being run and its reproducer, the coordinate decoders, the
/// penalty decoders and the checks on a set of projected Hessians. See docs/fuzzing.md.
#pragma once

#include "fuzz_eigensolvers.hpp"
#include "fuzz_pair.hpp"

#include <pce/pce.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cfenv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

namespace pce_fuzz {

// ---------------------------------------------------------------------------------------
// Byte reader: every read past the end yields zeros, so every byte string is a valid case.

class Bytes {
 public:
  Bytes(const uint8_t* d, size_t n) : d_(d), n_(n) {}
  uint8_t u8() { return i_ < n_ ? d_[i_++] : uint8_t(0); }
  // Little-endian; each read is its own statement (the order of operands is unspecified).
  uint16_t u16() {
    const uint16_t lo = u8();
    return uint16_t(lo | (uint16_t(u8()) << 8));
  }
  uint32_t u32() {
    const uint32_t lo = u16();
    return lo | (uint32_t(u16()) << 16);
  }
  uint64_t u64() {
    const uint64_t lo = u32();
    return lo | (uint64_t(u32()) << 32);
  }
  /// In [0, 1].
  double unit() { return u16() / 65535.0; }
  /// In [-1, 1].
  double sym() { return 2.0 * unit() - 1.0; }
  /// A small integer in [lo, hi].
  int range(int lo, int hi) { return lo + int(u8() % unsigned(hi - lo + 1)); }

 private:
  const uint8_t* d_;
  size_t n_;
  size_t i_ = 0;
};

// ---------------------------------------------------------------------------------------
// The case being run, for the reproducer printed on failure.

struct CaseInfo {
  const char* scalar = "";
  const char* pair = "";
  const char* length = "";
  const char* penalty = "";
  const char* projection = "";
  double k = 0, eps = 0, delta = 0, dhat = 0;
  long double x[12] = {};
  int nx = 12;  ///< coordinates: 12, 9 (point_edge) or 6 (point_point)
  int coord_mode = 0;
  std::string ops;
  bool failed = false;  ///< this input already reported (keep-going mode: one report per input)
};

extern CaseInfo g_case;

#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
void fail(const char* fmt, ...);

#define PCE_FUZZ_CHECK(cond, ...)               \
  do {                                          \
    if (!(cond)) ::pce_fuzz::fail(__VA_ARGS__); \
  } while (0)

/// Escapes an object's address, so that an opaque call (fetestexcept) may read it: the
/// computations stored into it cannot be moved past that call.
extern void* volatile g_escape;

// ---------------------------------------------------------------------------------------
// Scalars.

template <class S> int scalar_index() {
  return std::is_same<S, float>::value ? 0 : std::is_same<S, double>::value ? 1 : 2;
}
template <class S> const char* scalar_name() {
  return std::is_same<S, float>::value ? "float" : std::is_same<S, double>::value ? "double" : "long double";
}

/// Relative tolerance of the PSD and symmetry checks: 1024 ε of the scalar (1.2e-4 in
/// float, 2.3e-13 in double, 1.1e-16 in long double). Rounding alone stays below ~16 ε
/// (measured, docs/fuzzing.md); a wrong sign, a missing clamp or an unstable reassembly is
/// orders of magnitude above it.
template <class S> long double psd_tolerance() { return 1024.0L * std::numeric_limits<S>::epsilon(); }

template <class S, std::enable_if_t<std::is_floating_point<S>::value, int> = 0> bool finite(const S& v) {
  return std::isfinite(v);
}
template <class Derived> bool finite(const Eigen::MatrixBase<Derived>& m) {
  for (Eigen::Index j = 0; j < m.cols(); ++j)
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      if (!std::isfinite(m(i, j))) return false;
  return true;
}

/// Equal entries, NaN equal to NaN (the same computation gives the same NaN positions).
template <class A, class B> bool same_values(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a.array() == b.array() || (a.array().isNaN() && b.array().isNaN())).all();
}

/// The object representation of `t`, to check that a failing call wrote nothing.
template <class T> class Snapshot {
 public:
  explicit Snapshot(const T& t) { std::memcpy(bytes_, static_cast<const void*>(&t), sizeof(T)); }
  bool unchanged(const T& t) const { return std::memcmp(bytes_, static_cast<const void*>(&t), sizeof(T)) == 0; }

 private:
  unsigned char bytes_[sizeof(T)];
};

/// A value no call computes by accident.
template <class S> S sentinel() { return S(-7777.125); }

template <class S> void fill(pce::PenaltyDerivatives<S>& p) { p.value = p.first = p.second = sentinel<S>(); }
template <class S> void fill(pce::Frame<S>& f) {
  f.P.setConstant(sentinel<S>());
  f.n.setConstant(sentinel<S>());
  f.t0.setConstant(sentinel<S>());
  f.t1.setConstant(sentinel<S>());
  f.l = f.a0 = f.a1 = f.alpha = f.beta = f.gamma = sentinel<S>();
}
template <class S> void fill(pce::PairEnergy<S>& e) {
  fill(e.frame);
  e.sigma = e.length = sentinel<S>();
  fill(e.psi);
}
template <class S, int N, int F> void fill(pce::PairResult<S, N, F>& r) {
  r.length = r.value = sentinel<S>();
  r.gradient.setConstant(sentinel<S>());
  r.hessian.setConstant(sentinel<S>());
  r.projected_hessian.setConstant(sentinel<S>());
  r.eigen.values.setConstant(sentinel<S>());
  r.eigen.vectors.setConstant(sentinel<S>());
}

// ---------------------------------------------------------------------------------------
// Coordinates.

template <class S> S pow10(int k) {
  using std::pow;
  return S(pow(S(10), S(k)));
}

template <class S> S raw_bits(Bytes& b) {
  S v;
  if constexpr (std::is_same<S, float>::value) {
    const uint32_t u = b.u32();
    std::memcpy(&v, &u, sizeof v);
  } else if constexpr (std::is_same<S, double>::value) {
    const uint64_t u = b.u64();
    std::memcpy(&v, &u, sizeof v);
  } else {
    // x87 80-bit extended: 64-bit significand (explicit integer bit) and sign+exponent.
    // Non-canonical encodings (unnormals, pseudo-denormals) are included on purpose.
    unsigned char buf[sizeof(S)] = {};
    const uint64_t m = b.u64();
    const uint16_t e = b.u16();
    std::memcpy(buf, &m, 8);
    std::memcpy(buf + 8, &e, 2);
    std::memcpy(&v, buf, sizeof v);
  }
  return v;
}

/// NaN, ±Inf, subnormals, the extremes, max_coordinate and its neighbours, raw bits, ...
template <class S> S special(Bytes& b) {
  using L = std::numeric_limits<S>;
  using std::ldexp;
  using std::nextafter;
  const S mc = pce::Constants<S>::max_coordinate();
  switch (b.u8() % 28) {
    case 0:
      return S(0);
    case 1:
      return -S(0);
    case 2:
      return S(1);
    case 3:
      return S(-1);
    case 4:
      return S(0.5);
    case 5:
      return S(b.range(-8, 8));
    case 6:
      return L::quiet_NaN();
    case 7:
      return -L::quiet_NaN();
    case 8:
      return L::signaling_NaN();
    case 9:
      return L::infinity();
    case 10:
      return -L::infinity();
    case 11:
      return (L::max)();
    case 12:
      return L::lowest();
    case 13:
      return (L::min)();
    case 14:
      return L::denorm_min();
    case 15:
      return -L::denorm_min();
    case 16:
      return L::epsilon();
    case 17:
      return mc;
    case 18:
      return -mc;
    case 19:
      return nextafter(mc, L::infinity());
    case 20:
      return nextafter(mc, S(0));
    case 21:
      return -nextafter(mc, L::infinity());
    case 22:
    case 23:
      return raw_bits<S>(b);
    case 24: {  // any power of two from deep subnormal to the top, with a significand
      const int lo = L::min_exponent - L::digits, hi = L::max_exponent;
      const int e = lo + int(b.u16() % unsigned(hi - lo + 1));
      return ldexp(S(b.sym()), e);
    }
    case 25: {
      const S m = S(b.sym());
      return m * pow10<S>(b.range(-30, 30));
    }
    case 26:
      return S(1e6) + S(b.sym());
    default:
      return S(b.sym());
  }
}

/// 0, ±10^-k, or a few ulps: how far from exact degeneracy.
template <class S> S severity(Bytes& b) {
  const int m = b.u8() % 8;
  const S sign = (b.u8() & 1) ? S(-1) : S(1);
  switch (m) {
    case 0:
      return S(0);
    case 1:
      return sign * std::numeric_limits<S>::epsilon() * S(b.range(1, 4));
    case 2:
      return sign * std::numeric_limits<S>::denorm_min();
    default:
      return sign * pow10<S>(-b.range(0, 20));
  }
}

/// Three values in [-1, 1], read in order (the order of function arguments is unspecified).
template <class S> pce::Vec3<S> sym3(Bytes& b) {
  pce::Vec3<S> v;
  for (int c = 0; c < 3; ++c) v[c] = S(b.sym());
  return v;
}

template <class S> pce::Vec3<S> axis(Bytes& b) {
  pce::Vec3<S> a = pce::Vec3<S>::Zero();
  const int m = b.u8() % 4;
  if (m < 3) {
    a[m] = S(1);
  } else {
    a = sym3<S>(b);
    if (!(a.norm() > S(0.01))) a = pce::Vec3<S>(S(0), S(0), S(1));
    a.normalize();
  }
  return a;
}

/// severity × axis: a displacement of size 0, 10^-k or a few ulps.
template <class S> pce::Vec3<S> offset(Bytes& b) {
  const S sev = severity<S>(b);
  return sev * axis<S>(b);
}

/// Which geometric template `decode_x` starts from.
enum class Layout { vertex_face, edge_edge, point_edge, point_point };

/// Points of the layout's kind (4, 4, 3 or 2 used) decoded from a template, small
/// integers, uniform or special values, then edited by up to four operations
/// (docs/fuzzing.md, "Coordinates"). Defined in fuzz_plane.hpp.
template <class S> std::array<pce::Vec3<S>, 4> decode_points(Bytes& b, Layout layout);

/// The first N/3 decoded points as one coordinate vector, recorded in `g_case`.
template <class S, int N> pce::VecN<S, N> decode_x(Bytes& b, Layout layout) {
  const std::array<pce::Vec3<S>, 4> p = decode_points<S>(b, layout);
  pce::VecN<S, N> x;
  for (int j = 0; j < N / 3; ++j) x.template segment<3>(3 * j) = p[j];
  g_case.nx = N;
  for (int i = 0; i < N; ++i) g_case.x[i] = static_cast<long double>(x[i]);
  return x;
}

// ---------------------------------------------------------------------------------------
// Penalties (doubles, as the penalty types store them).

/// One decoded penalty: `type` 0 quadratic, 1 cubic, 2 log barrier (the member of that
/// type is set); `activation` is ε or d̂.
struct DecodedPenalty {
  int type = 0;
  pce::QuadraticPenalty quadratic{1.0, 1.0};
  pce::CubicPenalty cubic{1.0, 1.0, 1.0};
  pce::LogBarrierPenalty barrier{1.0, 1.0};
  double activation = 0;
};

/// Decodes the parameters of penalty `type` relative to the geometry's length `Lhint`
/// (docs/fuzzing.md) and records them in `g_case`.
DecodedPenalty decode_penalty(Bytes& b, int type, double Lhint);

/// Calls `f` with the decoded penalty object (one instantiation of `f` per penalty type).
template <class F> void with_penalty(const DecodedPenalty& d, F&& f) {
  switch (d.type) {
    case 0:
      f(d.quadratic);
      break;
    case 1:
      f(d.cubic);
      break;
    default:
      f(d.barrier);
      break;
  }
}

// ---------------------------------------------------------------------------------------
// Checks on a set of projected Hessians (every kind, padded to 12×12 in long double).

using LdMat = Eigen::Matrix<long double, 12, 12>;

/// `M` cast exactly to long double, zero-padded to 12×12 (padding adds only zero
/// eigenvalues, so λ_min ≥ −tol·scale holds for the padded matrix iff it holds for `M`).
template <class S, int N> LdMat padded(const pce::MatN<S, N>& M) {
  LdMat out = LdMat::Zero();
  out.template topLeftCorner<N, N>() = M.template cast<long double>();
  return out;
}

constexpr int kNumStrategies = 6;
/// Indexed as `pce::Projection`: none, analytic, numerical, gauss_newton, abs, exact.
constexpr pce::Projection kStrategies[kNumStrategies] = {pce::Projection::none,      pce::Projection::analytic,
                                                         pce::Projection::numerical, pce::Projection::gauss_newton,
                                                         pce::Projection::abs,       pce::Projection::exact};

/// The exact Hessian (P[0]) and every projection of one `ok` energy, in long double.
struct ProjectionSet {
  LdMat P[kNumStrategies];
  bool fin[kNumStrategies] = {};  ///< P[s] finite in the scalar type
  bool uf[kNumStrategies] = {};   ///< an underflow that matters happened before or in P[s]
  bool underflow = false;         ///< underflow in the frame, ψ or the exact Hessian
  /// Orthonormality defect δ of the frame's basis (max |b_i·b_j − δ_ij|), set by the caller:
  /// `exact` equals `numerical` only for an orthonormal basis.
  long double basis_defect = 0;
};

/// max |b_i·b_j − δ_ij| of three vectors (computed in long double).
template <class S> long double basis_defect(const pce::Vec3<S>& a, const pce::Vec3<S>& b, const pce::Vec3<S>& c) {
  const Eigen::Matrix<long double, 3, 3> M = (Eigen::Matrix<long double, 3, 3>() << a.template cast<long double>(),
                                              b.template cast<long double>(), c.template cast<long double>())
                                                 .finished();
  return (M.transpose() * M - Eigen::Matrix<long double, 3, 3>::Identity()).cwiseAbs().maxCoeff();
}

/// Computes every projection of `e` (any energy type with `pce::projected_hessian`), with
/// the underflow bookkeeping of docs/fuzzing.md: `underflow` is whether FE_UNDERFLOW was
/// raised while the frame, ψ and the exact Hessian were computed (the caller cleared the
/// flags before `pair_energy` and computed `H` since); inside `numerical` and `exact`, whose
/// errors are relative to ‖H‖, an underflow counts only when max|H_ij| < min()/ε.
template <class E, class S, int N> void compute_projections(const E& e, const pce::MatN<S, N>& H, bool underflow,
                                                            pce::MatN<S, N> (&P)[kNumStrategies], ProjectionSet& ps) {
  const S hmax = H.cwiseAbs().maxCoeff();
  const bool tiny_h = !(hmax >= (std::numeric_limits<S>::min)() / std::numeric_limits<S>::epsilon());
  ps.underflow = underflow;
  for (int s = 0; s < kNumStrategies; ++s) {
    std::feclearexcept(FE_ALL_EXCEPT);
    P[s] = pce::projected_hessian(e, kStrategies[s]);
    g_escape = &P[s];
    const bool here = std::fetestexcept(FE_UNDERFLOW) != 0;
    const bool relative_to_h = kStrategies[s] == pce::Projection::numerical || kStrategies[s] == pce::Projection::exact;
    ps.uf[s] = underflow || (here && (!relative_to_h || tiny_h));
    ps.fin[s] = finite(P[s]);
    if (ps.fin[s]) ps.P[s] = padded<S, N>(P[s]);
  }
}

/// Symmetry of the exact Hessian and of every projection, PSD-ness of every strategy but
/// `none`, the orderings abs ⪰ analytic ⪰ gauss_newton and exact ⪰ H, and exact ≈ numerical
/// (docs/fuzzing.md, invariants 14–17). Defined in fuzz_plane.hpp.
template <class S> void check_projection_set(const ProjectionSet& ps);

// ---------------------------------------------------------------------------------------
// Helpers of the point kinds and closest-feature evaluation.

// Sentinels for the point kinds' and closest-feature outputs (frames before energies,
// since ADL does not look into pce_fuzz).

template <class S> void fill(pce::PointEdgeFrame<S>& f) {
  f.P.setConstant(sentinel<S>());
  f.t.setConstant(sentinel<S>());
  f.u.setConstant(sentinel<S>());
  f.n.setConstant(sentinel<S>());
  f.d = f.a = f.beta = sentinel<S>();
}
template <class S> void fill(pce::PointPointFrame<S>& f) {
  f.u.setConstant(sentinel<S>());
  f.v.setConstant(sentinel<S>());
  f.w.setConstant(sentinel<S>());
  f.d = sentinel<S>();
}
template <class S> void fill(pce::PointEdgeEnergy<S>& e) {
  fill(e.frame);
  e.length = sentinel<S>();
  fill(e.psi);
}
template <class S> void fill(pce::PointPointEnergy<S>& e) {
  fill(e.frame);
  e.length = sentinel<S>();
  fill(e.psi);
}
template <class S> void fill(pce::ClosestFeatureEnergy<S>& e) {
  e.feature = static_cast<pce::Feature>(77);
  e.points = {-7, -7, -7};
  fill(e.plane);
  fill(e.edge);
  fill(e.point);
  e.length = sentinel<S>();
  fill(e.psi);
}

// ---------------------------------------------------------------------------------------
// Small helpers in long double.

using LdVec3 = Eigen::Matrix<long double, 3, 1>;

template <class S, int N> LdVec3 point_ld(const pce::VecN<S, N>& x, int j) {
  return x.template segment<3>(3 * j).template cast<long double>();
}

template <class S, int N> bool same_point(const pce::VecN<S, N>& x, int i, int j) {
  return same_values(x.template segment<3>(3 * i), x.template segment<3>(3 * j));
}

template <class S> long double eps_ld() { return static_cast<long double>(std::numeric_limits<S>::epsilon()); }

/// The exponent k of the power of two 2^k at or above `big` (0 for big = 0): scaling by 2^-k
/// (with ldexp, since 2^-k itself need not be representable) is exact and keeps long double
/// norms of the scaled vectors from overflowing or underflowing (the references below are
/// computed in units of the configuration's size).
inline int unit_exponent(long double big) {
  int ex = 0;
  if (big > 0) std::frexp(big, &ex);
  return ex;
}
inline long double down(long double v, int ex) { return std::ldexp(v, -ex); }
inline LdVec3 down(const LdVec3& v, int ex) {
  return v.unaryExpr([ex](long double c) { return std::ldexp(c, -ex); });
}

template <class S, int N> bool coordinates_invalid(const pce::VecN<S, N>& x, bool& nonfinite) {
  bool absurd = false;
  nonfinite = false;
  for (int i = 0; i < N; ++i) {
    using std::abs;
    if (!std::isfinite(x[i]))
      nonfinite = true;
    else if (abs(x[i]) > pce::Constants<S>::max_coordinate())
      absurd = true;
  }
  return nonfinite || absurd;
}

/// The `N/3` points `idx` of `x` as one vector (what closest-feature evaluation evaluates).
template <int N, class S> pce::VecN<S, N> gather(const pce::Vec12<S>& x, const std::array<int, 3>& idx) {
  pce::VecN<S, N> y;
  for (int j = 0; j < N / 3; ++j) y.template segment<3>(3 * j) = x.template segment<3>(3 * idx[j]);
  return y;
}
template <int N, class S> pce::Vec12<S> scatter(const pce::VecN<S, N>& g, const std::array<int, 3>& idx) {
  pce::Vec12<S> out = pce::Vec12<S>::Zero();
  for (int j = 0; j < N / 3; ++j) out.template segment<3>(3 * idx[j]) = g.template segment<3>(3 * j);
  return out;
}
template <int N, class S> pce::Mat12<S> scatter(const pce::MatN<S, N>& H, const std::array<int, 3>& idx) {
  pce::Mat12<S> out = pce::Mat12<S>::Zero();
  for (int i = 0; i < N / 3; ++i)
    for (int j = 0; j < N / 3; ++j)
      out.template block<3, 3>(3 * idx[i], 3 * idx[j]) = H.template block<3, 3>(3 * i, 3 * j);
  return out;
}

/// ψ ≥ 0, ψ′ ≤ 0, ψ″ ≥ 0 for the built-in penalties (k ≥ 0); all zero when inactive.
template <class S>
void check_psi(const pce::PenaltyDerivatives<S>& psi, const S& L, double activation, const char* who) {
  PCE_FUZZ_CHECK(psi.value >= S(0) && psi.first <= S(0) && psi.second >= S(0),
                 "%s: penalty signs: psi = %.17Lg, psi' = %.17Lg, psi'' = %.17Lg", who, (long double)psi.value,
                 (long double)psi.first, (long double)psi.second);
  if (!(L < S(activation)))
    PCE_FUZZ_CHECK(psi.value == S(0) && psi.first == S(0) && psi.second == S(0),
                   "%s: inactive penalty (L >= activation length) but psi, psi' or psi'' nonzero", who);
}

/// A `SignedLength` request is `invalid_input` and writes nothing (the point kinds have no side).
template <class S, class E>
void check_signed_rejected(pce::Status s, const Snapshot<E>& snap, const E& out, const char* who) {
  ++pce_fuzz_stats().signed_rejected;
  PCE_FUZZ_CHECK(s == pce::Status::invalid_input, "%s with a SignedLength: status %s, expected invalid_input", who,
                 pce::to_string(s));
  PCE_FUZZ_CHECK(snap.unchanged(out), "%s with a SignedLength: the output was written", who);
}

/// The point kinds and closest-feature evaluation (fuzz_points.hpp): decodes the rest of
/// the case and checks it. `kind` is a `PceFuzzKind` other than the two plane kinds.
template <class S> void run_new_kind(Bytes& b, int kind);

/// Closest-feature evaluation of a vertex-face (`vf`) or edge-edge candidate
/// (fuzz_closest.hpp), after `run_new_kind` decoded the side of the SignedLength request.
template <class S> void run_closest(Bytes& b, pce::Side side, bool vf);

/// The body for one input of scalar type `S` (`pce_fuzz_one` decoded the scalar): decodes
/// the kind and runs it (fuzz_plane.hpp). Compiled once per scalar type, with every template
/// of the body for that scalar, in a translation unit of its own (`fuzz_float.cpp`,
/// `fuzz_double.cpp`, `fuzz_long_double.cpp`): g++ 12 compiles the three scalar types
/// together several times slower than one after the other, and apart they build in parallel.
template <class S> void run_scalar(Bytes& b);
extern template void run_scalar<float>(Bytes&);
extern template void run_scalar<double>(Bytes&);
extern template void run_scalar<long double>(Bytes&);

}  // namespace pce_fuzz
