// SPDX-License-Identifier: MIT
/// @file
/// `pce-bench` driver: registers the vertex-face and edge-edge benchmarks, runs them all
/// with Google Benchmark's usual flags, and afterwards prints a ratio summary built from
/// the same run (a reporter that records each benchmark's real time per pair and forwards
/// everything to the normal console or JSON reporter). No timing is asserted: the exit
/// code says only whether the run itself worked.
#include "bench_common.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

/// Time per pair in ns (real and CPU), by benchmark name (`vertex_face/analytic/double`).
struct Times {
  double real = 0, cpu = 0;
};

struct Collected {
  std::map<std::string, Times> best;                 // "min" aggregate, with repetitions
  std::map<std::string, std::vector<Times>> single;  // plain runs (one per repetition)
  double worst_real_over_cpu = 0;                    // well above 1: the machine was busy
  std::string worst_name;

  /// The fastest run: with --benchmark_repetitions=N the best of N (the estimate least
  /// disturbed by other load; the "min" aggregate, shown even with
  /// --benchmark_display_aggregates_only), else the single run.
  bool get(const std::string& name, bool cpu, double& ns) const {
    if (auto it = best.find(name); it != best.end()) {
      ns = cpu ? it->second.cpu : it->second.real;
      return true;
    }
    if (auto it = single.find(name); it != single.end() && !it->second.empty()) {
      ns = cpu ? it->second.front().cpu : it->second.front().real;
      for (const Times& t : it->second) ns = std::min(ns, cpu ? t.cpu : t.real);
      return true;
    }
    return false;
  }
};

/// Wraps one of Google Benchmark's reporters: records, then forwards unchanged.
template <class Base> class CollectingReporter : public Base {
 public:
  template <class... A> explicit CollectingReporter(Collected& out, A... a) : Base(a...), out_(out) {}

  void ReportRuns(const std::vector<benchmark::BenchmarkReporter::Run>& runs) override {
    using Run = benchmark::BenchmarkReporter::Run;
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const double to_ns = 1e9 / benchmark::GetTimeUnitMultiplier(r.time_unit);
      const Times t{r.GetAdjustedRealTime() * to_ns, r.GetAdjustedCPUTime() * to_ns};
      const std::string& name = r.run_name.function_name;
      if (r.run_type == Run::RT_Iteration)
        out_.single[name].push_back(t);
      else if (r.aggregate_name == "min")
        out_.best[name] = t;
      else
        continue;
      if (t.cpu > 0 && t.real / t.cpu > out_.worst_real_over_cpu) {
        out_.worst_real_over_cpu = t.real / t.cpu;
        out_.worst_name = name;
      }
    }
    Base::ReportRuns(runs);
  }

 private:
  Collected& out_;
};

/// Last value of `--flag=value` in argv (Google Benchmark's own rule), or `fallback`.
std::string flag_value(const std::vector<char*>& args, const char* flag, const std::string& fallback) {
  const std::string prefix = std::string("--") + flag;
  std::string v = fallback;
  for (const char* a : args) {
    if (a == nullptr) continue;
    const std::string s(a);
    if (s == prefix)
      v = "true";
    else if (s.rfind(prefix + "=", 0) == 0)
      v = s.substr(prefix.size() + 1);
  }
  return v;
}

bool truthy(const std::string& v) {
  return v == "true" || v == "yes" || v == "1" || v == "on" || v == "t" || v == "y" || v == "TRUE" || v == "Yes";
}

void print_ratios(std::ostream& os, const Collected& c, bool cpu) {
  const char* pairs[] = {"vertex_face", "edge_edge", "point_edge", "point_point"};
  const char* scalars[] = {"double", "float"};
  char line[512];
  os << "\nRatio summary (" << (cpu ? "CPU" : "real")
     << " time per pair, this run, best repetition). Requirements, for double, not asserted:\n"
        "  [1] analytic/hessian <= 1.25 and analytic/numerical <= 1/15 (closed form vs the 12x12 baseline)\n"
        "  [2] exact/analytic <= 2 and exact/numerical <= 1/8 (the exact projection at closed-form cost;\n"
        "      required of the plane kinds, vertex_face and edge_edge: for the point kinds the columns say how "
        "close)\n";
  std::snprintf(line, sizeof line, "%-12s %-7s %9s %9s %9s %9s %10s %9s %9s %9s %9s  %s\n", "pair", "scalar", "hess ns",
                "analyt ns", "exact ns", "numer ns", "analytic/", "exact/", "numer/", "numer/", "abs/", "requirements");
  os << line;
  std::snprintf(line, sizeof line, "%-12s %-7s %9s %9s %9s %9s %10s %9s %9s %9s %9s\n", "", "", "", "", "", "",
                "hessian", "analytic", "analytic", "exact", "hessian");
  os << line;
  for (const char* p : pairs)
    for (const char* s : scalars) {
      const auto name = [&](const char* q) { return std::string(p) + "/" + q + "/" + s; };
      double he = 0, an = 0, ex = 0, nu = 0, ab = 0;
      const bool has_he = c.get(name("exact_hessian"), cpu, he), has_an = c.get(name("analytic"), cpu, an),
                 has_ex = c.get(name("exact"), cpu, ex), has_nu = c.get(name("numerical"), cpu, nu),
                 has_ab = c.get(name("abs"), cpu, ab);
      if (!has_he && !has_an && !has_ex && !has_nu && !has_ab) continue;  // filtered out
      const auto num = [](bool ok, double v, const char* fmt) {
        char b[32];
        if (ok)
          std::snprintf(b, sizeof b, fmt, v);
        else
          std::snprintf(b, sizeof b, "n/a");
        return std::string(b);
      };
      std::string req = "-";
      if (std::strcmp(s, "double") == 0) {
        std::string r1 = "n/a", r2 = "n/a";
        if (has_he && has_an && has_nu) r1 = (an <= 1.25 * he && an * 15.0 <= nu) ? "met" : "MISSED";
        const bool plane = std::strcmp(p, "vertex_face") == 0 || std::strcmp(p, "edge_edge") == 0;
        if (has_ex && has_an && has_nu) r2 = (ex <= 2.0 * an && ex * 8.0 <= nu) ? "met" : plane ? "MISSED" : "not met";
        req = "[1] " + r1 + " [2] " + r2;
      }
      std::snprintf(line, sizeof line, "%-12s %-7s %9s %9s %9s %9s %10s %9s %9s %9s %9s  %s\n", p, s,
                    num(has_he, he, "%.1f").c_str(), num(has_an, an, "%.1f").c_str(), num(has_ex, ex, "%.1f").c_str(),
                    num(has_nu, nu, "%.0f").c_str(), num(has_an && has_he, an / he, "%.3f").c_str(),
                    num(has_ex && has_an, ex / an, "%.3f").c_str(), num(has_nu && has_an, nu / an, "%.1fx").c_str(),
                    num(has_nu && has_ex, nu / ex, "%.1fx").c_str(), num(has_ab && has_he, ab / he, "%.3f").c_str(),
                    req.c_str());
      os << line;
    }
  os.flush();
}

/// Batched (evaluate_batch over 1024 pairs, a packet of pairs at a time) against the same
/// outputs one pair at a time: single ns / batched ns per pair.
void print_batch_ratios(std::ostream& os, const Collected& c, bool cpu) {
  const char* pairs[] = {"vertex_face", "edge_edge", "point_edge", "point_point"};
  const char* scalars[] = {"double", "float"};
  const char* rows[][2] = {{"value_gradient", "batch_value_gradient"},
                           {"exact_hessian", "batch_exact_hessian"},
                           {"analytic", "batch_analytic"}};
  char line[512];
  bool header = false;
  for (const char* p : pairs)
    for (const char* s : scalars) {
      std::string cells;
      bool any = false;
      for (const auto& r : rows) {
        double one = 0, batch = 0;
        const bool ok = c.get(std::string(p) + "/" + r[0] + "/" + s, cpu, one) &&
                        c.get(std::string(p) + "/" + r[1] + "/" + s, cpu, batch);
        char cell[64];
        if (ok)
          std::snprintf(cell, sizeof cell, " %9.1f %9.1f %7.2fx", one, batch, one / batch);
        else
          std::snprintf(cell, sizeof cell, " %9s %9s %8s", "n/a", "n/a", "n/a");
        cells += cell;
        any = any || ok;
      }
      if (!any) continue;
      if (!header) {
        os << "\nBatched (evaluate_batch, 1024 pairs, " << (cpu ? "CPU" : "real")
           << " time per pair) against one pair at a time, the same outputs:\n";
        std::snprintf(line, sizeof line, "%-12s %-7s %9s %9s %8s %9s %9s %8s %9s %9s %8s\n", "pair", "scalar", "vg ns",
                      "batch", "speedup", "hess ns", "batch", "speedup", "analyt ns", "batch", "speedup");
        os << line;
        header = true;
      }
      std::snprintf(line, sizeof line, "%-12s %-7s%s\n", p, s, cells.c_str());
      os << line;
    }
  os.flush();
}

/// The stable Neo-Hookean tetrahedron (`tet_snh/...`): its costs and requirement [3],
/// numerical/analytic >= 5 per tetrahedron (double).
void print_tet_ratios(std::ostream& os, const Collected& c, bool cpu) {
  char line[512];
  bool header = false;
  for (const char* s : {"double", "float"}) {
    const auto name = [&](const char* q) { return std::string("tet_snh/") + q + "/" + s; };
    double eg = 0, he = 0, an = 0, nu = 0, pa = 0, pn = 0;
    const bool has_eg = c.get(name("energy_gradient"), cpu, eg), has_he = c.get(name("hessian"), cpu, he),
               has_an = c.get(name("analytic"), cpu, an), has_nu = c.get(name("numerical"), cpu, nu),
               has_pa = c.get(name("projection_analytic"), cpu, pa),
               has_pn = c.get(name("projection_numerical"), cpu, pn);
    if (!(has_eg || has_he || has_an || has_nu || has_pa || has_pn)) continue;
    if (!header) {
      os << "\nStable Neo-Hookean tetrahedron (" << (cpu ? "CPU" : "real")
         << " time per tetrahedron). Requirement, for double, not asserted:\n"
            "  [3] numerical/analytic >= 5 (the closed-form eigensystem against a 9x9 eigensolve, per tetrahedron)\n";
      std::snprintf(line, sizeof line, "%-7s %9s %9s %9s %9s %9s %9s %9s %9s  %s\n", "scalar", "E,grad ns", "hess ns",
                    "analyt ns", "numer ns", "numer/", "F-proj a", "F-proj n", "numer/", "requirement");
      os << line;
      std::snprintf(line, sizeof line, "%-7s %9s %9s %9s %9s %9s %9s %9s %9s\n", "", "", "", "", "", "analytic", "ns",
                    "ns", "analytic");
      os << line;
      header = true;
    }
    const auto num = [](bool ok, double v, const char* fmt) {
      char b[32];
      std::snprintf(b, sizeof b, ok ? fmt : "n/a", v);
      return std::string(b);
    };
    std::string req = "-";
    if (std::string(s) == "double" && has_an && has_nu) req = std::string("[3] ") + (nu >= 5.0 * an ? "met" : "MISSED");
    std::snprintf(line, sizeof line, "%-7s %9s %9s %9s %9s %9s %9s %9s %9s  %s\n", s, num(has_eg, eg, "%.1f").c_str(),
                  num(has_he, he, "%.1f").c_str(), num(has_an, an, "%.1f").c_str(), num(has_nu, nu, "%.0f").c_str(),
                  num(has_an && has_nu, nu / an, "%.2fx").c_str(), num(has_pa, pa, "%.1f").c_str(),
                  num(has_pn, pn, "%.0f").c_str(), num(has_pa && has_pn, pn / pa, "%.2fx").c_str(), req.c_str());
    os << line;
  }
  os.flush();
}

/// The real-time table; when real time exceeded CPU time noticeably (other processes
/// took the CPU), also the CPU-time table, which is then the better estimate.
void print_summary(std::ostream& os, const Collected& c) {
  if (c.single.empty() && c.best.empty()) return;  // nothing ran (--benchmark_list_tests, empty filter)
  print_ratios(os, c, false);
  print_batch_ratios(os, c, false);
  print_tet_ratios(os, c, false);
  if (c.worst_real_over_cpu > 1.1) {
    char line[512];
    std::snprintf(line, sizeof line,
                  "note: real time exceeded CPU time by up to %.0f%% (%s): the machine was busy and the\n"
                  "      real-time ratios are unreliable; rerun on a quiet machine, or add\n"
                  "      --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true\n"
                  "      (the summary then uses the best of 5). CPU-time ratios:\n",
                  100.0 * (c.worst_real_over_cpu - 1.0), c.worst_name.c_str());
    os << line;
    print_ratios(os, c, true);
    print_batch_ratios(os, c, true);
    print_tet_ratios(os, c, true);
  }
}

void print_pool(const char* kind, const pce_bench::PoolStats& st) {
  std::fprintf(stderr,
               "pce-bench: %-11s pool: %zu active pairs (%zu draws); every exact Hessian has %d..%d negative "
               "eigenvalues, min eig/max|eig| <= %.2e (float and double); |analytic - exact|_F/|exact|_F "
               "median %.3g, max %.3g (double)\n",
               kind, pce_bench::kPoolSize, st.draws, st.min_negative, st.max_negative, st.worst_ratio, st.gap_median,
               st.gap_max);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<char*> args(argv, argv + argc);
  // Default: a short minimum time per benchmark so the whole run stays well under a
  // minute on a small machine. Any --benchmark_min_time on the command line wins.
  static char default_min_time[] = "--benchmark_min_time=0.2";
  bool has_min_time = false;
  for (int i = 1; i < argc; ++i)
    if (std::strncmp(argv[i], "--benchmark_min_time", 20) == 0) has_min_time = true;
  if (!has_min_time) args.push_back(default_min_time);
  const std::string format = flag_value(args, "benchmark_format", "console");
  const std::string color = flag_value(args, "benchmark_color", "auto");
  const bool tabular = truthy(flag_value(args, "benchmark_counters_tabular", "false"));
  args.push_back(nullptr);

  int n = static_cast<int>(args.size()) - 1;
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;

#ifndef NDEBUG
  std::fprintf(stderr,
               "pce-bench: WARNING: built without NDEBUG (not a Release build); timings are not "
               "meaningful\n");
#endif
  std::fprintf(stderr,
               "pce-bench: log barrier k=1, dhat=%g on the signed length (point kinds: unsigned), L uniform in [%g, "
               "%g]*dhat, seed %llu\n",
               pce_bench::kDhat, pce_bench::kLMin, pce_bench::kLMax, static_cast<unsigned long long>(pce_bench::kSeed));
  print_pool("vertex_face", pce_bench::register_vertex_face_benchmarks());
  print_pool("edge_edge", pce_bench::register_edge_edge_benchmarks());
  print_pool("point_edge", pce_bench::register_point_edge_benchmarks());
  print_pool("point_point", pce_bench::register_point_point_benchmarks());
  const pce_bench::TetPoolStats tets = pce_bench::register_tet_benchmarks();
  std::fprintf(
      stderr,
      "pce-bench: tet_snh pool: %d tetrahedra (stable Neo-Hookean, E = 1e5, nu = 0.4), %d inverted, %d with an "
      "indefinite scaling block (double)\n",
      tets.count, tets.inverted, tets.indefinite);

  Collected collected;
  if (format == "json") {
    // stdout stays valid JSON: the ratio summary goes to stderr.
    CollectingReporter<benchmark::JSONReporter> rep(collected);
    benchmark::RunSpecifiedBenchmarks(&rep);
    print_summary(std::cerr, collected);
  } else if (format == "console") {
    const bool use_color = color == "auto" ? ::isatty(STDOUT_FILENO) != 0 : truthy(color);
    int opts = benchmark::ConsoleReporter::OO_None;
    if (use_color) opts |= benchmark::ConsoleReporter::OO_Color;
    if (tabular) opts |= benchmark::ConsoleReporter::OO_Tabular;
    CollectingReporter<benchmark::ConsoleReporter> rep(collected,
                                                       static_cast<benchmark::ConsoleReporter::OutputOptions>(opts));
    benchmark::RunSpecifiedBenchmarks(&rep);
    print_summary(std::cout, collected);
  } else {
    std::fprintf(stderr, "pce-bench: no ratio summary for --benchmark_format=%s (console and json only)\n",
                 format.c_str());
    benchmark::RunSpecifiedBenchmarks();
  }
  benchmark::Shutdown();
  return 0;
}
