// SPDX-License-Identifier: MIT
/// @file
/// The fuzz body shared by both drivers (`pce-fuzz`, the standalone randomized driver, and
/// `pce-fuzz-libfuzzer`, the libFuzzer entry point): one byte string is decoded into one
/// per-pair evaluation (pair kind, length, penalty and its parameters, projection, scalar
/// type, 12, 9 or 6 coordinates) that is run through `pce::evaluate` and through the
/// lower-level per-pair functions, or through `pce::closest_feature_energy`, checking the
/// invariants of `docs/fuzzing.md`. See there.
#pragma once

#include <cstddef>
#include <cstdint>

/// Decodes `data` into one case, evaluates it and checks every invariant. A violation
/// prints the invariant and a reproducer (coordinates with %.17g and as hex floats, and
/// every option) to stderr and aborts, unless `pce_fuzz_config().abort_on_failure` is
/// false (then it is counted in `pce_fuzz_stats().failures`). Always returns 0.
int pce_fuzz_one(const uint8_t* data, size_t size);

struct PceFuzzConfig {
  bool abort_on_failure = true;    ///< abort at the first violated invariant (what the fuzzers expect)
  int max_reports = 20;            ///< with abort_on_failure = false: reproducers printed at most
  void (*on_failure)() = nullptr;  ///< called after a reproducer is printed (the driver saves the input)
};

/// Kinds the body fuzzes (`PceFuzzStats::kind_status`), in decoding order.
enum PceFuzzKind {
  pce_fuzz_vertex_face,  ///< pce::VertexFace through pce::evaluate and the lower-level functions
  pce_fuzz_edge_edge,    ///< pce::EdgeEdge, the same
  pce_fuzz_point_edge,   ///< pce::PointEdge (9 coordinates)
  pce_fuzz_point_point,  ///< pce::PointPoint (6 coordinates)
  pce_fuzz_closest_vf,   ///< pce::closest_feature_energy<pce::VertexFace>
  pce_fuzz_closest_ee,   ///< pce::closest_feature_energy<pce::EdgeEdge>
  pce_fuzz_kinds
};

/// PSD checks (`PceFuzzStats::worst_psd`): λ_min(M)/scale of each projection and of the
/// differences the definitions make PSD.
enum PceFuzzCheck {
  pce_fuzz_check_analytic,
  pce_fuzz_check_numerical,
  pce_fuzz_check_gauss_newton,
  pce_fuzz_check_abs,
  pce_fuzz_check_exact,
  pce_fuzz_check_abs_minus_analytic,
  pce_fuzz_check_analytic_minus_gn,
  pce_fuzz_check_exact_minus_hessian,
  pce_fuzz_checks
};

/// What the body has seen so far (for the standalone driver's summary).
struct PceFuzzStats {
  unsigned long long inputs = 0;
  unsigned long long failures = 0;
  /// Final status of each input, indexed by `pce::Status`: of `pce::evaluate` for the four
  /// pair kinds, of `pce::closest_feature_energy` for the closest-feature candidates.
  unsigned long long status[5] = {0, 0, 0, 0, 0};
  unsigned long long kind_status[pce_fuzz_kinds][5] = {};  ///< the same per kind
  unsigned long long feature[2][4] = {};        ///< closest feature (vf, ee) × `pce::Feature` of the ok evaluations
  unsigned long long signed_rejected = 0;       ///< SignedLength requests checked to give invalid_input
  unsigned long long active = 0;                ///< ok with ψ″ or ψ′ nonzero (penalty active)
  unsigned long long psd_checks = 0;            ///< projected Hessians checked for PSD-ness
  unsigned long long projection_overflow = 0;   ///< lower-level projection not finite (evaluate: overflow)
  unsigned long long eig_no_convergence = 0;    ///< the checker's long double eigensolver gave up
  unsigned long long psd_checks_underflow = 0;  ///< of which an intermediate underflowed
  unsigned long long underflow_excused = 0;     ///< PSD/symmetry/agreement misses where an intermediate underflowed
  unsigned long long exact_compared = 0;        ///< exact vs numerical comparisons made (both finite)
  unsigned long long exact_basis_defect = 0;    ///< of which the frame's basis was not orthonormal to 1024 ε
  /// Worst λ_min(P)/scale seen (checks without underflow), per scalar (float, double, long double) and
  /// `PceFuzzCheck`; 0 when never negative.
  double worst_psd[3][pce_fuzz_checks] = {};
  /// Worst |P(i,j) − P(j,i)|/scale seen per scalar over all strategies.
  double worst_asym[3] = {};
  /// Worst ‖P_exact − P_numerical‖_F / scale per scalar (comparisons without underflow), and
  /// the same over the comparisons whose basis defect is negligible (16 δ ≤ 1024 ε).
  double worst_exact_vs_numerical[3] = {};
  double worst_exact_vs_numerical_orthonormal[3] = {};
  /// Worst (‖P_exact − P_numerical‖_F / scale − 1024 ε) / δ over the comparisons beyond 1024 ε,
  /// δ the frame basis' orthonormality defect (docs/fuzzing.md).
  double worst_exact_per_defect[3] = {};
};

PceFuzzConfig& pce_fuzz_config();
PceFuzzStats& pce_fuzz_stats();
