// SPDX-License-Identifier: MIT
/// @file
/// The fuzz body shared by both drivers (`pce-fuzz`, the standalone randomized driver, and
/// `pce-fuzz-libfuzzer`, the libFuzzer entry point): one byte string is decoded into one
/// per-pair evaluation (pair kind, length, penalty and its parameters, projection, scalar
/// type, 12 coordinates) that is run through `pce::evaluate` and through the lower-level
/// per-pair functions, checking the invariants of `docs/fuzzing.md`. See there.
#pragma once

#include <cstddef>
#include <cstdint>

/// Decodes `data` into one case, evaluates it and checks every invariant. A violation
/// prints the invariant and a reproducer (coordinates with %.17g and as hex floats, and
/// every option) to stderr and aborts, unless `pce_fuzz_config().abort_on_failure` is
/// false (then it is counted in `pce_fuzz_stats().failures`). Always returns 0.
int pce_fuzz_one(const uint8_t* data, size_t size);

struct PceFuzzConfig {
  bool abort_on_failure = true;  ///< abort at the first violated invariant (what the fuzzers expect)
  int max_reports = 20;          ///< with abort_on_failure = false: reproducers printed at most
  void (*on_failure)() = nullptr;  ///< called after a reproducer is printed (the driver saves the input)
};

/// What the body has seen so far (for the standalone driver's summary).
struct PceFuzzStats {
  unsigned long long inputs = 0;
  unsigned long long failures = 0;
  unsigned long long status[5] = {0, 0, 0, 0, 0};  ///< of `pce::evaluate`, indexed by `pce::Status`
  unsigned long long active = 0;                   ///< ok with ψ″ or ψ′ nonzero (penalty active)
  unsigned long long psd_checks = 0;               ///< projected Hessians checked for PSD-ness
  unsigned long long projection_overflow = 0;      ///< lower-level projection not finite (evaluate: overflow)
  unsigned long long eig_no_convergence = 0;       ///< the checker's long double eigensolver gave up
  unsigned long long psd_checks_underflow = 0;     ///< of which an intermediate underflowed
  unsigned long long underflow_excused = 0;        ///< PSD/symmetry misses where an intermediate underflowed
  /// Worst λ_min(P)/scale seen (checks without underflow), per scalar (float, double, long double) and check
  /// (0 analytic, 1 numerical, 2 gauss_newton, 3 abs, 4 abs − analytic, 5 analytic − gauss_newton);
  /// 0 when never negative.
  double worst_psd[3][6] = {};
  /// Worst |P(i,j) − P(j,i)|/scale seen per scalar over all strategies.
  double worst_asym[3] = {};
};

PceFuzzConfig& pce_fuzz_config();
PceFuzzStats& pce_fuzz_stats();
