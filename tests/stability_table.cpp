// SPDX-License-Identifier: MIT
// Prints the measured stability table of docs/stability.md: for every hard-case family
// and severity (tests/support/hard_cases.hpp), the relative error of value, gradient and
// Hessian against the 50-digit reference, BEFORE (the paper's direct forms,
// tests/support/naive_forms.hpp) and AFTER (the library), next to the input-rounding bound.
// "NaN": the direct form produced NaN/Inf or divided by zero. "ok" is the library's
// pass/fail criterion (pce_test::passes, as tests/test_stability.cpp asserts it);
// "before ok" applies the same error criterion to the direct forms.
//
//   ./build/tests/pce-stability-table [double|float|long_double] [--condensed]   > table.md
//
// --condensed prints the table of docs/stability.md instead: a few representative
// severities per family, signed and unsigned side by side, cells "before / after (bound)".
#include "support/naive_forms.hpp"
#include "support/stability_measure.hpp"

#include <cstdio>
#include <cstring>
#include <set>
#include <string>
#include <vector>

namespace {
using namespace pce_test;

/// Errors of the direct forms, measured exactly as `measure` measures the library's: vs
/// the library in 50 digits at the same (rounded) input, and for an unsigned length within
/// rounding of 0 vs the nearer of its two one-sided derivatives.
struct Before {
  bool have_reference = false;
  bool value_ok = false, gradient_ok = false, hessian_ok = false;
  double value = 0, gradient = 0, hessian = 0;
};

template <class S> Before measure_before(const HardCase& hc, const Measurement& m) {
  Before b;
  const pce::Vec12<S> xs = cast12<S>(hc.x);
  const NaiveOutputs<S> nv = naive_pair_energy<S>(hc.pair, hc.length, hc.penalty, xs);
  b.value_ok = nv.value_ok;
  b.gradient_ok = nv.gradient_ok;
  b.hessian_ok = nv.hessian_ok;
  with_pair(hc.pair, [&](auto pair) {
    using Pair = decltype(pair);
    with_length(hc.length, [&](const auto& len) {
      with_penalty(hc.penalty, [&](const auto& pen) {
        const pce::Vec12<HighPrecision> y = cast12<HighPrecision>(xs);
        const Outputs ref = reference_outputs<Pair>(y, len, pen);
        if (ref.status != pce::Status::ok) return 0;
        b.have_reference = true;
        b.value = rel_scalar(static_cast<double>(nv.value), ref.value);
        b.gradient = rel_error(nv.gradient, ref.gradient, 1e-300);
        b.hessian = rel_error(nv.hessian, ref.hessian, 1e-300);
        if (m.sign_ambiguous) {
          pce::PairEnergy<HighPrecision> e;
          pce::pair_energy<Pair>(y, pce::SignedLength{}, pen, e);
          const pce::Side flipped = e.frame.l < 0 ? pce::Side::positive : pce::Side::negative;
          const Outputs alt = reference_outputs<Pair>(y, pce::SignedLength{flipped}, pen);
          if (alt.status == pce::Status::ok) {
            b.value = std::min(b.value, rel_scalar(static_cast<double>(nv.value), alt.value));
            b.gradient = std::min(b.gradient, rel_error(nv.gradient, alt.gradient, 1e-300));
            b.hessian = std::min(b.hessian, rel_error(nv.hessian, alt.hessian, 1e-300));
          }
        }
        return 0;
      });
      return 0;
    });
    return 0;
  });
  return b;
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1e", v);
  return buf;
}

std::string before_cell(bool have_reference, bool ok, double err) {
  if (!ok) return "NaN";
  return have_reference ? fmt(err) : "–";
}

/// The representative severities of the condensed table.
bool condensed_row(const HardCase& hc) {
  static const std::set<std::string> scale = {"1e-08", "1e+00", "1e+08"};
  static const std::set<std::string> angle = {"1e-02", "1e-08", "1e-12", "0"};
  static const std::set<std::string> delta = {"1e-02", "1e-08", "1e-16"};
  static const std::set<std::string> other = {"1e-02", "1e-08", "1e-14", "0"};
  if (hc.degenerate) return false;
  if (hc.family == "scale_vf" || hc.family == "scale_ee") return scale.count(hc.severity) > 0;
  if (hc.family == "ee_near_parallel" || hc.family == "vf_sliver") return angle.count(hc.severity) > 0;
  if (hc.family == "cubic_tiny_delta") return delta.count(hc.severity) > 0;
  if (hc.family.rfind("offset", 0) == 0) return true;
  return other.count(hc.severity) > 0;
}

struct Row {
  const HardCase* hc;
  Measurement m;
  Before b;
  bool ok, before_ok;
};

std::string after_cell(const Measurement& m, double err) { return m.status == pce::Status::ok ? fmt(err) : "–"; }
std::string bound_cell(const Measurement& m, double bound) {
  return m.reference_status == pce::Status::ok ? fmt(bound) : "–";
}

void print_full(const std::vector<Row>& rows) {
  std::printf(
      "| family | severity | length | status | value before | value after | value bound | gradient before | "
      "gradient after | gradient bound | Hessian before | Hessian after | Hessian bound | "
      "min PSD eig/max\\|eig\\| | before ok | ok |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const HardCase& hc = *r.hc;
    const Measurement& m = r.m;
    const Before& b = r.b;
    std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n",
                hc.family.c_str(), hc.severity.c_str(), name(hc.length), pce::to_string(m.status),
                before_cell(b.have_reference, b.value_ok, b.value).c_str(), after_cell(m, m.err_value).c_str(),
                bound_cell(m, m.bound_value).c_str(), before_cell(b.have_reference, b.gradient_ok, b.gradient).c_str(),
                after_cell(m, m.err_gradient).c_str(), bound_cell(m, m.bound_gradient).c_str(),
                before_cell(b.have_reference, b.hessian_ok, b.hessian).c_str(), after_cell(m, m.err_hessian).c_str(),
                bound_cell(m, m.bound_hessian).c_str(), after_cell(m, m.worst_psd).c_str(),
                hc.degenerate ? "–" : (r.before_ok ? "yes" : "no"), r.ok ? "yes" : "**no**");
  }
}

/// "before / after (bound)" for one output of one row.
std::string pair_cell(const Row& r, int which) {
  const Measurement& m = r.m;
  const Before& b = r.b;
  const bool ok[3] = {b.value_ok, b.gradient_ok, b.hessian_ok};
  const double before[3] = {b.value, b.gradient, b.hessian};
  const double after[3] = {m.err_value, m.err_gradient, m.err_hessian};
  const double bound[3] = {m.bound_value, m.bound_gradient, m.bound_hessian};
  return before_cell(b.have_reference, ok[which], before[which]) + " / " + after_cell(m, after[which]) + " (" +
         bound_cell(m, bound[which]) + ")";
}

/// One line per family and representative severity: signed and unsigned side by side.
void print_condensed(const std::vector<Row>& rows) {
  std::printf(
      "| family | severity | signed: value | signed: gradient | signed: Hessian | unsigned: value | "
      "unsigned: gradient | unsigned: Hessian |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    if (r.hc->length == LengthKind::unsigned_ || !condensed_row(*r.hc)) continue;
    const Row* u = nullptr;
    for (std::size_t j = i + 1; j < rows.size() && !u; ++j)
      if (rows[j].hc->length == LengthKind::unsigned_ && rows[j].hc->family == r.hc->family &&
          rows[j].hc->severity == r.hc->severity)
        u = &rows[j];
    std::printf("| %s | %s | %s | %s | %s | %s | %s | %s |\n", r.hc->family.c_str(), r.hc->severity.c_str(),
                pair_cell(r, 0).c_str(), pair_cell(r, 1).c_str(), pair_cell(r, 2).c_str(),
                u ? pair_cell(*u, 0).c_str() : "–", u ? pair_cell(*u, 1).c_str() : "–",
                u ? pair_cell(*u, 2).c_str() : "–");
  }
}

template <class S> int run(bool condensed) {
  const std::vector<HardCase> cases = hard_cases();
  std::vector<Row> rows;
  int bad = 0, bad_before = 0;
  for (const HardCase& hc : cases) {
    Row r{&hc, measure<S>(hc), {}, false, false};
    r.b = measure_before<S>(hc, r.m);
    r.ok = passes(hc, r.m);
    const double u = r.m.unit_roundoff;
    r.before_ok = !hc.degenerate && r.b.have_reference && r.b.value_ok && r.b.gradient_ok && r.b.hessian_ok &&
                  within(r.b.value, r.m.bound_value, u) && within(r.b.gradient, r.m.bound_gradient, u) &&
                  within(r.b.hessian, r.m.bound_hessian, u);
    bad += !r.ok;
    bad_before += !hc.degenerate && !r.before_ok;
    rows.push_back(r);
  }
  if (condensed)
    print_condensed(rows);
  else
    print_full(rows);
  std::fprintf(stderr,
               "%zu case(s); after: %d outside the bound; before: %d non-degenerate case(s) outside the bound or NaN\n",
               rows.size(), bad, bad_before);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const char* s = "double";
  bool condensed = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--condensed"))
      condensed = true;
    else
      s = argv[i];
  }
  if (!std::strcmp(s, "float")) return run<float>(condensed);
  if (!std::strcmp(s, "long_double")) return run<long double>(condensed);
  return run<double>(condensed);
}
