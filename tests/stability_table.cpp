// SPDX-License-Identifier: MIT
// Prints the measured stability table of docs/stability.md: for every hard-case family
// and severity (tests/support/hard_cases.hpp), the relative error of value, gradient and
// Hessian against the 50-digit reference, next to the input-rounding bound.
//
//   ./build/tests/pce-stability-table [double|float|long_double]   > table.md
#include "support/stability_measure.hpp"

#include <cstdio>
#include <cstring>

namespace {

template <class S> int run() {
  std::printf("| family | severity | length | status | value err (bound) | gradient err (bound) | Hessian err (bound) | min PSD eig/|eig| | ok |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  int bad = 0;
  for (const pce_test::HardCase& hc : pce_test::hard_cases()) {
    const pce_test::Measurement m = pce_test::measure<S>(hc);
    const bool ok = hc.degenerate ? m.status == pce::Status::degenerate
                                  : (m.status == pce::Status::ok && m.finite && m.worst_psd >= -1e-12 &&
                                     pce_test::within(m.err_value, m.bound_value, m.unit_roundoff) &&
                                     pce_test::within(m.err_gradient, m.bound_gradient, m.unit_roundoff) &&
                                     pce_test::within(m.err_hessian, m.bound_hessian, m.unit_roundoff));
    bad += !ok;
    std::printf("| %s | %s | %s | %s |", hc.family.c_str(), hc.severity.c_str(), pce_test::name(hc.length),
                pce::to_string(m.status));
    if (m.status == pce::Status::ok)
      std::printf(" %.1e (%.1e) | %.1e (%.1e) | %.1e (%.1e) | %.1e |", m.err_value, m.bound_value, m.err_gradient,
                  m.bound_gradient, m.err_hessian, m.bound_hessian, m.worst_psd);
    else
      std::printf(" – | – | – | – |");
    std::printf(" %s |\n", ok ? "yes" : "**no**");
  }
  std::fprintf(stderr, "%d case(s) outside the bound\n", bad);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const char* s = argc > 1 ? argv[1] : "double";
  if (!std::strcmp(s, "float")) return run<float>();
  if (!std::strcmp(s, "long_double")) return run<long double>();
  return run<double>();
}
