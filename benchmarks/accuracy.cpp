// SPDX-License-Identifier: MIT
// pce-accuracy: per-pair accuracy of every PSD strategy beside its cost (pce-bench), for
// pair kind × length × penalty × strategy × scalar on fixed, seeded sets of configurations
// (random, near_contact, and every hard-case family of tests/support/hard_cases.hpp).
//
// Per group it reports the relative Frobenius distance ‖P − P*‖/‖P*‖ of the strategy's
// projected Hessian P (computed in the scalar) to P*, the nearest PSD matrix of the exact
// Hessian computed in 50 digits at the same rounded input (median, 90th percentile and max),
// the PSD-violation count (λ_min(P) < −n·ε·max|λ(P)|, λ in long double), and the counts of
// non-finite outputs and of non-ok statuses. Definitions: tests/support/accuracy_measure.hpp.
// Accuracy is reported, never asserted (tests/test_accuracy_reference.cpp checks the
// measurement itself).
//
//   pce-accuracy [--quick] [--count N] [--seed S] [--out FILE.json] [--csv FILE.csv]
#include "support/accuracy_measure.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace pce_test {
extern template SampleOutcome measure_sample<float>(const Sample&);
extern template SampleOutcome measure_sample<double>(const Sample&);
}  // namespace pce_test

namespace {
using namespace pce_test;

struct Settings {
  bool quick = false;
  int count = 1000;  ///< samples per random / near_contact group
  unsigned long long seed = 20231;
  int hard_stride = 1;  ///< every k-th hard case (--quick: 8)
  std::string out, csv;
};

/// One output row: pair × length × penalty × family × scalar × strategy.
struct Row {
  std::string pair, length, penalty, family, scalar, strategy;
  int configurations = 0, not_ok = 0, status_mismatch = 0, non_finite = 0, psd_violations = 0;
  int sign_ambiguous = 0, zero_reference = 0;
  std::vector<double> dists;
  double median = NAN, p90 = NAN, max = NAN;
};

/// Nearest-rank quantile of sorted values.
double quantile(const std::vector<double>& v, double p) {
  if (v.empty()) return NAN;
  const std::size_t k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
  return v[std::min(v.size() - 1, k > 0 ? k - 1 : 0)];
}

struct Worst {
  double value = -1;
  std::string where;
};

const char* length_name(LengthKind l) { return l == LengthKind::unsigned_ ? "unsigned" : "signed"; }
const char* scalar_name(int s) { return s == 0 ? "float" : "double"; }

std::string describe(const Sample& s) {
  std::string d = std::string(name(s.pair)) + " " + length_name(s.length) + " " + name(s.penalty.kind) + " " + s.family;
  if (!s.severity.empty()) d += " severity " + s.severity;
  char buf[160];
  std::snprintf(buf, sizeof buf, " (range %.3g)", active_range(s.penalty));
  return d + buf;
}

struct Tally {
  std::vector<Row> rows;
  std::map<std::string, Worst> worst_dist, worst_psd;  ///< key: scalar/strategy
  std::map<std::string, int> statuses;                 ///< "scalar status expected|unexpected family"
  int samples = 0;
};

/// Measures one group (one set of samples) in both scalars; appends 10 rows.
void measure_group(const std::vector<Sample>& samples, const std::string& family, Tally& t) {
  if (samples.empty()) return;
  const Sample& s0 = samples.front();
  for (int sc = 0; sc < 2; ++sc) {
    std::vector<Row> rows(kStrategies.size());
    for (std::size_t k = 0; k < kStrategies.size(); ++k) {
      rows[k].pair = name(s0.pair);
      rows[k].length = length_name(s0.length);
      rows[k].penalty = name(s0.penalty.kind);
      rows[k].family = family;
      rows[k].scalar = scalar_name(sc);
      rows[k].strategy = pce::to_string(kStrategies[k]);
    }
    for (const Sample& s : samples) {
      const SampleOutcome o = sc == 0 ? measure_sample<float>(s) : measure_sample<double>(s);
      ++t.samples;
      if (o.status == pce::Status::ok && o.reference_status != pce::Status::ok)  // no rel_dist for these
        ++t.statuses[std::string(scalar_name(sc)) + " ok (50 digits: " + pce::to_string(o.reference_status) +
                     ", not "
                     "measured) " +
                     s.family];
      if (o.status != pce::Status::ok) {
        const bool expected = o.status == o.reference_status;
        ++t.statuses[std::string(scalar_name(sc)) + " " + pce::to_string(o.status) +
                     (expected ? " (50 digits agree) " : " (50 digits: ") +
                     (expected ? "" : std::string(pce::to_string(o.reference_status)) + ") ") + s.family];
      }
      for (std::size_t k = 0; k < kStrategies.size(); ++k) {
        Row& r = rows[k];
        ++r.configurations;
        r.status_mismatch += o.status != o.reference_status;
        if (o.status != pce::Status::ok) {
          ++r.not_ok;
          continue;
        }
        const StrategyOutcome& so = o.strategies[k];
        if (!so.finite) {
          ++r.non_finite;
          continue;
        }
        r.psd_violations += so.psd_violation;
        r.sign_ambiguous += o.sign_ambiguous;
        r.zero_reference += o.zero_reference;
        const std::string key = std::string(scalar_name(sc)) + " " + r.strategy;
        if (so.psd_violation && (t.worst_psd[key].value < 0 || -so.psd_ratio > t.worst_psd[key].value))
          t.worst_psd[key] = {-so.psd_ratio, describe(s)};
        if (std::isnan(so.rel_dist)) continue;  // the 50-digit evaluation is not ok here
        r.dists.push_back(so.rel_dist);
        if (so.rel_dist > t.worst_dist[key].value) t.worst_dist[key] = {so.rel_dist, describe(s)};
      }
    }
    for (Row& r : rows) {
      std::sort(r.dists.begin(), r.dists.end());
      r.median = quantile(r.dists, 0.5);
      r.p90 = quantile(r.dists, 0.9);
      r.max = r.dists.empty() ? NAN : r.dists.back();
      t.rows.push_back(std::move(r));
    }
  }
}

std::string num(double v, const char* fmt = "%.2e") {
  if (std::isnan(v)) return "-";
  if (std::isinf(v)) return "inf";
  char b[32];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}

/// JSON number: null for "no value", 1e999 for +inf (parsers read it as infinity).
std::string json_num(double v) {
  if (std::isnan(v)) return "null";
  if (std::isinf(v)) return "1e999";
  char b[32];
  std::snprintf(b, sizeof b, "%.6e", v);
  return b;
}

/// Summary: one table per pair kind, hard families pooled ("hard", all severities).
void print_tables(const Tally& t) {
  for (const char* pair : {"vertex_face", "edge_edge", "point_edge", "point_point"}) {
    std::printf("\n## %s   cells: rel_dist p90 / max  (! = PSD violations in that group)\n", pair);
    std::printf("%-8s %-11s %-12s %-6s %5s %5s %4s", "length", "penalty", "family", "scalar", "N", "notok", "nonf");
    for (pce::Projection p : kStrategies) std::printf(" | %-15s", pce::to_string(p));
    std::printf("\n");
    for (const char* length : {"signed", "unsigned"})
      for (const char* pen : {"quadratic", "cubic", "log_barrier"})
        for (const char* fam : {"random", "near_contact", "hard"})
          for (const char* sc : {"float", "double"}) {
            // Pool the rows of this cell (hard: every hard family).
            std::vector<double> d[kStrategies.size()];
            int n = 0, notok = 0, nonf = 0, viol[kStrategies.size()] = {};
            bool any = false;
            for (const Row& r : t.rows) {
              const bool is_fam = std::strcmp(fam, "hard") == 0 ? (r.family != "random" && r.family != "near_contact")
                                                                : r.family == fam;
              if (r.pair != pair || r.length != length || r.penalty != pen || r.scalar != sc || !is_fam) continue;
              any = true;
              std::size_t k = 0;
              while (pce::to_string(kStrategies[k]) != r.strategy) ++k;
              d[k].insert(d[k].end(), r.dists.begin(), r.dists.end());
              viol[k] += r.psd_violations;
              if (k == 0) {
                n += r.configurations;
                notok += r.not_ok;
              }
              nonf += r.non_finite;
            }
            if (!any) continue;
            std::printf("%-8s %-11s %-12s %-6s %5d %5d %4d", length, pen, fam, sc, n, notok, nonf);
            for (std::size_t k = 0; k < kStrategies.size(); ++k) {
              std::sort(d[k].begin(), d[k].end());
              const std::string cell = num(quantile(d[k], 0.9), "%.0e") + " / " +
                                       num(d[k].empty() ? NAN : d[k].back(), "%.0e") + (viol[k] ? "!" : " ");
              std::printf(" | %-15s", cell.c_str());
            }
            std::printf("\n");
          }
  }
}

void print_worst(const Tally& t) {
  std::printf("\n## Worst rel_dist per scalar and strategy\n");
  for (const auto& [key, w] : t.worst_dist)
    std::printf("%-20s %9s  %s\n", key.c_str(), num(w.value).c_str(), w.where.c_str());
  std::printf("\n## PSD violations (most negative λ_min/max|λ| per scalar and strategy)\n");
  if (t.worst_psd.empty()) std::printf("none\n");
  for (const auto& [key, w] : t.worst_psd) {
    int count = 0;
    for (const Row& r : t.rows)
      if (std::string(r.scalar) + " " + r.strategy == key) count += r.psd_violations;
    std::printf("%-20s %5d violation(s), worst %9s  %s\n", key.c_str(), count, num(-w.value).c_str(), w.where.c_str());
  }
  std::printf(
      "\n## Non-ok statuses and status mismatches (samples: scalar, status, the 50-digit status at the same input, "
      "family)\n");
  if (t.statuses.empty()) std::printf("none\n");
  for (const auto& [key, count] : t.statuses) std::printf("%6d  %s\n", count, key.c_str());
}

const char* const kColumns[] = {"pair",           "length",         "penalty",        "family",          "scalar",
                                "strategy",       "configurations", "not_ok",         "status_mismatch", "non_finite",
                                "psd_violations", "sign_ambiguous", "zero_reference", "rel_dist_median", "rel_dist_p90",
                                "rel_dist_max"};

bool write_json(const std::string& path, const Tally& t, const Settings& s) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  std::fprintf(f,
               "{\n  \"settings\": {\"quick\": %s, \"seed\": %llu, \"count_random\": %d, \"count_near_contact\": %d, "
               "\"hard_case_stride\": %d, \"samples_measured\": %d,\n",
               s.quick ? "true" : "false", s.seed, s.count, s.count, s.hard_stride, t.samples);
  std::fprintf(f,
               "    \"reference\": \"project_psd of the exact Hessian, both in 50 digits (cpp_bin_float<50>) at the "
               "input rounded to the scalar\",\n");
  std::fprintf(f,
               "    \"rel_dist\": \"||P - P*||_F / ||P*||_F (||H*||_F when ||P*|| = 0; 0 if both and P are 0, else "
               "1e999); nearest-rank quantiles over ok, finite results with an ok reference\",\n");
  std::fprintf(f,
               "    \"psd_violation\": \"lambda_min(P) < -tau * max|lambda(P)|, lambda in long double, tau = n * "
               "epsilon\", \"tau_float_n12\": %.3e, \"tau_double_n12\": %.3e,\n",
               psd_tolerance<float>(12), psd_tolerance<double>(12));
  std::fprintf(f,
               "    \"random\": \"size s log-uniform 1e-2..1e2, offset <= s, range R = s/2, L = R*U(0.02, 0.98)\",\n");
  std::fprintf(f, "    \"near_contact\": \"as random, L = R*10^U(-6, -2)\",\n");
  std::fprintf(f,
               "    \"hard\": \"tests/support/hard_cases.hpp; own penalty for its kind, other kinds with the same "
               "active range (cubic delta = (R/10)^2), stiffness 1\"},\n  \"rows\": [\n");
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const Row& r = t.rows[i];
    std::fprintf(
        f,
        "    {\"pair\": \"%s\", \"length\": \"%s\", \"penalty\": \"%s\", \"family\": \"%s\", \"scalar\": \"%s\", "
        "\"strategy\": \"%s\", \"configurations\": %d, \"not_ok\": %d, \"status_mismatch\": %d, "
        "\"non_finite\": %d, \"psd_violations\": %d, \"sign_ambiguous\": %d, \"zero_reference\": %d, "
        "\"rel_dist_median\": %s, \"rel_dist_p90\": %s, \"rel_dist_max\": %s}%s\n",
        r.pair.c_str(), r.length.c_str(), r.penalty.c_str(), r.family.c_str(), r.scalar.c_str(), r.strategy.c_str(),
        r.configurations, r.not_ok, r.status_mismatch, r.non_finite, r.psd_violations, r.sign_ambiguous,
        r.zero_reference, json_num(r.median).c_str(), json_num(r.p90).c_str(), json_num(r.max).c_str(),
        i + 1 < t.rows.size() ? "," : "");
  }
  std::fprintf(f, "  ]\n}\n");
  return std::fclose(f) == 0;
}

bool write_csv(const std::string& path, const Tally& t) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) return false;
  for (std::size_t i = 0; i < std::size(kColumns); ++i) std::fprintf(f, "%s%s", i ? "," : "", kColumns[i]);
  std::fprintf(f, "\n");
  for (const Row& r : t.rows)
    std::fprintf(f, "%s,%s,%s,%s,%s,%s,%d,%d,%d,%d,%d,%d,%d,%s,%s,%s\n", r.pair.c_str(), r.length.c_str(),
                 r.penalty.c_str(), r.family.c_str(), r.scalar.c_str(), r.strategy.c_str(), r.configurations, r.not_ok,
                 r.status_mismatch, r.non_finite, r.psd_violations, r.sign_ambiguous, r.zero_reference,
                 num(r.median, "%.6e").c_str(), num(r.p90, "%.6e").c_str(), num(r.max, "%.6e").c_str());
  return std::fclose(f) == 0;
}

int usage(const char* msg) {
  std::fprintf(stderr,
               "pce-accuracy: %s\nusage: pce-accuracy [--quick] [--count N] [--seed S] [--out FILE.json] "
               "[--csv FILE.csv]\n",
               msg);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  bool count_given = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
    if (a == "--quick") {
      s.quick = true;
    } else if (a == "--help" || a == "-h") {
      usage("per-pair accuracy of the PSD strategies against the 50-digit nearest PSD matrix");
      return 0;
    } else if (a == "--count" || a == "--seed" || a == "--out" || a == "--csv") {
      const char* v = value();
      if (!v) return usage((a + " needs a value").c_str());
      char* end = nullptr;
      if (a == "--count") {
        const long n = std::strtol(v, &end, 10);
        if (*end || n < 1 || n > 1000000) return usage("--count needs a positive integer");
        s.count = static_cast<int>(n);
        count_given = true;
      } else if (a == "--seed") {
        s.seed = std::strtoull(v, &end, 10);
        if (*end) return usage("--seed needs an integer");
      } else if (a == "--out") {
        s.out = v;
      } else {
        s.csv = v;
      }
    } else {
      return usage(("unknown argument '" + a + "'").c_str());
    }
  }
  if (s.quick) {
    if (!count_given) s.count = 4;
    s.hard_stride = 8;
  }

  const auto t0 = std::chrono::steady_clock::now();
  Tally t;
  const PenaltyKind penalties[] = {PenaltyKind::quadratic, PenaltyKind::cubic, PenaltyKind::log_barrier};
  for (AnyPair pair : {AnyPair::vertex_face, AnyPair::edge_edge, AnyPair::point_edge, AnyPair::point_point}) {
    const std::vector<LengthKind> lengths =
        is_plane(pair) ? std::vector<LengthKind>{LengthKind::signed_positive, LengthKind::unsigned_}
                       : std::vector<LengthKind>{LengthKind::unsigned_};
    for (LengthKind len : lengths)
      for (std::size_t ip = 0; ip < std::size(penalties); ++ip) {
        const PenaltyKind pen = penalties[ip];
        for (LengthDraw draw : {LengthDraw::spread, LengthDraw::near_contact}) {
          const unsigned long long seed = s.seed + 1000ULL * static_cast<unsigned>(pair) +
                                          100ULL * static_cast<unsigned>(len) + 10ULL * ip +
                                          static_cast<unsigned>(draw);
          measure_group(generated_samples(pair, len, pen, draw, s.count, seed),
                        draw == LengthDraw::spread ? "random" : "near_contact", t);
        }
        if (!is_plane(pair)) continue;
        // Hard families of this pair kind and length, in hard_cases() order.
        std::vector<std::string> order;
        std::map<std::string, std::vector<Sample>> fam;
        int index = 0;
        for (const Sample& h : hard_samples(pen)) {
          if (h.pair != pair || h.length != len) continue;
          if (index++ % s.hard_stride) continue;
          if (!fam.count(h.family)) order.push_back(h.family);
          fam[h.family].push_back(h);
        }
        for (const std::string& f : order) measure_group(fam[f], f, t);
      }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::printf("pce-accuracy%s: %d sample evaluations (each: 50-digit reference + 5 strategies), %zu rows, %.1f s\n",
              s.quick ? " --quick" : "", t.samples, t.rows.size(), seconds);
  std::printf(
      "rel_dist = ||P - P*||_F/||P*||_F, P* the nearest PSD matrix of the 50-digit Hessian at the rounded "
      "input; PSD violation: lambda_min < -n*eps*max|lambda| (float %.1e, double %.1e for n = 12)\n",
      psd_tolerance<float>(12), psd_tolerance<double>(12));
  print_tables(t);
  print_worst(t);
  int rc = 0;
  if (!s.out.empty() && !write_json(s.out, t, s)) {
    std::fprintf(stderr, "pce-accuracy: cannot write %s\n", s.out.c_str());
    rc = 1;
  }
  if (!s.csv.empty() && !write_csv(s.csv, t)) {
    std::fprintf(stderr, "pce-accuracy: cannot write %s\n", s.csv.c_str());
    rc = 1;
  }
  return rc;
}
