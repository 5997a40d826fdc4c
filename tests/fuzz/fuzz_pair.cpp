// SPDX-License-Identifier: MIT
/// @file
/// The fuzz body of `docs/fuzzing.md`, its parts that do not depend on the scalar type:
/// the statistics and configuration, the reproducer printed on a failure, the decoding of
/// the penalty parameters, and `pce_fuzz_one`, which decodes the scalar type and hands the
/// input to `run_scalar<S>`. The templates of the body (the coordinate decoder, the
/// projection checks and the plane kinds, `fuzz_plane.hpp`; the point kinds,
/// `fuzz_points.hpp`; closest-feature evaluation, `fuzz_closest.hpp`) are compiled once per
/// scalar type (`fuzz_float.cpp`, `fuzz_double.cpp`, `fuzz_long_double.cpp`).
///
/// Penalty parameters are drawn relative to the decoded geometry's length L (so the penalty
/// is active, just active, at its boundary, or inactive) or from a menu including invalid
/// ones (negative, NaN, ±Inf) and extreme ones (0, subnormal, 1e300, DBL_MAX).
#include "fuzz_common.hpp"

#include <cstdarg>
#include <cstdio>
#include <cstdlib>

PceFuzzConfig& pce_fuzz_config() {
  static PceFuzzConfig c;
  return c;
}

PceFuzzStats& pce_fuzz_stats() {
  static PceFuzzStats s;
  return s;
}

namespace pce_fuzz {

CaseInfo g_case;
void* volatile g_escape = nullptr;

namespace {

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
  for (int i = 0; i < c.nx; ++i) {
    if (ld)
      std::fprintf(stderr, "%s%.21Lg", i ? ", " : "", c.x[i]);
    else
      std::fprintf(stderr, "%s%.17g", i ? ", " : "", double(c.x[i]));
  }
  std::fprintf(stderr, "}\n  x (hex) = {");
  for (int i = 0; i < c.nx; ++i) {
    if (ld)
      std::fprintf(stderr, "%s%La", i ? ", " : "", c.x[i]);
    else
      std::fprintf(stderr, "%s%a", i ? ", " : "", double(c.x[i]));
  }
  std::fprintf(stderr, "}\n  decoded from: coordinate mode %d, ops [%s]\n", c.coord_mode, c.ops.c_str());
}

}  // namespace

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

// ---------------------------------------------------------------------------------------
// Penalty parameters (doubles, as the penalty types store them).

namespace {

double raw_double(Bytes& b) {
  const uint64_t u = b.u64();
  double v;
  std::memcpy(&v, &u, sizeof v);
  return v;
}

double decode_stiffness(Bytes& b) {
  switch (b.u8() % 32) {
    case 0:
      return 0.0;
    case 1:
      return -0.0;
    case 2:
      return 1e3;
    case 3:
      return 1e-3;
    case 4:
      return 1e8;
    case 5:
      return 1e-8;
    case 6:
      return std::pow(10.0, b.range(-30, 30));
    case 7:
      return 1e300;
    case 8:
      return std::numeric_limits<double>::max();
    case 9:
      return std::numeric_limits<double>::denorm_min();
    case 10:
      return raw_double(b);
    case 11:
      return -1.0;  // invalid
    case 12:
      return std::numeric_limits<double>::quiet_NaN();  // invalid
    case 13:
      return std::numeric_limits<double>::infinity();  // invalid
    case 14:
      return 4.0 * b.unit();
    default:
      return 1.0;
  }
}

/// Activation length ε relative to the geometry's L (active, just active, at the boundary,
/// inactive), or from the menu.
double decode_eps(Bytes& b, double L) {
  const double m = std::fabs(L) > 0 ? std::fabs(L) : 1.0;
  switch (b.u8() % 32) {
    case 0:
      return 0.0;
    case 1:
      return L;  // exactly at the activation length: inactive
    case 2:
      return std::nextafter(L, std::numeric_limits<double>::infinity());
    case 3:
      return L + m * std::pow(10.0, -b.range(0, 16));
    case 4:
      return L - m * std::pow(10.0, -b.range(0, 16));
    case 5:
      return 2 * m;
    case 6:
      return L + m * std::pow(10.0, b.range(0, 8));
    case 7:
      return -m;
    case 8:
      return 1.0;
    case 9:
      return -1.0;
    case 10:
      return 1e300;
    case 11:
      return -1e300;
    case 12:
      return std::numeric_limits<double>::max();
    case 13: {
      const double sign = (b.u8() & 1) ? -1 : 1;
      return sign * std::pow(10.0, b.range(-30, 30));
    }
    case 14:
      return raw_double(b);
    case 15:
      return std::numeric_limits<double>::quiet_NaN();  // invalid
    case 16:
      return std::numeric_limits<double>::infinity();  // invalid
    case 17:
      return -std::numeric_limits<double>::infinity();  // invalid
    default:
      return L + m * (0.1 + 2 * b.unit());
  }
}

double decode_delta(Bytes& b, double d) {
  const double m2 = d * d > 0 && std::isfinite(d * d) ? d * d : 1.0;
  switch (b.u8() % 24) {
    case 0:
      return 0.0;
    case 1:
      return -0.0;
    case 2:
      return m2 * std::pow(10.0, -b.range(0, 32));
    case 3:
      return m2 * std::pow(10.0, b.range(0, 8));
    case 4:
      return 1e-300;
    case 5:
      return std::numeric_limits<double>::denorm_min();
    case 6:
      return 1e300;
    case 7:
      return std::numeric_limits<double>::max();
    case 8:
      return raw_double(b);
    case 9:
      return -1e-3;  // invalid
    case 10:
      return std::numeric_limits<double>::quiet_NaN();  // invalid
    case 11:
      return std::numeric_limits<double>::infinity();  // invalid
    default:
      return m2 * 4 * b.unit();
  }
}

double decode_dhat(Bytes& b, double L) {
  const double m = std::fabs(L) > 0 ? std::fabs(L) : 1.0;
  switch (b.u8() % 32) {
    case 0:
      return 2 * m;
    case 1:
      return m;  // L = d̂: inactive
    case 2:
      return std::nextafter(m, std::numeric_limits<double>::infinity());
    case 3:
      return m * (1 + std::pow(10.0, -b.range(1, 16)));  // L just below d̂
    case 4:
      return m * std::pow(10.0, b.range(1, 16));  // L ≪ d̂: near the pole
    case 5:
      return m * 0.5;  // inactive
    case 6:
      return 1.0;
    case 7:
      return 1e-3;
    case 8:
      return 1e300;
    case 9:
      return std::numeric_limits<double>::denorm_min();
    case 10:
      return std::numeric_limits<double>::max();
    case 11:
      return raw_double(b);
    case 12:
      return 0.0;  // invalid
    case 13:
      return -0.0;  // invalid
    case 14:
      return -1.0;  // invalid
    case 15:
      return std::numeric_limits<double>::quiet_NaN();  // invalid
    case 16:
      return std::numeric_limits<double>::infinity();  // invalid
    default:
      return m * (1 + 4 * b.unit());
  }
}

}  // namespace

DecodedPenalty decode_penalty(Bytes& b, int type, double Lhint) {
  DecodedPenalty d;
  d.type = type;
  const double k = decode_stiffness(b);
  g_case.k = k;
  switch (type) {
    case 0:
      d.quadratic = pce::QuadraticPenalty{k, decode_eps(b, Lhint)};
      d.activation = d.quadratic.eps;
      g_case.penalty = "quadratic";
      g_case.eps = d.quadratic.eps;
      break;
    case 1: {
      const double eps = decode_eps(b, Lhint);
      d.cubic = pce::CubicPenalty{k, eps, decode_delta(b, Lhint - eps)};
      d.activation = d.cubic.eps;
      g_case.penalty = "cubic";
      g_case.eps = d.cubic.eps;
      g_case.delta = d.cubic.delta;
      break;
    }
    default:
      d.barrier = pce::LogBarrierPenalty{k, decode_dhat(b, Lhint)};
      d.activation = d.barrier.dhat;
      g_case.penalty = "log_barrier";
      g_case.dhat = d.barrier.dhat;
      break;
  }
  return d;
}

}  // namespace pce_fuzz

int pce_fuzz_one(const uint8_t* data, size_t size) {
  using namespace pce_fuzz;
  ++pce_fuzz_stats().inputs;
  g_case = CaseInfo{};
  Bytes b(data, size);
  switch (b.u8() % 3) {
    case 0:
      run_scalar<float>(b);
      break;
    case 1:
      run_scalar<double>(b);
      break;
    default:
      run_scalar<long double>(b);
      break;
  }
  return 0;
}
