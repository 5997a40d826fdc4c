// SPDX-License-Identifier: MIT
/// @file
/// `pce-fuzz`: the standalone randomized driver of the fuzz body (works with any compiler;
/// built with AddressSanitizer and UndefinedBehaviorSanitizer when PCE_FUZZ_SANITIZE is on).
///
///     pce-fuzz [--inputs N] [--seed S] [--seconds T] [--max-len B] [--keep-going [--max-reports R]]
///     pce-fuzz --seed S --index I        replay input I of seed S
///     pce-fuzz FILE...                   replay saved inputs (also libFuzzer crash files)
///
/// Input I of seed S is B' random bytes (B' uniform in [0, B]) from std::mt19937_64 seeded
/// with a mix of S and I, so every input can be regenerated alone. Stops after N inputs or
/// T seconds, whichever comes first (default: 100000 inputs). Prints one summary line:
///
///     fuzz: N inputs, F failures, status counts: ok=.. invalid_input=.. degenerate=.. out_of_domain=.. overflow=..
///
/// and exits non-zero if an invariant failed. On a failure the input is saved as
/// `pce-fuzz-failure-seed<S>-input<I>.bin` in the working directory.
#include "fuzz_pair.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#if defined(PCE_FUZZ_SANITIZED) && PCE_FUZZ_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

namespace {

std::vector<uint8_t> g_input;
unsigned long long g_seed = 1, g_index = 0;
bool g_from_file = false;
const char* g_file = "";

void report_input() {
  if (g_from_file) {
    std::fprintf(stderr, "pce-fuzz: failing input: file %s\n", g_file);
    return;
  }
  char name[96];
  std::snprintf(name, sizeof name, "pce-fuzz-failure-seed%llu-input%llu.bin", g_seed, g_index);
  if (FILE* f = std::fopen(name, "wb")) {
    std::fwrite(g_input.data(), 1, g_input.size(), f);
    std::fclose(f);
  }
  std::fprintf(
      stderr,
      "pce-fuzz: failing input %llu of seed %llu (%zu bytes) saved as %s; replay: pce-fuzz --seed %llu --index %llu\n",
      g_index, g_seed, g_input.size(), name, g_seed, g_index);
}

#if defined(PCE_FUZZ_SANITIZED) && PCE_FUZZ_SANITIZED
void on_sanitizer_death() { report_input(); }
#endif

uint64_t splitmix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

void make_input(unsigned long long seed, unsigned long long index, unsigned max_len) {
  std::mt19937_64 rng(splitmix64(seed ^ splitmix64(index)));
  const size_t n = static_cast<size_t>(rng() % (max_len + 1ull));
  g_input.resize(n);
  for (size_t i = 0; i < n; i += 8) {
    const uint64_t w = rng();
    for (size_t j = 0; j < 8 && i + j < n; ++j) g_input[i + j] = static_cast<uint8_t>(w >> (8 * j));
  }
}

void usage() {
  std::fprintf(stderr,
               "usage: pce-fuzz [--inputs N] [--seed S] [--seconds T] [--max-len B] [--keep-going [--max-reports R]]\n"
               "       pce-fuzz --seed S --index I\n"
               "       pce-fuzz FILE...\n");
}

void summary(double seconds) {
  const PceFuzzStats& st = pce_fuzz_stats();
  std::printf(
      "fuzz: %llu inputs, %llu failures, status counts: ok=%llu invalid_input=%llu degenerate=%llu "
      "out_of_domain=%llu overflow=%llu\n",
      st.inputs, st.failures, st.status[0], st.status[1], st.status[2], st.status[3], st.status[4]);
  static const char* kinds[pce_fuzz_kinds] = {"vertex_face", "edge_edge",   "point_edge",
                                              "point_point", "closest(vf)", "closest(ee)"};
  for (int k = 0; k < pce_fuzz_kinds; ++k) {
    const unsigned long long* c = st.kind_status[k];
    std::printf("fuzz:   %-11s ok=%llu invalid_input=%llu degenerate=%llu out_of_domain=%llu overflow=%llu\n", kinds[k],
                c[0], c[1], c[2], c[3], c[4]);
  }
  std::printf(
      "fuzz: closest features (ok): vertex-face point_plane=%llu point_edge=%llu point_point=%llu; "
      "edge-edge line_line=%llu point_edge=%llu point_point=%llu; %llu SignedLength requests rejected\n",
      st.feature[0][0], st.feature[0][2], st.feature[0][3], st.feature[1][1], st.feature[1][2], st.feature[1][3],
      st.signed_rejected);
  std::printf(
      "fuzz: %.1f s (%.0f inputs/s); penalty active in %llu ok pairs; %llu PSD checks; "
      "%llu projections not finite beside a finite Hessian; %llu checker eigensolves not converged; "
      "%llu PSD checks with an underflow, %llu misses excused by it; %llu exact-numerical comparisons "
      "(%llu beyond 1024 eps within the frame basis' defect)\n",
      seconds, seconds > 0 ? double(st.inputs) / seconds : 0.0, st.active, st.psd_checks, st.projection_overflow,
      st.eig_no_convergence, st.psd_checks_underflow, st.underflow_excused, st.exact_compared, st.exact_basis_defect);
  static const char* scal[3] = {"float", "double", "long double"};
  for (int s = 0; s < 3; ++s)
    std::printf(
        "fuzz: worst lambda_min/scale %-11s analytic %.2e numerical %.2e gauss_newton %.2e abs %.2e exact %.2e "
        "abs-analytic %.2e analytic-gn %.2e exact-H %.2e; worst asymmetry %.2e; worst |exact-numerical| %.2e "
        "(%.2e with an orthonormal basis; beyond 1024 eps: %.2f delta)\n",
        scal[s], st.worst_psd[s][0], st.worst_psd[s][1], st.worst_psd[s][2], st.worst_psd[s][3], st.worst_psd[s][4],
        st.worst_psd[s][5], st.worst_psd[s][6], st.worst_psd[s][7], st.worst_asym[s], st.worst_exact_vs_numerical[s],
        st.worst_exact_vs_numerical_orthonormal[s], st.worst_exact_per_defect[s]);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  unsigned long long inputs = 0;
  double seconds = 0;
  unsigned max_len = 160;
  bool have_inputs = false, have_index = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--inputs" && has_value) {
      inputs = std::strtoull(argv[++i], nullptr, 10);
      have_inputs = true;
    } else if (a == "--seed" && has_value) {
      g_seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--seconds" && has_value) {
      seconds = std::strtod(argv[++i], nullptr);
    } else if (a == "--max-len" && has_value) {
      max_len = static_cast<unsigned>(std::strtoul(argv[++i], nullptr, 10));
    } else if (a == "--index" && has_value) {
      g_index = std::strtoull(argv[++i], nullptr, 10);
      have_index = true;
    } else if (a == "--max-reports" && has_value) {
      pce_fuzz_config().max_reports = std::atoi(argv[++i]);
    } else if (a == "--keep-going") {
      pce_fuzz_config().abort_on_failure = false;
    } else if (a == "--help" || a == "-h") {
      usage();
      return 0;
    } else if (!a.empty() && a[0] != '-') {
      files.push_back(a);
    } else {
      usage();
      return 2;
    }
  }
  pce_fuzz_config().on_failure = report_input;
#if defined(PCE_FUZZ_SANITIZED) && PCE_FUZZ_SANITIZED
  __sanitizer_set_death_callback(on_sanitizer_death);
#endif

  const auto t0 = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };

  if (!files.empty()) {  // replay files
    g_from_file = true;
    for (const std::string& name : files) {
      std::ifstream in(name, std::ios::binary);
      if (!in) {
        std::fprintf(stderr, "pce-fuzz: cannot read %s\n", name.c_str());
        return 2;
      }
      g_input.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      g_file = name.c_str();
      pce_fuzz_one(g_input.data(), g_input.size());
    }
  } else if (have_index) {  // replay one generated input
    make_input(g_seed, g_index, max_len);
    pce_fuzz_one(g_input.data(), g_input.size());
  } else {
    if (!have_inputs && !(seconds > 0)) inputs = 100000;
    double next_progress = 60;
    for (g_index = 0; !have_inputs || g_index < inputs; ++g_index) {
      if (seconds > 0 && (g_index & 63) == 0) {
        const double t = elapsed();
        if (t >= seconds) break;
        if (t >= next_progress) {
          const PceFuzzStats& st = pce_fuzz_stats();
          std::fprintf(stderr, "fuzz: %.0f s, %llu inputs, %llu failures\n", t, st.inputs, st.failures);
          next_progress += 60;
        }
      }
      make_input(g_seed, g_index, max_len);
      pce_fuzz_one(g_input.data(), g_input.size());
    }
  }
  summary(elapsed());
  return pce_fuzz_stats().failures == 0 ? 0 : 1;
}
