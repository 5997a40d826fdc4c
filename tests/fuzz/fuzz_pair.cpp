// SPDX-License-Identifier: MIT
/// @file
/// The fuzz body of `docs/fuzzing.md`: decode bytes into one per-pair case, run it through
/// `pce::evaluate` and the lower-level per-pair functions, check the invariants.
///
/// Decoding is menu-driven, so that random bytes give interesting cases often: coordinates
/// come from geometric templates (a triangle and a vertex near its plane, two edges near
/// each other), small integers, uniform values or special values (NaN, ±Inf, subnormals,
/// the largest finite values, `max_coordinate` and its neighbours, raw bit patterns), and
/// are then edited by a few operations (duplicate a point, make points collinear or
/// coplanar, make edges nearly parallel by a perturbation 10^-k, scale by 10^k or 2^k,
/// offset by 10^k, rotate, nudge by ulps, plant a special value). Penalty parameters are
/// drawn relative to the decoded geometry's length L (so the penalty is active, just
/// active, at its boundary, or inactive) or from a menu including invalid ones (negative,
/// NaN, ±Inf) and extreme ones (0, subnormal, 1e300, DBL_MAX).
#include "fuzz_pair.hpp"
#include "fuzz_eigensolvers.hpp"

#include <pce/pce.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cfenv>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

PceFuzzConfig& pce_fuzz_config() {
  static PceFuzzConfig c;
  return c;
}

PceFuzzStats& pce_fuzz_stats() {
  static PceFuzzStats s;
  return s;
}

namespace {

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
  int coord_mode = 0;
  std::string ops;
  bool failed = false;  ///< this input already reported (keep-going mode: one report per input)
};

CaseInfo g_case;

void print_reproducer() {
  const CaseInfo& c = g_case;
  std::fprintf(stderr, "  scalar=%s pair=%s length=%s projection=%s\n", c.scalar, c.pair, c.length, c.projection);
  if (std::strcmp(c.penalty, "quadratic") == 0)
    std::fprintf(stderr, "  penalty=QuadraticPenalty{k=%.17g, eps=%.17g}\n", c.k, c.eps);
  else if (std::strcmp(c.penalty, "cubic") == 0)
    std::fprintf(stderr, "  penalty=CubicPenalty{k=%.17g, eps=%.17g, delta=%.17g}\n", c.k, c.eps, c.delta);
  else
    std::fprintf(stderr, "  penalty=LogBarrierPenalty{k=%.17g, dhat=%.17g}\n", c.k, c.dhat);
  const bool ld = std::strcmp(c.scalar, "long double") == 0;
  std::fprintf(stderr, "  x = {");
  for (int i = 0; i < 12; ++i) {
    if (ld)
      std::fprintf(stderr, "%s%.21Lg", i ? ", " : "", c.x[i]);
    else
      std::fprintf(stderr, "%s%.17g", i ? ", " : "", double(c.x[i]));
  }
  std::fprintf(stderr, "}\n  x (hex) = {");
  for (int i = 0; i < 12; ++i) {
    if (ld)
      std::fprintf(stderr, "%s%La", i ? ", " : "", c.x[i]);
    else
      std::fprintf(stderr, "%s%a", i ? ", " : "", double(c.x[i]));
  }
  std::fprintf(stderr, "}\n  decoded from: coordinate mode %d, ops [%s]\n", c.coord_mode, c.ops.c_str());
}

#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
void fail(const char* fmt, ...) {
  PceFuzzStats& st = pce_fuzz_stats();
  const PceFuzzConfig& cfg = pce_fuzz_config();
  if (g_case.failed && !cfg.abort_on_failure) return;  // one report per input
  g_case.failed = true;
  ++st.failures;
  if (cfg.abort_on_failure || st.failures <= static_cast<unsigned long long>(cfg.max_reports)) {
    std::fprintf(stderr, "pce-fuzz: invariant violated: ");
    va_list ap;
    va_start(ap, fmt);
    std::vfprintf(stderr, fmt, ap);
    va_end(ap);
    std::fprintf(stderr, "\n");
    print_reproducer();
    if (cfg.on_failure) cfg.on_failure();
    std::fflush(stderr);
  }
  if (cfg.abort_on_failure) std::abort();
}

#define PCE_FUZZ_CHECK(cond, ...) \
  do {                            \
    if (!(cond)) fail(__VA_ARGS__); \
  } while (0)

// ---------------------------------------------------------------------------------------
// Scalars.

template <class S> int scalar_index() { return std::is_same<S, float>::value ? 0 : std::is_same<S, double>::value ? 1 : 2; }
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

template <class A, class B> bool same_values(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a.array() == b.array()).all();
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

template <class S> void fill(pce::Frame<S>& f) {
  f.P.setConstant(sentinel<S>());
  f.n.setConstant(sentinel<S>());
  f.t0.setConstant(sentinel<S>());
  f.t1.setConstant(sentinel<S>());
  f.l = f.a0 = f.a1 = f.alpha = f.beta = f.gamma = sentinel<S>();
}
template <class S> void fill(pce::PairEnergy<S>& e) {
  fill(e.frame);
  e.sigma = e.length = e.psi.value = e.psi.first = e.psi.second = sentinel<S>();
}
template <class S> void fill(pce::PairResult<S>& r) {
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
    case 0: return S(0);
    case 1: return -S(0);
    case 2: return S(1);
    case 3: return S(-1);
    case 4: return S(0.5);
    case 5: return S(b.range(-8, 8));
    case 6: return L::quiet_NaN();
    case 7: return -L::quiet_NaN();
    case 8: return L::signaling_NaN();
    case 9: return L::infinity();
    case 10: return -L::infinity();
    case 11: return (L::max)();
    case 12: return L::lowest();
    case 13: return (L::min)();
    case 14: return L::denorm_min();
    case 15: return -L::denorm_min();
    case 16: return L::epsilon();
    case 17: return mc;
    case 18: return -mc;
    case 19: return nextafter(mc, L::infinity());
    case 20: return nextafter(mc, S(0));
    case 21: return -nextafter(mc, L::infinity());
    case 22:
    case 23: return raw_bits<S>(b);
    case 24: {  // any power of two from deep subnormal to the top, with a significand
      const int lo = L::min_exponent - L::digits, hi = L::max_exponent;
      const int e = lo + int(b.u16() % unsigned(hi - lo + 1));
      return ldexp(S(b.sym()), e);
    }
    case 25: {
      const S m = S(b.sym());
      return m * pow10<S>(b.range(-30, 30));
    }
    case 26: return S(1e6) + S(b.sym());
    default: return S(b.sym());
  }
}

/// 0, ±10^-k, or a few ulps: how far from exact degeneracy.
template <class S> S severity(Bytes& b) {
  const int m = b.u8() % 8;
  const S sign = (b.u8() & 1) ? S(-1) : S(1);
  switch (m) {
    case 0: return S(0);
    case 1: return sign * std::numeric_limits<S>::epsilon() * S(b.range(1, 4));
    case 2: return sign * std::numeric_limits<S>::denorm_min();
    default: return sign * pow10<S>(-b.range(0, 20));
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

template <class S> pce::Vec12<S> decode_x(Bytes& b, bool edge_edge) {
  using V = pce::Vec3<S>;
  std::array<V, 4> p;
  const int mode = b.u8() % 8;
  g_case.coord_mode = mode;
  switch (mode) {
    case 0:
    case 1:
    case 2: {  // template: a nice pair with one severity knob
      if (!edge_edge) {
        const S d = (b.u8() % 4 == 0) ? S(std::fabs(double(severity<S>(b)))) : S(0.05 + b.unit());
        p[1] = V(0, 0, 0);
        p[2] = V(1, 0, 0);
        p[3] = V(S(b.sym()), d, 0);
        const S h = (b.u8() % 2) ? severity<S>(b) : S(b.sym());
        const S px = S(2 * b.sym());
        p[0] = V(px, S(2 * b.sym()), h);
      } else {
        const S h = (b.u8() % 2) ? severity<S>(b) : S(b.sym());
        const S th = (b.u8() % 4 == 0) ? severity<S>(b) : S(3 * b.sym());
        using std::cos;
        using std::sin;
        p[0] = V(-1, 0, 0);
        p[1] = V(1, 0, 0);
        const S cx = S(b.sym());
        const V c(cx, S(b.sym()), h);
        p[2] = c - V(cos(th), sin(th), 0);
        p[3] = c + V(cos(th), sin(th), 0);
      }
      break;
    }
    case 3:
    case 4:  // small integers: exact coincidences, collinearity and coplanarity
      for (auto& q : p)
        for (int c = 0; c < 3; ++c) q[c] = S(b.range(-2, 2));
      break;
    case 5:
    case 6:  // uniform
      for (auto& q : p) q = sym3<S>(b);
      break;
    default:  // coordinates from the special menu (each with probability 1/2), else uniform
      for (auto& q : p)
        for (int c = 0; c < 3; ++c) q[c] = (b.u8() & 1) ? special<S>(b) : S(b.sym());
      break;
  }
  const int nops = b.u8() % 5;
  g_case.ops.clear();
  for (int o = 0; o < nops; ++o) {
    const int op = b.u8() % 12;
    const int i = b.u8() % 4, j = b.u8() % 4, k = b.u8() % 4;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%d(%d,%d,%d)", o ? " " : "", op, i, j, k);
    g_case.ops += buf;
    switch (op) {
      case 0: p[i] = p[j]; break;  // exact duplicate
      case 1: {                    // on the line through p[j], p[k], then off it by 10^-m
        const S t = (b.u8() % 2) ? S(b.range(-2, 3)) / S(2) : S(b.sym() * 3);
        p[i] = p[j] + t * (p[k] - p[j]);
        if (b.u8() % 2) p[i] += offset<S>(b);
        break;
      }
      case 2: {  // in the plane of p[j], p[k], p[m]
        const int m = b.u8() % 4;
        const S u = S(b.sym() * 2);
        p[i] = p[j] + u * (p[k] - p[j]) + S(b.sym() * 2) * (p[m] - p[j]);
        break;
      }
      case 3: p[i] += offset<S>(b); break;  // perturb by 10^-m
      case 4: {  // nearly parallel: p[i] − p[i^1] ∥ p[j] − p[k], up to 10^-m
        const int i2 = i ^ 1;
        const S u = S(b.sym() * 2);
        p[i] = p[i2] + u * (p[j] - p[k]) + offset<S>(b);
        break;
      }
      case 5: {  // scale: 10^[-8, 8] or 2^[-128, 127]
        const S s = (b.u8() % 2) ? pow10<S>(b.range(-8, 8)) : S(std::ldexp(S(1), int(int8_t(b.u8()))));
        for (auto& q : p) q *= s;
        break;
      }
      case 6: {  // offset by 10^[0, 8] (1e6 often)
        const int e = (b.u8() % 2) ? 6 : b.range(0, 8);
        const V off = pow10<S>(e) * axis<S>(b);
        for (auto& q : p) q += off;
        break;
      }
      case 7: p[i][j % 3] = special<S>(b); break;
      case 8: std::swap(p[i], p[j]); break;
      case 9: {  // rotate: no coordinate stays exact
        const S angle = S(b.sym() * 3.2);
        const Eigen::AngleAxis<S> R(angle, axis<S>(b));
        const pce::Mat3<S> M = R.toRotationMatrix();
        for (auto& q : p) q = M * q;
        break;
      }
      case 10: {  // nudge one coordinate by 1..4 ulps
        using std::nextafter;
        const S to = (b.u8() % 2) ? std::numeric_limits<S>::infinity() : -std::numeric_limits<S>::infinity();
        for (int n = b.range(1, 4); n > 0; --n) p[i][j % 3] = nextafter(p[i][j % 3], to);
        break;
      }
      default:  // all points in the plane z = p[j].z: exactly coplanar
        for (auto& q : p) q[2] = p[j][2];
        break;
    }
  }
  pce::Vec12<S> x;
  x << p[0], p[1], p[2], p[3];
  return x;
}

// ---------------------------------------------------------------------------------------
// Penalty parameters (doubles, as the penalty types store them).

double raw_double(Bytes& b) {
  const uint64_t u = b.u64();
  double v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

double decode_stiffness(Bytes& b) {
  switch (b.u8() % 32) {
    case 0: return 0.0;
    case 1: return -0.0;
    case 2: return 1e3;
    case 3: return 1e-3;
    case 4: return 1e8;
    case 5: return 1e-8;
    case 6: return std::pow(10.0, b.range(-30, 30));
    case 7: return 1e300;
    case 8: return std::numeric_limits<double>::max();
    case 9: return std::numeric_limits<double>::denorm_min();
    case 10: return raw_double(b);
    case 11: return -1.0;                                       // invalid
    case 12: return std::numeric_limits<double>::quiet_NaN();   // invalid
    case 13: return std::numeric_limits<double>::infinity();    // invalid
    case 14: return 4.0 * b.unit();
    default: return 1.0;
  }
}

/// Activation length ε relative to the geometry's L (active, just active, at the boundary,
/// inactive), or from the menu.
double decode_eps(Bytes& b, double L) {
  const double m = std::fabs(L) > 0 ? std::fabs(L) : 1.0;
  switch (b.u8() % 32) {
    case 0: return 0.0;
    case 1: return L;  // exactly at the activation length: inactive
    case 2: return std::nextafter(L, std::numeric_limits<double>::infinity());
    case 3: return L + m * std::pow(10.0, -b.range(0, 16));
    case 4: return L - m * std::pow(10.0, -b.range(0, 16));
    case 5: return 2 * m;
    case 6: return L + m * std::pow(10.0, b.range(0, 8));
    case 7: return -m;
    case 8: return 1.0;
    case 9: return -1.0;
    case 10: return 1e300;
    case 11: return -1e300;
    case 12: return std::numeric_limits<double>::max();
    case 13: {
      const double sign = (b.u8() & 1) ? -1 : 1;
      return sign * std::pow(10.0, b.range(-30, 30));
    }
    case 14: return raw_double(b);
    case 15: return std::numeric_limits<double>::quiet_NaN();   // invalid
    case 16: return std::numeric_limits<double>::infinity();    // invalid
    case 17: return -std::numeric_limits<double>::infinity();   // invalid
    default: return L + m * (0.1 + 2 * b.unit());
  }
}

double decode_delta(Bytes& b, double d) {
  const double m2 = d * d > 0 && std::isfinite(d * d) ? d * d : 1.0;
  switch (b.u8() % 24) {
    case 0: return 0.0;
    case 1: return -0.0;
    case 2: return m2 * std::pow(10.0, -b.range(0, 32));
    case 3: return m2 * std::pow(10.0, b.range(0, 8));
    case 4: return 1e-300;
    case 5: return std::numeric_limits<double>::denorm_min();
    case 6: return 1e300;
    case 7: return std::numeric_limits<double>::max();
    case 8: return raw_double(b);
    case 9: return -1e-3;                                       // invalid
    case 10: return std::numeric_limits<double>::quiet_NaN();   // invalid
    case 11: return std::numeric_limits<double>::infinity();    // invalid
    default: return m2 * 4 * b.unit();
  }
}

double decode_dhat(Bytes& b, double L) {
  const double m = std::fabs(L) > 0 ? std::fabs(L) : 1.0;
  switch (b.u8() % 32) {
    case 0: return 2 * m;
    case 1: return m;  // L = d̂: inactive
    case 2: return std::nextafter(m, std::numeric_limits<double>::infinity());
    case 3: return m * (1 + std::pow(10.0, -b.range(1, 16)));  // L just below d̂
    case 4: return m * std::pow(10.0, b.range(1, 16));         // L ≪ d̂: near the pole
    case 5: return m * 0.5;                                    // inactive
    case 6: return 1.0;
    case 7: return 1e-3;
    case 8: return 1e300;
    case 9: return std::numeric_limits<double>::denorm_min();
    case 10: return std::numeric_limits<double>::max();
    case 11: return raw_double(b);
    case 12: return 0.0;                                        // invalid
    case 13: return -0.0;                                       // invalid
    case 14: return -1.0;                                       // invalid
    case 15: return std::numeric_limits<double>::quiet_NaN();   // invalid
    case 16: return std::numeric_limits<double>::infinity();    // invalid
    default: return m * (1 + 4 * b.unit());
  }
}

// ---------------------------------------------------------------------------------------
// Checks.

long double max_abs(const Eigen::Matrix<long double, 12, 12>& M) { return M.cwiseAbs().maxCoeff(); }

const char* check_name(int c) {
  static const char* names[6] = {"analytic", "numerical", "gauss_newton", "abs", "abs - analytic",
                                 "analytic - gauss_newton"};
  return names[c];
}

/// λ_min(M) ≥ −tol·scale, M symmetric up to tol·scale. `check` indexes `worst_psd`.
/// `underflow`: an intermediate of the library's computation underflowed (IEEE underflow
/// flag), so relative accuracy is not defined there; a violation is then counted, not failed.
template <class S> void check_psd(const Eigen::Matrix<long double, 12, 12>& M, long double scale, int check,
                                  bool underflow) {
  PceFuzzStats& st = pce_fuzz_stats();
  const int si = scalar_index<S>();
  if (!(scale > 0)) return;
  const long double tol = psd_tolerance<S>();
  const long double asym = (M - M.transpose()).cwiseAbs().maxCoeff() / scale;
  if (underflow) ++st.psd_checks_underflow;

  if (asym > tol && underflow) {
    ++st.underflow_excused;
    return;
  }
  if (!underflow && double(asym) > st.worst_asym[si]) st.worst_asym[si] = double(asym);
  PCE_FUZZ_CHECK(asym <= tol, "%s projection not symmetric: max|P - P^T| / scale = %.3Le > %.1Le", check_name(check),
                 asym, tol);
  const pce_fuzz::MinEig e = pce_fuzz::min_eigenvalue(M);
  ++st.psd_checks;
  if (!e.converged) {
    ++st.eig_no_convergence;
    return;
  }
  const long double ratio = e.lambda_min / scale;
  if (ratio < -tol && underflow) {
    ++st.underflow_excused;
    return;
  }
  if (!underflow && double(ratio) < st.worst_psd[si][check]) st.worst_psd[si][check] = double(ratio);
  PCE_FUZZ_CHECK(ratio >= -tol, "%s not PSD: lambda_min = %.6Le, scale %.6Le, ratio %.3Le < -%.1Le", check_name(check),
                 e.lambda_min, scale, ratio, tol);
}

/// Escapes an object's address, so that an opaque call (fetestexcept) may read it: the
/// computations stored into it cannot be moved past that call.
void* volatile g_escape = nullptr;

template <class S> Eigen::Matrix<long double, 12, 12> ld(const pce::Mat12<S>& M) { return M.template cast<long double>(); }

constexpr pce::Projection kStrategies[5] = {pce::Projection::none, pce::Projection::analytic, pce::Projection::numerical,
                                            pce::Projection::gauss_newton, pce::Projection::abs};

/// The lower-level outputs of one `ok` energy (gradient, exact Hessian, eigensystem and
/// every projection) and the invariants on them that involve neither the pair kind, the
/// length nor the penalty. Templated on the scalar alone, so it is compiled 3 times rather
/// than once per scalar × pair × length × penalty (36).
template <class S> struct LowerLevel {
  pce::Vec12<S> g;
  pce::Mat12<S> H;
  pce::FrameEigensystem<S> eig;
  pce::Mat12<S> P[5];
  bool core_finite = false;
};

template <class S> void check_lower_level(const pce::PairEnergy<S>& e, LowerLevel<S>& out) {
  PceFuzzStats& st = pce_fuzz_stats();
  pce::Vec12<S>& g = out.g;
  pce::Mat12<S>& H = out.H;
  pce::FrameEigensystem<S>& eig = out.eig;
  pce::Mat12<S>* const P = out.P;
  bool& core_finite = out.core_finite;
  if (e.psi.first != S(0) || e.psi.second != S(0)) ++st.active;
  g = pce::energy_gradient(e);
  H = pce::energy_hessian(e);
  eig = pce::energy_eigensystem(e);
  g_escape = &g;
  g_escape = &H;
  g_escape = &eig;
  // Underflow in the frame, ψ or the exact Hessian, and in each projection. Inside the
  // numerical projection's eigensolver an underflow only matters when ‖H‖ itself is
  // within 1/ε of the underflow threshold (its errors are relative to ‖H‖).
  const bool underflow = std::fetestexcept(FE_UNDERFLOW) != 0;
  const bool tiny_h = !(H.cwiseAbs().maxCoeff() >= (std::numeric_limits<S>::min)() / std::numeric_limits<S>::epsilon());
  bool uf[5];
  for (int s = 0; s < 5; ++s) {
    std::feclearexcept(FE_ALL_EXCEPT);
    P[s] = pce::projected_hessian(e, kStrategies[s]);
    g_escape = &P[s];
    const bool here = std::fetestexcept(FE_UNDERFLOW) != 0;
    uf[s] = underflow || (here && (kStrategies[s] != pce::Projection::numerical || tiny_h));
  }
  core_finite = finite(g) && finite(H) && finite(eig.values) && finite(e.length);

  // evaluate() tests only the eigenvalues for overflow: finite values must imply finite vectors.
  PCE_FUZZ_CHECK(!finite(eig.values) || finite(eig.vectors), "eigensystem: finite eigenvalues but a non-finite eigenvector");
  PCE_FUZZ_CHECK(same_values(P[0], H) || !finite(H), "projection none differs from energy_hessian");
  if (finite(eig.values)) {
    int zeros = 0;
    bool has_psi2 = false;
    for (int i = 0; i < 9; ++i) {
      if (i + 1 < 9)
        PCE_FUZZ_CHECK(eig.values[i] <= eig.values[i + 1], "eigenvalues not ascending at %d: %.17Lg > %.17Lg", i,
                       (long double)eig.values[i], (long double)eig.values[i + 1]);
      if (eig.values[i] == S(0)) ++zeros;
      if (eig.values[i] == e.psi.second) has_psi2 = true;
    }
    PCE_FUZZ_CHECK(zeros >= 4, "eigensystem: %d exact zeros, expected at least 4", zeros);
    PCE_FUZZ_CHECK(has_psi2, "eigensystem: psi'' = %.17Lg is not an eigenvalue", (long double)e.psi.second);
  }
  if (finite(H)) {
    const Eigen::Matrix<long double, 12, 12> Hl = ld(H);
    const long double hs = max_abs(Hl);
    if (hs > 0) {
      const long double asym = (Hl - Hl.transpose()).cwiseAbs().maxCoeff() / hs;
      if (asym > psd_tolerance<S>() && underflow)
        ++st.underflow_excused;
      else
        PCE_FUZZ_CHECK(asym <= psd_tolerance<S>(), "exact Hessian not symmetric: %.3Le", asym);
    }
  }
  // PSD-ness of every strategy but none, and the Loewner orderings abs ≥ analytic ≥ GN.
  Eigen::Matrix<long double, 12, 12> Pl[5];
  long double sc[5] = {0, 0, 0, 0, 0};
  bool fin[5];
  for (int s = 0; s < 5; ++s) {
    fin[s] = finite(P[s]);
    if (fin[s]) {
      Pl[s] = ld(P[s]);
      sc[s] = max_abs(Pl[s]);
    } else if (s != 0 && finite(H)) {
      ++st.projection_overflow;
    }
  }
  if (fin[1]) check_psd<S>(Pl[1], sc[1], 0, uf[1]);
  if (fin[2]) check_psd<S>(Pl[2], fin[0] ? (sc[2] > sc[0] ? sc[2] : sc[0]) : sc[2], 1, uf[2]);
  if (fin[3]) check_psd<S>(Pl[3], sc[3], 2, uf[3]);
  if (fin[4]) check_psd<S>(Pl[4], sc[4], 3, uf[4]);
  if (fin[4] && fin[1]) check_psd<S>(Pl[4] - Pl[1], sc[4] > sc[1] ? sc[4] : sc[1], 4, uf[4] || uf[1]);
  if (fin[1] && fin[3]) check_psd<S>(Pl[1] - Pl[3], sc[1] > sc[3] ? sc[1] : sc[3], 5, uf[1] || uf[3]);
}

template <class S, class Pair, class Length, class Penalty>
void check_case(const pce::Vec12<S>& x, const Length& len, const Penalty& pen, bool barrier, double eps_or_dhat,
                pce::Projection proj) {
  using pce::Status;
  PceFuzzStats& st = pce_fuzz_stats();

  bool nonfinite = false, absurd = false;
  for (int i = 0; i < 12; ++i) {
    using std::abs;
    if (!std::isfinite(x[i]))
      nonfinite = true;
    else if (abs(x[i]) > pce::Constants<S>::max_coordinate())
      absurd = true;
  }
  const bool valid = pce::penalty_valid(pen);

  // --- the frame ------------------------------------------------------------------------
  pce::Frame<S> f;
  fill(f);
  const Snapshot<pce::Frame<S>> fsnap(f);
  const Status fs = Pair::frame(x, f);
  if (nonfinite || absurd)
    PCE_FUZZ_CHECK(fs == Status::invalid_input, "frame: coordinate %s but status %s",
                   nonfinite ? "NaN/Inf" : "beyond max_coordinate", pce::to_string(fs));
  else
    PCE_FUZZ_CHECK(fs == Status::ok || fs == Status::degenerate || fs == Status::overflow, "frame: valid coordinates but status %s",
                   pce::to_string(fs));
  if (fs != Status::ok) {
    PCE_FUZZ_CHECK(fsnap.unchanged(f), "frame: status %s but the output was written", pce::to_string(fs));
  } else {
    PCE_FUZZ_CHECK(finite(f.P) && finite(f.n) && finite(f.t0) && finite(f.t1) && finite(f.l) && finite(f.a0) &&
                       finite(f.a1) && finite(f.alpha) && finite(f.beta) && finite(f.gamma),
                   "frame: status ok but a non-finite member");
    PCE_FUZZ_CHECK(f.a0 >= S(0) && f.a1 >= S(0), "frame: negative |e0| or |e1perp|");
  }

  // --- pair_energy ----------------------------------------------------------------------
  S L = S(0);
  if (fs == Status::ok) L = len.sigma(f) * f.l;
  pce::PairEnergy<S> e;
  fill(e);
  const Snapshot<pce::PairEnergy<S>> esnap(e);
  g_escape = &e;
  std::feclearexcept(FE_ALL_EXCEPT);
  const Status ps = pce::pair_energy<Pair>(x, len, pen, e);
  if (!valid || nonfinite || absurd) {
    PCE_FUZZ_CHECK(ps == Status::invalid_input, "pair_energy: %s but status %s",
                   !valid ? "invalid penalty parameters" : "invalid coordinates", pce::to_string(ps));
  } else if (fs != Status::ok) {
    PCE_FUZZ_CHECK(ps == fs, "pair_energy: frame status %s but pair_energy status %s", pce::to_string(fs),
                   pce::to_string(ps));
  } else if (barrier && !(L > S(0))) {
    PCE_FUZZ_CHECK(ps == Status::out_of_domain, "pair_energy: log barrier at L = %.17Lg <= 0 but status %s",
                   (long double)L, pce::to_string(ps));
  } else {
    const pce::PenaltyDerivatives<S> d = pen.template evaluate<S>(L);
    const bool psi_finite = finite(d.value) && finite(d.first) && finite(d.second);
    PCE_FUZZ_CHECK(ps == (psi_finite ? Status::ok : Status::overflow), "pair_energy: status %s, psi %s finite",
                   pce::to_string(ps), psi_finite ? "is" : "is not");
  }
  if (ps == Status::out_of_domain)
    PCE_FUZZ_CHECK(barrier, "pair_energy: out_of_domain for a penalty defined everywhere");
  if (ps != Status::ok) {
    PCE_FUZZ_CHECK(esnap.unchanged(e), "pair_energy: status %s but the output was written", pce::to_string(ps));
  } else {
    PCE_FUZZ_CHECK(finite(e.length) && finite(e.psi.value) && finite(e.psi.first) && finite(e.psi.second),
                   "pair_energy: status ok but L = %.17Lg, psi = %.17Lg, psi' = %.17Lg, psi'' = %.17Lg",
                   (long double)e.length, (long double)e.psi.value, (long double)e.psi.first, (long double)e.psi.second);
    PCE_FUZZ_CHECK(e.length == L && (e.sigma == S(1) || e.sigma == S(-1)), "pair_energy: length or sigma inconsistent");
    PCE_FUZZ_CHECK(e.frame.l == f.l && same_values(e.frame.P, f.P) && same_values(e.frame.n, f.n),
                   "pair_energy: frame differs from Pair::frame");
    if (std::is_same<Length, pce::UnsignedLength>::value)
      PCE_FUZZ_CHECK(e.length >= S(0), "unsigned length negative: %.17Lg", (long double)e.length);
    // ψ ≥ 0, ψ′ ≤ 0, ψ″ ≥ 0 for the three built-in penalties (k ≥ 0); all zero when inactive.
    PCE_FUZZ_CHECK(e.psi.value >= S(0) && e.psi.first <= S(0) && e.psi.second >= S(0),
                   "penalty signs: psi = %.17Lg, psi' = %.17Lg, psi'' = %.17Lg", (long double)e.psi.value,
                   (long double)e.psi.first, (long double)e.psi.second);
    const bool active = e.length < S(eps_or_dhat);
    if (!active)
      PCE_FUZZ_CHECK(e.psi.value == S(0) && e.psi.first == S(0) && e.psi.second == S(0),
                     "inactive penalty (L >= activation length) but psi, psi' or psi'' nonzero");
  }

  // --- lower-level outputs ----------------------------------------------------------------
  LowerLevel<S> low;
  if (ps == Status::ok) check_lower_level(e, low);
  const pce::Vec12<S>& g = low.g;
  const pce::Mat12<S>& H = low.H;
  const pce::FrameEigensystem<S>& eig = low.eig;
  const pce::Mat12<S>* const P = low.P;
  const bool core_finite = low.core_finite;

  // --- evaluate ---------------------------------------------------------------------------
  pce::PairResult<S> r;
  fill(r);
  const Snapshot<pce::PairResult<S>> rsnap(r);
  const Status es = pce::evaluate<Pair>(x, len, pen, proj, r);
  ++st.status[static_cast<int>(es)];
  if (nonfinite) PCE_FUZZ_CHECK(es == Status::invalid_input, "evaluate: NaN/Inf coordinate but status %s", pce::to_string(es));
  if (ps != Status::ok) {
    PCE_FUZZ_CHECK(es == ps, "evaluate: status %s, pair_energy status %s", pce::to_string(es), pce::to_string(ps));
  } else {
    const bool all = core_finite && finite(P[static_cast<int>(proj)]);
    PCE_FUZZ_CHECK(es == (all ? Status::ok : Status::overflow),
                   "evaluate: status %s but the lower-level outputs are %sfinite", pce::to_string(es), all ? "" : "not ");
  }
  if (es != Status::ok) {
    PCE_FUZZ_CHECK(rsnap.unchanged(r), "evaluate: status %s but the output was written", pce::to_string(es));
  } else {
    PCE_FUZZ_CHECK(finite(r.length) && finite(r.value) && finite(r.gradient) && finite(r.hessian) &&
                       finite(r.projected_hessian) && finite(r.eigen.values) && finite(r.eigen.vectors),
                   "evaluate: status ok but a non-finite output");
    PCE_FUZZ_CHECK(r.length == e.length && r.value == e.psi.value && same_values(r.gradient, g) &&
                       same_values(r.hessian, H) && same_values(r.projected_hessian, P[static_cast<int>(proj)]) &&
                       same_values(r.eigen.values, eig.values) && same_values(r.eigen.vectors, eig.vectors),
                   "evaluate: outputs differ from the lower-level functions");
  }
}

// ---------------------------------------------------------------------------------------
// Dispatch.

template <class S, class Pair, class Length> void run_length(Bytes& b, const pce::Vec12<S>& x, const Length& len) {
  const int penalty = b.u8() % 3;
  const pce::Projection proj = kStrategies[b.u8() % 5];
  g_case.projection = pce::to_string(proj);
  // The geometry's own L, so that the activation lengths can be placed around it.
  double Lhint = 1.0;
  pce::Frame<S> f;
  if (Pair::frame(x, f) == pce::Status::ok) Lhint = double(len.sigma(f) * f.l);
  const double k = decode_stiffness(b);
  g_case.k = k;
  switch (penalty) {
    case 0: {
      const pce::QuadraticPenalty pen{k, decode_eps(b, Lhint)};
      g_case.penalty = "quadratic";
      g_case.eps = pen.eps;
      check_case<S, Pair>(x, len, pen, false, pen.eps, proj);
      break;
    }
    case 1: {
      const double eps = decode_eps(b, Lhint);
      const pce::CubicPenalty pen{k, eps, decode_delta(b, Lhint - eps)};
      g_case.penalty = "cubic";
      g_case.eps = pen.eps;
      g_case.delta = pen.delta;
      check_case<S, Pair>(x, len, pen, false, pen.eps, proj);
      break;
    }
    default: {
      const pce::LogBarrierPenalty pen{k, decode_dhat(b, Lhint)};
      g_case.penalty = "log_barrier";
      g_case.dhat = pen.dhat;
      check_case<S, Pair>(x, len, pen, true, pen.dhat, proj);
      break;
    }
  }
}

template <class S, class Pair> void run_pair(Bytes& b, const pce::Vec12<S>& x, int length) {
  switch (length) {
    case 0:
      g_case.length = "signed(positive)";
      run_length<S, Pair>(b, x, pce::SignedLength{pce::Side::positive});
      break;
    case 1:
      g_case.length = "signed(negative)";
      run_length<S, Pair>(b, x, pce::SignedLength{pce::Side::negative});
      break;
    default:
      g_case.length = "unsigned";
      run_length<S, Pair>(b, x, pce::UnsignedLength{});
      break;
  }
}

template <class S> void run_scalar(Bytes& b) {
  g_case.scalar = scalar_name<S>();
  const bool edge_edge = b.u8() & 1;
  const int length = b.u8() % 3;
  g_case.pair = edge_edge ? pce::EdgeEdge::name : pce::VertexFace::name;
  const pce::Vec12<S> x = decode_x<S>(b, edge_edge);
  for (int i = 0; i < 12; ++i) g_case.x[i] = static_cast<long double>(x[i]);
  if (edge_edge)
    run_pair<S, pce::EdgeEdge>(b, x, length);
  else
    run_pair<S, pce::VertexFace>(b, x, length);
}

}  // namespace

int pce_fuzz_one(const uint8_t* data, size_t size) {
  ++pce_fuzz_stats().inputs;
  g_case = CaseInfo{};
  Bytes b(data, size);
  switch (b.u8() % 3) {
    case 0: run_scalar<float>(b); break;
    case 1: run_scalar<double>(b); break;
    default: run_scalar<long double>(b); break;
  }
  return 0;
}
