// SPDX-License-Identifier: MIT
// Tests for the pce-probe executable (what it promises: docs/probe.md and
// docs/conventions.md). Each test writes a JSON Lines file, runs the built probe on it through
// popen, and checks the answers: order, bit-exact agreement with the library after the
// text round trip, every projection and scalar name, every error status, the opt-in
// "mollifier" field, the point kinds (9 and 6 coordinates), the opt-in "closest_feature"
// field and the "exact" projection.
#include <pce/pce.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <regex>
#include <string>
#include <vector>

#ifndef PCE_PROBE_PATH
#error "PCE_PROBE_PATH must name the pce-probe executable"
#endif

namespace {

using nlohmann::json;
using X = std::array<double, 12>;

/// Output of one probe run.
struct ProbeRun {
  int exit_code = -1;
  std::string output;
  std::vector<std::string> lines;
};

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) {
      lines.push_back(text.substr(start));
      break;
    }
    lines.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

/// Runs the probe with `args` on `input` (through a temporary file).
ProbeRun run_probe(const std::string& input, const std::string& args = "") {
  char path[] = "/tmp/pce_probe_test_XXXXXX";
  const int fd = mkstemp(path);
  EXPECT_GE(fd, 0);
  EXPECT_EQ(write(fd, input.data(), input.size()), static_cast<ssize_t>(input.size()));
  close(fd);
  const std::string cmd = std::string("'") + PCE_PROBE_PATH + "' " + args + " < '" + path + "' 2>/dev/null";
  ProbeRun run;
  FILE* pipe = popen(cmd.c_str(), "r");
  EXPECT_NE(pipe, nullptr);
  if (pipe != nullptr) {
    char buf[4096];
    std::size_t n = 0;
    while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) run.output.append(buf, n);
    const int status = pclose(pipe);
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  unlink(path);
  run.lines = split_lines(run.output);
  return run;
}

/// JSON has no NaN or Inf; the probe must never print them (docs/probe.md).
void expect_no_nan_or_inf(const ProbeRun& run) {
  const std::regex bad(R"(\b(nan|inf|infinity)\b)", std::regex::icase);
  EXPECT_FALSE(std::regex_search(run.output, bad)) << run.output;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string coordinates(const X& x) {
  std::string s = "[";
  for (std::size_t i = 0; i < x.size(); ++i) s += (i ? "," : "") + number(x[i]);
  return s + "]";
}

/// One request line; `extra` is appended inside the object (e.g. `,"scalar":"float"`).
std::string request(const std::string& pair, const std::string& length, const std::string& penalty, const X& x,
                    const std::string& extra = "") {
  return R"({"pair":")" + pair + R"(","length":")" + length + R"(","penalty":)" + penalty + R"(,"x":)" +
         coordinates(x) + extra + "}\n";
}

const std::string quadratic = R"({"type":"quadratic","stiffness":3.5,"eps":0.25})";
const std::string log_barrier = R"({"type":"log_barrier","stiffness":2,"dhat":0.1})";

/// A vertex 0.1234… above a generic triangle (coordinates with many significant digits).
const X vertex_face_x = {
    0.3141592653589793, 0.2718281828459045, 0.12345678901234567, 0.01, -0.02, 0.003, 1.1, 0.1, -0.05, 0.2, 0.9, 0.07};
/// Two skew edges 0.05 apart.
const X edge_edge_x = {0, 0, 0, 1, 0.1, 0, 0.4, -0.5, 0.05, 0.6, 0.5, 0.05};
/// Two parallel edges.
const X parallel_x = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 1, 0};

/// The numbers of the array member `key` of a response line, parsed back with strtod.
std::vector<double> numbers_of(const std::string& line, const std::string& key) {
  std::vector<double> out;
  const std::string tag = "\"" + key + "\":[";
  const std::size_t at = line.find(tag);
  if (at == std::string::npos) return out;
  const char* p = line.c_str() + at + tag.size();
  while (*p != ']' && *p != '\0') {
    char* end = nullptr;
    out.push_back(std::strtod(p, &end));
    if (end == p) break;
    p = *end == ',' ? end + 1 : end;
  }
  return out;
}

/// The number member `key` of a response line, parsed back with strtod.
double number_of(const std::string& line, const std::string& key) {
  const std::string tag = "\"" + key + "\":";
  const std::size_t at = line.find(tag);
  return at == std::string::npos ? -1.0 : std::strtod(line.c_str() + at + tag.size(), nullptr);
}

std::uint64_t bits(double v) {
  std::uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

/// Bit-for-bit equality of printed numbers and library values (signed zeros included).
template <class Vector> void expect_same_bits(const std::vector<double>& printed, const Vector& lib, int n) {
  ASSERT_EQ(printed.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    EXPECT_EQ(bits(printed[static_cast<std::size_t>(i)]), bits(static_cast<double>(lib(i))))
        << "entry " << i << ": printed " << number(printed[static_cast<std::size_t>(i)]) << ", library "
        << number(static_cast<double>(lib(i)));
}

/// Row-major view of a 12×12 matrix as a flat index.
template <class Matrix> auto row_major(const Matrix& m) {
  return [&m](int i) { return m(i / 12, i % 12); };
}

template <class Scalar> pce::Vec12<Scalar> to_vec(const X& x) {
  pce::Vec12<Scalar> v;
  for (int i = 0; i < 12; ++i) v[i] = static_cast<Scalar>(x[static_cast<std::size_t>(i)]);
  return v;
}

json parsed(const std::string& line) { return json::parse(line); }

TEST(Probe, VertexFaceGradientMatchesLibraryBitForBit) {
  const ProbeRun run = run_probe(request("vertex_face", "signed", quadratic, vertex_face_x));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 1u);
  const std::string& line = run.lines[0];
  ASSERT_EQ(parsed(line)["status"], "ok") << line;

  pce::QuadraticPenalty pen;
  pen.stiffness = 3.5;
  pen.eps = 0.25;
  pce::PairEnergy<double> e;
  ASSERT_EQ(pce::pair_energy<pce::VertexFace>(to_vec<double>(vertex_face_x), pce::SignedLength{}, pen, e),
            pce::Status::ok);
  const pce::Vec12<double> g = pce::energy_gradient(e);
  expect_same_bits(
      numbers_of(line, "gradient"), [&g](int i) { return g[i]; }, 12);

  pce::PairResult<double> r;
  ASSERT_EQ(pce::evaluate<pce::VertexFace>(to_vec<double>(vertex_face_x), pce::SignedLength{}, pen,
                                           pce::Projection::analytic, r),
            pce::Status::ok);
  EXPECT_EQ(bits(number_of(line, "length")), bits(r.length));
  EXPECT_EQ(bits(number_of(line, "value")), bits(r.value));
  expect_same_bits(numbers_of(line, "hessian"), row_major(r.hessian), 144);
  expect_same_bits(numbers_of(line, "projected_hessian"), row_major(r.projected_hessian), 144);
  expect_same_bits(
      numbers_of(line, "eigenvalues"), [&r](int i) { return r.eigen.values[i]; }, 9);
}

TEST(Probe, FloatEdgeEdgeMatchesLibraryBitForBit) {
  const ProbeRun run = run_probe(request("edge_edge", "unsigned", quadratic, edge_edge_x,
                                         R"(,"scalar":"float","projection":"numerical","side":-1)"));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 1u);
  const std::string& line = run.lines[0];
  ASSERT_EQ(parsed(line)["status"], "ok") << line;
  pce::QuadraticPenalty pen;
  pen.stiffness = 3.5;
  pen.eps = 0.25;
  pce::PairResult<float> r;
  ASSERT_EQ(pce::evaluate<pce::EdgeEdge>(to_vec<float>(edge_edge_x), pce::UnsignedLength{}, pen,
                                         pce::Projection::numerical, r),
            pce::Status::ok);
  expect_same_bits(
      numbers_of(line, "gradient"), [&r](int i) { return r.gradient[i]; }, 12);
  expect_same_bits(numbers_of(line, "projected_hessian"), row_major(r.projected_hessian), 144);
}

TEST(Probe, EveryProjectionAndScalarIsAcceptedInOrder) {
  const char* projections[] = {"analytic", "numerical", "gauss_newton", "abs", "none"};
  const char* scalars[] = {"double", "float", "long_double"};
  std::string input;
  int id = 0;
  for (const char* p : projections)
    for (const char* s : scalars)
      input +=
          request("vertex_face", "signed", quadratic, vertex_face_x,
                  std::string(R"(,"projection":")") + p + R"(","scalar":")" + s + R"(","id":)" + std::to_string(id++));
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 15u);
  id = 0;
  for (const char* p : projections)
    for (const char* s : scalars) {
      const std::string& line = run.lines[static_cast<std::size_t>(id)];
      const json r = parsed(line);
      EXPECT_EQ(r["status"], "ok") << line;
      EXPECT_EQ(r["id"], id++);
      EXPECT_EQ(r["projection"], p);
      EXPECT_EQ(r["scalar"], s);
      EXPECT_EQ(r["gradient"].size(), 12u);
      EXPECT_EQ(r["hessian"].size(), 144u);
      EXPECT_EQ(r["projected_hessian"].size(), 144u);
      EXPECT_EQ(r["eigenvalues"].size(), 9u);
    }
}

TEST(Probe, MalformedLineGetsErrorAndNextLineIsAnswered) {
  const std::string input = request("vertex_face", "signed", quadratic, vertex_face_x, R"(,"id":"a")") +
                            "{\"pair\": not json\n" +
                            request("vertex_face", "signed", quadratic, vertex_face_x, R"(,"id":"c")");
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 3u);
  EXPECT_EQ(parsed(run.lines[0])["id"], "a");
  const json bad = parsed(run.lines[1]);
  EXPECT_EQ(bad["status"], "invalid_request");
  EXPECT_TRUE(bad["message"].is_string());
  EXPECT_EQ(parsed(run.lines[2])["status"], "ok");
  EXPECT_EQ(parsed(run.lines[2])["id"], "c");
}

TEST(Probe, BlankLinesAreSkipped) {
  const std::string ok = request("vertex_face", "signed", quadratic, vertex_face_x);
  const ProbeRun run = run_probe("\n   \n" + ok + "\t\r\n\n" + ok);
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_EQ(run.lines.size(), 2u);
}

TEST(Probe, HugeCoordinatesAreInvalidInput) {
  X huge = vertex_face_x;
  huge[4] = 1e300;
  const std::string beyond_double = R"({"pair":"vertex_face","length":"signed","penalty":)" + quadratic +
                                    R"(,"x":[0,0,1e400,0,0,0,1,0,0,0,1,0]})" + "\n";
  const ProbeRun run = run_probe(request("vertex_face", "signed", quadratic, huge) + beyond_double);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 2u);
  for (const std::string& line : run.lines) {
    const json r = parsed(line);
    EXPECT_EQ(r["status"], "invalid_input") << line;
    EXPECT_NE(r["message"].get<std::string>().find("\"x\""), std::string::npos) << line;
  }
}

TEST(Probe, LogBarrierAtNegativeLengthIsOutOfDomain) {
  X below = vertex_face_x;
  below[2] = -0.05;
  const ProbeRun run = run_probe(request("vertex_face", "signed", log_barrier, below));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 1u);
  const json r = parsed(run.lines[0]);
  EXPECT_EQ(r["status"], "out_of_domain");
  EXPECT_FALSE(r.contains("gradient"));
  EXPECT_NE(r["message"].get<std::string>().find("L <= 0"), std::string::npos);
}

TEST(Probe, ParallelEdgesAreDegenerate) {
  const ProbeRun run = run_probe(request("edge_edge", "signed", quadratic, parallel_x));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 1u);
  EXPECT_EQ(parsed(run.lines[0])["status"], "degenerate");
}

TEST(Probe, MalformedFieldsAreInvalidRequestNamingTheField) {
  const std::string head = R"({"pair":"vertex_face","length":"signed","penalty":)";
  const std::string tail = R"(,"x":[0,0,1,0,0,0,1,0,0,0,1,0]})";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {head + quadratic + R"(,"x":[0,0,1,0,0,0,1,0,0,0,1]})", "\"x\""},
      {head + quadratic + R"(,"x":[0,0,1,0,null,0,1,0,0,0,1,0]})", "\"x\"[4]"},
      {head + R"({"type":"quadratic","stiffness":1})" + tail, "penalty.eps"},
      {head + R"({"type":"spring","stiffness":1})" + tail, "penalty.type"},
      {head + quadratic + R"(,"side":0)" + tail, "side"},
      {head + quadratic + R"(,"projection":"nearest")" + tail, "projection"},
      {head + quadratic + R"(,"scalar":"half")" + tail, "scalar"},
      {R"({"pair":"point_point","length":"signed","penalty":)" + quadratic + tail, "pair"},
  };
  std::string input;
  for (const auto& c : cases) input += c.first + "\n";
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const json r = parsed(run.lines[i]);
    EXPECT_EQ(r["status"], "invalid_request") << run.lines[i];
    EXPECT_NE(r["message"].get<std::string>().find(cases[i].second), std::string::npos) << run.lines[i];
  }
}

TEST(Probe, IdIsEchoedOnSuccessAndOnErrors) {
  const ProbeRun run =
      run_probe(request("vertex_face", "signed", quadratic, vertex_face_x, R"(,"id":{"case":[1,"two"]})") +
                request("edge_edge", "signed", quadratic, parallel_x, R"(,"id":"p")"));
  ASSERT_EQ(run.lines.size(), 2u);
  EXPECT_EQ(parsed(run.lines[0])["id"], json::parse(R"({"case":[1,"two"]})"));
  EXPECT_EQ(parsed(run.lines[1])["id"], "p");
}

TEST(Probe, OutputNeverContainsNanOrInf) {
  X below = vertex_face_x;
  below[2] = -0.05;
  X huge = vertex_face_x;
  huge[0] = 1e300;
  std::string input;
  for (const char* s : {"double", "float", "long_double"}) {
    const std::string extra = std::string(R"(,"scalar":")") + s + "\"";
    input += request("vertex_face", "signed", quadratic, vertex_face_x, extra);
    input += request("vertex_face", "signed", log_barrier, below, extra);
    input += request("vertex_face", "signed", quadratic, huge, extra);
    input += request("edge_edge", "unsigned", log_barrier, edge_edge_x, extra);
    input += request("edge_edge", "signed", quadratic, parallel_x, extra);
  }
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  EXPECT_EQ(run.lines.size(), 15u);
  expect_no_nan_or_inf(run);
  for (const std::string& line : run.lines) EXPECT_NO_THROW(static_cast<void>(parsed(line))) << line;
}

// ---- Opt-in mollified energy (request field "mollifier") ----

/// Two edges 0.05 apart at an angle of about 0.01 rad: X = |e0 × e1|² = 1e-4.
const X nearly_parallel_x = {0, 0, 0, 1, 0.01, 0, 0, 0, 0.05, 1, 0, 0.05};
/// A vertex 0.1 above a sliver triangle: X = 1e-4.
const X sliver_x = {0.5, 0.005, 0.1, 0, 0, 0, 1, 0, 0, 0.5, 0.01, 0};
/// A vertex above a zero-area (collinear) triangle.
const X flat_x = {0.2, 0.3, 1, 0, 0, 0, 1, 0, 0, 2, 0, 0};

std::string mollifier_threshold(double threshold) { return R"(,"mollifier":{"threshold":)" + number(threshold) + "}"; }

/// The mollified response line with its extra members removed.
std::string without_mollifier_fields(const std::string& line) {
  static const std::regex extra(R"(,"mollified":true,"mollifier":1,"mollifier_threshold":[^,]*)");
  return std::regex_replace(line, extra, "");
}

TEST(ProbeMollifier, AboveTheThresholdEqualsThePlainResponseFieldByField) {
  const char* projections[] = {"analytic", "numerical", "gauss_newton", "abs", "none"};
  const char* scalars[] = {"double", "float", "long_double"};
  struct Case {
    std::string pair, length, penalty;
    X x;
  };
  const Case cases[] = {{"vertex_face", "signed", quadratic, vertex_face_x},
                        {"edge_edge", "unsigned", log_barrier, edge_edge_x}};
  std::string input;
  int n = 0;
  for (const Case& c : cases)
    for (const char* p : projections)
      for (const char* s : scalars) {
        const std::string extra = std::string(R"(,"projection":")") + p + R"(","scalar":")" + s + "\"";
        input += request(c.pair, c.length, c.penalty, c.x, extra);
        input += request(c.pair, c.length, c.penalty, c.x, extra + mollifier_threshold(1e-9));
        input += request(c.pair, c.length, c.penalty, c.x,
                         extra + R"(,"mollifier":{"rest":)" + coordinates(c.x) + R"(,"factor":1e-6})");
        n += 3;
      }
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < run.lines.size(); i += 3) {
    const std::string& plain = run.lines[i];
    ASSERT_EQ(parsed(plain)["status"], "ok") << plain;
    for (std::size_t k = 1; k <= 2; ++k) {
      const std::string& mollified = run.lines[i + k];
      const json m = parsed(mollified);
      EXPECT_EQ(m["status"], "ok") << mollified;
      EXPECT_EQ(m["mollified"], true) << mollified;
      EXPECT_EQ(m["mollifier"], 1) << mollified;
      EXPECT_TRUE(m.contains("length")) << mollified;
      // Every other member, as text: the same numbers bit for bit, in the same order.
      EXPECT_EQ(without_mollifier_fields(mollified), plain);
    }
  }
}

TEST(ProbeMollifier, InTheBandTheEnergyIsReducedAndMatchesTheLibraryBitForBit) {
  pce::QuadraticPenalty pen;
  pen.stiffness = 3.5;
  pen.eps = 0.25;
  const std::string rest_form = R"(,"mollifier":{"rest":)" + coordinates(nearly_parallel_x) + "}";
  const ProbeRun run = run_probe(request("edge_edge", "unsigned", quadratic, nearly_parallel_x) +
                                 request("edge_edge", "unsigned", quadratic, nearly_parallel_x, rest_form) +
                                 request("vertex_face", "signed", quadratic, sliver_x) +
                                 request("vertex_face", "signed", quadratic, sliver_x, mollifier_threshold(1e-3)));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 4u);

  const auto check = [&](const std::string& plain, const std::string& line, auto pair, const X& x, const auto& length,
                         double threshold) {
    using Pair = decltype(pair);
    const json p = parsed(plain), m = parsed(line);
    ASSERT_EQ(p["status"], "ok") << plain;
    ASSERT_EQ(m["status"], "ok") << line;
    EXPECT_EQ(m["mollified"], true);
    const double mol = m["mollifier"].get<double>();
    EXPECT_GT(mol, 0.0);
    EXPECT_LT(mol, 1.0);
    EXPECT_GT(m["value"].get<double>(), 0.0);
    EXPECT_LT(m["value"].get<double>(), p["value"].get<double>());
    EXPECT_EQ(bits(number_of(line, "mollifier_threshold")), bits(threshold));

    pce::Mollifier mollifier;
    mollifier.threshold = threshold;
    pce::MollifiedEnergy<double> e;
    ASSERT_EQ(pce::mollified_pair_energy<Pair>(to_vec<double>(x), length, pen, mollifier, e), pce::Status::ok);
    ASSERT_TRUE(e.has_frame);
    EXPECT_EQ(bits(number_of(line, "mollifier")), bits(e.mollifier));
    EXPECT_EQ(bits(number_of(line, "length")), bits(e.base.length));
    EXPECT_EQ(bits(number_of(line, "length")), bits(number_of(plain, "length")));
    EXPECT_EQ(bits(number_of(line, "value")), bits(e.value));
    const pce::Vec12<double> g = pce::energy_gradient(e);
    expect_same_bits(
        numbers_of(line, "gradient"), [&g](int i) { return g[i]; }, 12);
    const pce::Mat12<double> h = pce::energy_hessian(e);
    expect_same_bits(numbers_of(line, "hessian"), row_major(h), 144);
    const pce::Mat12<double> ph = pce::projected_hessian(e, pce::Projection::analytic);
    expect_same_bits(numbers_of(line, "projected_hessian"), row_major(ph), 144);
    const pce::FrameEigensystem<double> es = pce::energy_eigensystem(e);
    expect_same_bits(
        numbers_of(line, "eigenvalues"), [&es](int i) { return es.values[i]; }, 9);
  };
  // Rest form with the default factor 1e-3: X̂ = 1e-3 |e0|²|e1|².
  check(run.lines[0], run.lines[1], pce::EdgeEdge{}, nearly_parallel_x, pce::UnsignedLength{},
        pce::mollifier_threshold<pce::EdgeEdge>(to_vec<double>(nearly_parallel_x)));
  check(run.lines[2], run.lines[3], pce::VertexFace{}, sliver_x, pce::SignedLength{}, 1e-3);
}

TEST(ProbeMollifier, ExactlyDegenerateIsOkWithZerosWhilePlainIsDegenerate) {
  const char* projections[] = {"analytic", "numerical", "gauss_newton", "abs", "none"};
  const char* scalars[] = {"double", "float", "long_double"};
  std::string input;
  int n = 0;
  for (const char* p : projections)
    for (const char* s : scalars) {
      const std::string extra = std::string(R"(,"projection":")") + p + R"(","scalar":")" + s + "\"";
      input += request("edge_edge", "signed", quadratic, parallel_x, extra);
      input += request("edge_edge", "signed", quadratic, parallel_x, extra + mollifier_threshold(1e-3));
      input += request("vertex_face", "signed", log_barrier, flat_x, extra);
      input += request("vertex_face", "signed", log_barrier, flat_x, extra + mollifier_threshold(1e-3));
      n += 4;
    }
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < run.lines.size(); i += 2) {
    EXPECT_EQ(parsed(run.lines[i])["status"], "degenerate") << run.lines[i];
    const std::string& line = run.lines[i + 1];
    const json m = parsed(line);
    ASSERT_EQ(m["status"], "ok") << line;
    EXPECT_EQ(m["mollified"], true);
    EXPECT_EQ(m["mollifier"], 0);
    EXPECT_FALSE(m.contains("length")) << line;  // no frame: L is undefined
    EXPECT_EQ(m["value"], 0);
    const std::pair<const char*, std::size_t> arrays[] = {
        {"gradient", 12}, {"hessian", 144}, {"projected_hessian", 144}, {"eigenvalues", 9}};
    for (const auto& a : arrays) {
      ASSERT_EQ(m[a.first].size(), a.second) << a.first;
      for (const json& v : m[a.first]) EXPECT_EQ(v, 0) << a.first << ": " << line;
    }
  }
}

TEST(ProbeMollifier, BadMollifierFieldsAreInvalidRequestNamingTheField) {
  const std::string head = R"({"pair":"edge_edge","length":"signed","penalty":)" + quadratic +
                           R"(,"x":[0,0,0,1,0,0,0,1,0,2,1,0],"mollifier":)";
  const std::string rest = "[0,0,0,1,0,0,0,1,0,0,2,0]";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{}", "mollifier.threshold"},
      {R"({"factor":1e-3})", "mollifier.threshold"},
      {R"({"threshold":0})", "mollifier.threshold"},
      {R"({"threshold":-1})", "mollifier.threshold"},
      {R"({"threshold":-0})", "mollifier.threshold"},
      {R"({"threshold":1e400})", "mollifier.threshold"},
      {R"({"threshold":"1e-3"})", "mollifier.threshold"},
      {R"({"threshold":null})", "mollifier.threshold"},
      {R"({"threshold":1e-3,"rest":)" + rest + "}", "mollifier.rest"},
      {R"({"threshold":1e-3,"factor":1e-3})", "mollifier.factor"},
      {R"({"rest":[0,0,0,1,0,0,0,1,0,0,2]})", "mollifier.rest"},
      {R"({"rest":[0,0,0,1,0,0,0,1,0,0,2,"a"]})", "mollifier.rest\"[11]"},
      {R"({"rest":[0,0,0,1,0,0,0,1,0,0,2,1e400]})", "mollifier.rest\"[11]"},
      {R"({"rest":"none"})", "mollifier.rest"},
      {R"({"rest":[0,0,0,0,0,0,0,1,0,0,2,0]})", "mollifier.rest"},  // zero-length rest edge: X̂ = 0
      {R"({"rest":)" + rest + R"(,"factor":0})", "mollifier.factor"},
      {R"({"rest":)" + rest + R"(,"factor":-1e-3})", "mollifier.factor"},
      {R"({"rest":)" + rest + R"(,"factor":true})", "mollifier.factor"},
      {"1e-3", "\"mollifier\""},
      {"null", "\"mollifier\""},
  };
  std::string input;
  for (const auto& c : cases) input += head + c.first + "}\n";
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const json r = parsed(run.lines[i]);
    EXPECT_EQ(r["status"], "invalid_request") << run.lines[i];
    EXPECT_NE(r["message"].get<std::string>().find(cases[i].second), std::string::npos)
        << cases[i].first << " -> " << run.lines[i];
  }
}

TEST(ProbeMollifier, ThresholdBeyondTheScalarRangeIsInvalidInput) {
  const ProbeRun run = run_probe(
      request("vertex_face", "signed", quadratic, vertex_face_x, R"(,"scalar":"float")" + mollifier_threshold(1e300)) +
      request("vertex_face", "signed", quadratic, vertex_face_x, R"(,"scalar":"float")" + mollifier_threshold(1e-300)) +
      request("vertex_face", "signed", quadratic, vertex_face_x, mollifier_threshold(1e300)));
  ASSERT_EQ(run.lines.size(), 3u);
  for (std::size_t i = 0; i < 2; ++i) {
    const json r = parsed(run.lines[i]);
    EXPECT_EQ(r["status"], "invalid_input") << run.lines[i];
    EXPECT_NE(r["message"].get<std::string>().find("mollifier.threshold"), std::string::npos) << run.lines[i];
  }
  const json r = parsed(run.lines[2]);  // in double, X ≪ X̂: m is tiny but the request is valid
  EXPECT_EQ(r["status"], "ok") << run.lines[2];
  EXPECT_GE(r["mollifier"].get<double>(), 0.0);
  EXPECT_LT(r["mollifier"].get<double>(), 1e-200);
}

TEST(ProbeMollifier, OutputNeverContainsNanOrInf) {
  // X ≈ 1e-300, far inside the band (exactly parallel once rounded to float).
  const X tiny_angle = {0, 0, 0, 1, 0, 0, 0, 0, 0.05, 2, 1e-150, 0.05};
  // X ≈ 1e-30 (also in float).
  const X small_angle = {0, 0, 0, 1, 0, 0, 0, 0, 0.05, 2, 1e-15, 0.05};
  X below = vertex_face_x;
  below[2] = -0.05;
  std::string input;
  for (const char* s : {"double", "float", "long_double"})
    for (const char* p : {"analytic", "numerical", "none"}) {
      const std::string extra =
          std::string(R"(,"scalar":")") + s + R"(","projection":")" + p + "\"" + mollifier_threshold(1e-3);
      input += request("edge_edge", "signed", quadratic, tiny_angle, extra);
      input += request("edge_edge", "signed", quadratic, small_angle, extra);
      input += request("edge_edge", "unsigned", log_barrier, edge_edge_x, extra);
      input += request("edge_edge", "signed", quadratic, parallel_x, extra);
      input += request("vertex_face", "signed", log_barrier, below, extra);
      input += request("vertex_face", "signed", quadratic, flat_x, extra);
    }
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  EXPECT_EQ(run.lines.size(), 54u);
  expect_no_nan_or_inf(run);
  for (const std::string& line : run.lines) {
    json r;
    ASSERT_NO_THROW(r = parsed(line)) << line;
    if (r["status"] != "ok") continue;
    EXPECT_GE(r["mollifier"].get<double>(), 0.0) << line;
    EXPECT_LE(r["mollifier"].get<double>(), 1.0) << line;
  }
}

// ---- Point kinds, closest-feature evaluation and Projection::exact ----

using Coordinates = std::vector<double>;

std::string coordinates(const Coordinates& x) {
  std::string s = "[";
  for (std::size_t i = 0; i < x.size(); ++i) s += (i ? "," : "") + number(x[i]);
  return s + "]";
}

/// One request line with any number of coordinates.
std::string request(const std::string& pair, const std::string& length, const std::string& penalty,
                    const Coordinates& x, const std::string& extra = "") {
  return R"({"pair":")" + pair + R"(","length":")" + length + R"(","penalty":)" + penalty + R"(,"x":)" +
         coordinates(x) + extra + "}\n";
}

template <class Scalar, int N> pce::VecN<Scalar, N> to_vec(const Coordinates& x) {
  pce::VecN<Scalar, N> v;
  for (int i = 0; i < N; ++i) v[i] = static_cast<Scalar>(x.at(static_cast<std::size_t>(i)));
  return v;
}

/// Row-major view of an n×n matrix as a flat index.
template <class Matrix> auto row_major(const Matrix& m, int n) {
  return [&m, n](int i) { return m(i / n, i % n); };
}

/// Quadratic penalty active up to L = 2 (every pair below is closer than that).
const std::string wide_quadratic = R"({"type":"quadratic","stiffness":3.5,"eps":2})";

pce::QuadraticPenalty wide_quadratic_penalty() {
  pce::QuadraticPenalty pen;
  pen.stiffness = 3.5;
  pen.eps = 2;
  return pen;
}

/// A point 0.5 from the line through e0, e1 (the x axis): p − foot = (0, 0.3, 0.4), the
/// foot (0.5, 0, 0) in the middle of the edge.
const Coordinates point_edge_x = {0.5, 0.3, 0.4, -1, 0, 0, 2, 0, 0};
/// Two points 0.5 apart: p − q = (0, −0.3, −0.4).
const Coordinates point_point_x = {1, 2, 3, 1, 2.3, 3.4};
/// A vertex beyond the corner t0 of the unit right triangle: p − t0 = (−0.3, −0.4, 1.2), |·| = 1.3.
const X beyond_corner_x = {-0.3, -0.4, 1.2, 0, 0, 0, 1, 0, 0, 0, 1, 0};

/// The ok response of `line` checked against `pce::evaluate<Pair>` bit for bit, with the
/// sizes of the pair kind (Dofs gradient entries, Dofs² Hessian entries, FrameDofs eigenvalues).
template <class Pair>
void expect_matches_evaluate(const std::string& line, const Coordinates& x, pce::Projection projection) {
  constexpr int n = Pair::dofs;
  const json r = parsed(line);
  ASSERT_EQ(r["status"], "ok") << line;
  EXPECT_EQ(r["gradient"].size(), static_cast<std::size_t>(n));
  EXPECT_EQ(r["hessian"].size(), static_cast<std::size_t>(n * n));
  EXPECT_EQ(r["projected_hessian"].size(), static_cast<std::size_t>(n * n));
  EXPECT_EQ(r["eigenvalues"].size(), static_cast<std::size_t>(Pair::frame_dofs));
  EXPECT_FALSE(r.contains("feature")) << line;
  pce::PairResult<double, Pair::dofs, Pair::frame_dofs> lib;
  ASSERT_EQ(pce::evaluate<Pair>(to_vec<double, n>(x), pce::UnsignedLength{}, wide_quadratic_penalty(), projection, lib),
            pce::Status::ok);
  EXPECT_EQ(bits(number_of(line, "length")), bits(lib.length));
  EXPECT_EQ(bits(number_of(line, "value")), bits(lib.value));
  expect_same_bits(
      numbers_of(line, "gradient"), [&lib](int i) { return lib.gradient[i]; }, n);
  expect_same_bits(numbers_of(line, "hessian"), row_major(lib.hessian, n), n * n);
  expect_same_bits(numbers_of(line, "projected_hessian"), row_major(lib.projected_hessian, n), n * n);
  expect_same_bits(
      numbers_of(line, "eigenvalues"), [&lib](int i) { return lib.eigen.values[i]; }, Pair::frame_dofs);
}

TEST(ProbePointKinds, PointEdgeHasTheLineDistanceAndNineCoordinates) {
  const ProbeRun run = run_probe(request("point_edge", "unsigned", wide_quadratic, point_edge_x) +
                                 request("point_edge", "unsigned", wide_quadratic, point_edge_x,
                                         R"(,"projection":"numerical","scalar":"long_double")"));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 2u);
  const std::string& line = run.lines[0];
  const json r = parsed(line);
  ASSERT_EQ(r["status"], "ok") << line;
  EXPECT_NEAR(r["length"].get<double>(), 0.5, 1e-15);
  // ψ = 3.5 (0.5 − 2)², ψ′ = 7 (0.5 − 2) = −10.5: ∇_p E = ψ′ û = −10.5 (0, 0.6, 0.8), and
  // with the foot in the middle of the edge e0 and e1 each get half of −∇_p E.
  EXPECT_NEAR(r["value"].get<double>(), 3.5 * 1.5 * 1.5, 1e-13);
  const double expected[9] = {0, -6.3, -8.4, 0, 3.15, 4.2, 0, 3.15, 4.2};
  ASSERT_EQ(r["gradient"].size(), 9u);
  for (std::size_t i = 0; i < 9; ++i) EXPECT_NEAR(r["gradient"][i].get<double>(), expected[i], 1e-13) << i;
  EXPECT_EQ(r["hessian"].size(), 81u);
  EXPECT_EQ(r["projected_hessian"].size(), 81u);
  EXPECT_EQ(r["eigenvalues"].size(), 6u);
  expect_matches_evaluate<pce::PointEdge>(line, point_edge_x, pce::Projection::analytic);
  const json ld = parsed(run.lines[1]);
  ASSERT_EQ(ld["status"], "ok") << run.lines[1];
  EXPECT_EQ(ld["scalar"], "long_double");
  EXPECT_NEAR(ld["length"].get<double>(), 0.5, 1e-15);
  EXPECT_EQ(ld["eigenvalues"].size(), 6u);
}

TEST(ProbePointKinds, PointPointHasSixCoordinatesAndThreeEigenvalues) {
  const ProbeRun run = run_probe(request("point_point", "unsigned", wide_quadratic, point_point_x));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 1u);
  const std::string& line = run.lines[0];
  const json r = parsed(line);
  ASSERT_EQ(r["status"], "ok") << line;
  EXPECT_NEAR(r["length"].get<double>(), 0.5, 1e-15);
  // ψ = 3.5 (0.5 − 2)², ψ′ = 7 (0.5 − 2) = −10.5, ψ″ = 7; ∇_p E = ψ′ (p − q)/d, ∇_q E = −∇_p E.
  EXPECT_NEAR(r["value"].get<double>(), 3.5 * 1.5 * 1.5, 1e-13);
  const double expected[6] = {0, 6.3, 8.4, 0, -6.3, -8.4};
  ASSERT_EQ(r["gradient"].size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(r["gradient"][i].get<double>(), expected[i], 1e-13) << i;
  EXPECT_EQ(r["hessian"].size(), 36u);
  EXPECT_EQ(r["projected_hessian"].size(), 36u);
  // Frame eigenvalues ψ′/d (twice, across) and ψ″ (along), ascending.
  ASSERT_EQ(r["eigenvalues"].size(), 3u);
  EXPECT_NEAR(r["eigenvalues"][0].get<double>(), -21.0, 1e-12);
  EXPECT_NEAR(r["eigenvalues"][1].get<double>(), -21.0, 1e-12);
  EXPECT_NEAR(r["eigenvalues"][2].get<double>(), 7.0, 1e-12);
  expect_matches_evaluate<pce::PointPoint>(line, point_point_x, pce::Projection::analytic);
}

TEST(ProbePointKinds, EveryProjectionAndScalarWorksAndExactIsTheNearestPsdMatrix) {
  const char* projections[] = {"analytic", "numerical", "exact", "gauss_newton", "abs", "none"};
  const char* scalars[] = {"double", "float", "long_double"};
  struct Case {
    const char* pair;
    Coordinates x;
    std::size_t n, eigen;
  };
  // Closer than eps, so that the exact Hessians are indefinite.
  const Case cases[] = {{"point_edge", point_edge_x, 9, 6}, {"point_point", point_point_x, 6, 3}};
  std::string input;
  for (const Case& c : cases)
    for (const char* p : projections)
      for (const char* s : scalars)
        input += request(c.pair, "unsigned", wide_quadratic, c.x,
                         std::string(R"(,"projection":")") + p + R"(","scalar":")" + s + "\"");
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 36u);
  expect_no_nan_or_inf(run);
  std::size_t i = 0;
  for (const Case& c : cases)
    for (const char* p : projections)
      for (const char* s : scalars) {
        const json r = parsed(run.lines[i++]);
        ASSERT_EQ(r["status"], "ok") << run.lines[i - 1];
        EXPECT_EQ(r["projection"], p);
        EXPECT_EQ(r["scalar"], s);
        EXPECT_EQ(r["gradient"].size(), c.n);
        EXPECT_EQ(r["projected_hessian"].size(), c.n * c.n);
        EXPECT_EQ(r["eigenvalues"].size(), c.eigen);
      }
  // In double: "exact" equals "numerical" (both the nearest PSD matrix) and differs from
  // the exact Hessian ("none"), which is indefinite here.
  for (std::size_t k = 0; k < 2; ++k) {
    const std::size_t base = k * 18;
    const std::vector<double> numerical = numbers_of(run.lines[base + 3], "projected_hessian");
    const std::vector<double> exact = numbers_of(run.lines[base + 6], "projected_hessian");
    const std::vector<double> none = numbers_of(run.lines[base + 15], "projected_hessian");
    ASSERT_EQ(exact.size(), numerical.size());
    double scale = 0, diff = 0, from_none = 0;
    for (std::size_t j = 0; j < exact.size(); ++j) {
      scale = std::max(scale, std::abs(numerical[j]));
      diff = std::max(diff, std::abs(exact[j] - numerical[j]));
      from_none = std::max(from_none, std::abs(exact[j] - none[j]));
    }
    EXPECT_LE(diff, 1e-12 * scale) << cases[k].pair;
    EXPECT_GT(from_none, 1e-3 * scale) << cases[k].pair;
  }
}

TEST(ProbePointKinds, ZeroDistanceIsDegenerate) {
  const ProbeRun run =
      run_probe(request("point_point", "unsigned", wide_quadratic, Coordinates{1, 2, 3, 1, 2, 3}) +
                request("point_edge", "unsigned", wide_quadratic, Coordinates{0.5, 0, 0, -1, 0, 0, 2, 0, 0}) +
                request("point_edge", "unsigned", wide_quadratic, Coordinates{0.5, 1, 0, 1, 1, 1, 1, 1, 1}));
  ASSERT_EQ(run.lines.size(), 3u);
  for (const std::string& line : run.lines) {
    const json r = parsed(line);
    EXPECT_EQ(r["status"], "degenerate") << line;
    EXPECT_FALSE(r.contains("gradient")) << line;
  }
  EXPECT_NE(parsed(run.lines[0])["message"].get<std::string>().find("coincident"), std::string::npos);
  EXPECT_NE(parsed(run.lines[2])["message"].get<std::string>().find("zero-length edge"), std::string::npos);
}

TEST(ProbePointKinds, BadRequestsAreInvalidRequestNamingTheField) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {request("point_edge", "signed", wide_quadratic, point_edge_x), "\"length\""},
      {request("point_point", "signed", wide_quadratic, point_point_x, R"(,"side":-1)"), "\"length\""},
      {request("point_edge", "unsigned", wide_quadratic, point_point_x), "\"x\" must have 9 numbers"},
      {request("point_edge", "unsigned", wide_quadratic, vertex_face_x), "\"x\" must have 9 numbers"},
      {request("point_point", "unsigned", wide_quadratic, point_edge_x), "\"x\" must have 6 numbers"},
      {request("vertex_face", "unsigned", wide_quadratic, point_edge_x), "\"x\" must have 12 numbers, got 9"},
      {request("edge_edge", "unsigned", wide_quadratic, point_point_x), "\"x\" must have 12 numbers, got 6"},
      {request("point_point", "unsigned", wide_quadratic, point_point_x, mollifier_threshold(1e-3)), "\"mollifier\""},
      {request("point_edge", "unsigned", wide_quadratic, point_edge_x, R"(,"closest_feature":true)"),
       "\"closest_feature\""},
      {request("point_triangle", "unsigned", wide_quadratic, point_point_x), "\"pair\""},
  };
  std::string input;
  for (const auto& c : cases) input += c.first;
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const json r = parsed(run.lines[i]);
    EXPECT_EQ(r["status"], "invalid_request") << run.lines[i];
    EXPECT_NE(r["message"].get<std::string>().find(cases[i].second), std::string::npos) << run.lines[i];
  }
}

/// The library's closest-feature evaluation of a 12-coordinate candidate (double).
template <class Pair> pce::ClosestFeatureEnergy<double> closest_feature(const X& x) {
  pce::ClosestFeatureEnergy<double> e;
  EXPECT_EQ(pce::closest_feature_energy<Pair>(to_vec<double>(x), pce::UnsignedLength{}, wide_quadratic_penalty(), e),
            pce::Status::ok);
  return e;
}

/// The ok closest-feature response `line` checked against the library bit for bit.
void expect_matches_closest_feature(const std::string& line, const pce::ClosestFeatureEnergy<double>& e,
                                    pce::Projection projection) {
  const json r = parsed(line);
  ASSERT_EQ(r["status"], "ok") << line;
  EXPECT_EQ(r["feature"], pce::to_string(e.feature));
  EXPECT_EQ(bits(number_of(line, "length")), bits(e.length));
  EXPECT_EQ(bits(number_of(line, "value")), bits(e.psi.value));
  const pce::Vec12<double> g = pce::energy_gradient(e);
  expect_same_bits(
      numbers_of(line, "gradient"), [&g](int i) { return g[i]; }, 12);
  const pce::Mat12<double> h = pce::energy_hessian(e);
  expect_same_bits(numbers_of(line, "hessian"), row_major(h), 144);
  const pce::Mat12<double> ph = pce::projected_hessian(e, projection);
  expect_same_bits(numbers_of(line, "projected_hessian"), row_major(ph), 144);
  const auto ev = pce::feature_eigenvalues(e);
  expect_same_bits(
      numbers_of(line, "eigenvalues"), [&ev](int i) { return ev.values[i]; }, ev.count);
}

TEST(ProbeClosestFeature, VertexBeyondACornerIsPointPointOnAllTwelveCoordinates) {
  const ProbeRun run =
      run_probe(request("vertex_face", "unsigned", wide_quadratic, beyond_corner_x, R"(,"closest_feature":true)") +
                request("vertex_face", "unsigned", wide_quadratic, beyond_corner_x));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 2u);
  const std::string& line = run.lines[0];
  const json r = parsed(line);
  ASSERT_EQ(r["status"], "ok") << line;
  EXPECT_EQ(r["feature"], "point_point");
  // The distance to the corner t0, not the plane distance 1.2 of the plain request.
  EXPECT_NEAR(r["length"].get<double>(), 1.3, 1e-15);
  EXPECT_EQ(parsed(run.lines[1])["length"], 1.2);
  EXPECT_FALSE(parsed(run.lines[1]).contains("feature"));
  // ψ′ = 7 (1.3 − 2) = −4.9: ∇_p E = ψ′ (p − t0)/1.3, ∇_t0 E = −∇_p E, zeros on t1 and t2.
  const double c = -4.9 / 1.3;
  const double expected[12] = {-0.3 * c, -0.4 * c, 1.2 * c, 0.3 * c, 0.4 * c, -1.2 * c, 0, 0, 0, 0, 0, 0};
  ASSERT_EQ(r["gradient"].size(), 12u);
  for (std::size_t i = 0; i < 12; ++i) {
    EXPECT_NEAR(r["gradient"][i].get<double>(), expected[i], 1e-13) << i;
    if (i >= 6) {
      EXPECT_EQ(r["gradient"][i], 0) << i;
    }
  }
  ASSERT_EQ(r["hessian"].size(), 144u);
  ASSERT_EQ(r["projected_hessian"].size(), 144u);
  for (std::size_t row = 0; row < 12; ++row)
    for (std::size_t col = 0; col < 12; ++col)
      if (row >= 6 || col >= 6) {
        EXPECT_EQ(r["hessian"][12 * row + col], 0) << row << "," << col;
        EXPECT_EQ(r["projected_hessian"][12 * row + col], 0) << row << "," << col;
      }
  EXPECT_EQ(r["eigenvalues"].size(), 3u);  // point_point's frame space
  expect_matches_closest_feature(line, closest_feature<pce::VertexFace>(beyond_corner_x), pce::Projection::analytic);
}

TEST(ProbeClosestFeature, ParallelEdgesAreOkInsteadOfDegenerate) {
  const ProbeRun run =
      run_probe(request("edge_edge", "unsigned", wide_quadratic, parallel_x, R"(,"closest_feature":true)") +
                request("edge_edge", "unsigned", wide_quadratic, parallel_x));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 2u);
  EXPECT_EQ(parsed(run.lines[1])["status"], "degenerate") << run.lines[1];
  const std::string& line = run.lines[0];
  const json r = parsed(line);
  ASSERT_EQ(r["status"], "ok") << line;
  // The edges are 1 apart and overlap: an endpoint is closest (a point kind, never line_line).
  EXPECT_EQ(r["length"], 1);
  const std::string feature = r["feature"].get<std::string>();
  EXPECT_TRUE(feature == "point_point" || feature == "point_edge") << line;
  EXPECT_EQ(r["eigenvalues"].size(), feature == "point_point" ? 3u : 6u);
  // ψ′ = 7 (1 − 2) = −7 pushes the edges apart along y: the y components of the
  // gradient are −7 in total on edge a and +7 on edge b.
  ASSERT_EQ(r["gradient"].size(), 12u);
  const double ya = r["gradient"][1].get<double>() + r["gradient"][4].get<double>();
  const double yb = r["gradient"][7].get<double>() + r["gradient"][10].get<double>();
  EXPECT_NEAR(ya, 7.0, 1e-13);
  EXPECT_NEAR(yb, -7.0, 1e-13);
  expect_matches_closest_feature(line, closest_feature<pce::EdgeEdge>(parallel_x), pce::Projection::analytic);
}

TEST(ProbeClosestFeature, PlaneFeaturesEqualThePlainUnsignedResponse) {
  // A vertex over the interior of its triangle, and edges whose closest points are inside
  // both segments: the kinds evaluated are the plain ones, so apart from "feature" the
  // response is the plain unsigned one, byte for byte, for every projection.
  const char* projections[] = {"analytic", "numerical", "exact", "gauss_newton", "abs", "none"};
  std::string input;
  for (const char* p : projections) {
    const std::string extra = std::string(R"(,"projection":")") + p + "\"";
    input += request("vertex_face", "unsigned", quadratic, vertex_face_x, extra + R"(,"closest_feature":true)");
    input += request("vertex_face", "unsigned", quadratic, vertex_face_x, extra);
    input += request("edge_edge", "unsigned", quadratic, edge_edge_x, extra + R"(,"closest_feature":true)");
    input += request("edge_edge", "unsigned", quadratic, edge_edge_x, extra + R"(,"closest_feature":false)");
  }
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 24u);
  for (std::size_t i = 0; i < run.lines.size(); i += 2) {
    const std::string& cf = run.lines[i];
    const std::string& plain = run.lines[i + 1];
    ASSERT_EQ(parsed(plain)["status"], "ok") << plain;
    const std::string feature = (i / 2) % 2 == 0 ? "point_plane" : "line_line";
    const std::string tag = R"(,"feature":")" + feature + "\"";
    const std::size_t at = cf.find(tag);
    ASSERT_NE(at, std::string::npos) << cf;
    EXPECT_EQ(std::string(cf).erase(at, tag.size()), plain);
  }
}

TEST(ProbeClosestFeature, EveryProjectionAndScalarWorks) {
  const char* projections[] = {"analytic", "numerical", "exact", "gauss_newton", "abs", "none"};
  const pce::Projection strategies[] = {pce::Projection::analytic, pce::Projection::numerical,
                                        pce::Projection::exact,    pce::Projection::gauss_newton,
                                        pce::Projection::abs,      pce::Projection::none};
  const char* scalars[] = {"double", "float", "long_double"};
  // Vertex beside the edge t1-t2 of the unit right triangle, 0.5 from it.
  const X beside_edge_x = {0.75, 0.75, std::sqrt(0.125), 0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::string input;
  for (const char* p : projections)
    for (const char* s : scalars) {
      const std::string extra =
          std::string(R"(,"closest_feature":true,"projection":")") + p + R"(","scalar":")" + s + "\"";
      input += request("vertex_face", "unsigned", wide_quadratic, beside_edge_x, extra);
      input += request("vertex_face", "unsigned", log_barrier, beyond_corner_x, extra);
      input += request("edge_edge", "unsigned", wide_quadratic, parallel_x, extra);
    }
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 54u);
  expect_no_nan_or_inf(run);
  for (std::size_t i = 0; i < run.lines.size(); ++i) {
    const json r = parsed(run.lines[i]);
    ASSERT_EQ(r["status"], "ok") << run.lines[i];
    if (i % 3 == 0) {
      EXPECT_EQ(r["feature"], "point_edge") << run.lines[i];
      EXPECT_NEAR(r["length"].get<double>(), 0.5, 1e-6) << run.lines[i];
      EXPECT_EQ(r["eigenvalues"].size(), 6u);
    } else if (i % 3 == 1) {
      EXPECT_EQ(r["feature"], "point_point") << run.lines[i];
      EXPECT_NEAR(r["length"].get<double>(), 1.3, 1e-6) << run.lines[i];
      EXPECT_EQ(r["eigenvalues"].size(), 3u);
    }
    EXPECT_EQ(r["gradient"].size(), 12u);
    EXPECT_EQ(r["projected_hessian"].size(), 144u);
  }
  // Beside the edge, in double: the point-edge energy on the points (p, t1, t2).
  const X& x = beside_edge_x;
  const pce::ClosestFeatureEnergy<double> e = closest_feature<pce::VertexFace>(x);
  ASSERT_EQ(e.feature, pce::Feature::point_edge);
  for (std::size_t k = 0; k < 6; ++k) expect_matches_closest_feature(run.lines[9 * k], e, strategies[k]);
  // "exact" is the nearest PSD matrix, as "numerical" (indices: projection k, double, first case).
  const std::vector<double> numerical = numbers_of(run.lines[9], "projected_hessian");
  const std::vector<double> exact = numbers_of(run.lines[18], "projected_hessian");
  ASSERT_EQ(exact.size(), 144u);
  ASSERT_EQ(numerical.size(), 144u);
  double scale = 0;
  for (double v : numerical) scale = std::max(scale, std::abs(v));
  ASSERT_GT(scale, 0.0);
  for (std::size_t j = 0; j < 144; ++j) EXPECT_LE(std::abs(exact[j] - numerical[j]), 1e-12 * scale) << j;
}

TEST(ProbeClosestFeature, ZeroDistanceOnAPointKindIsDegenerateAndOnAPlaneKindOutOfDomain) {
  // Collinear edges touching end to end: ea1 = eb0, the distance is 0 at two endpoints.
  const X touching_x = {0, 0, 0, 1, 0, 0, 1, 0, 0, 2, 0, 0};
  // A vertex in the interior of its triangle: point_plane with L = 0.
  const X in_face_x = {0.25, 0.25, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0};
  const ProbeRun run =
      run_probe(request("edge_edge", "unsigned", wide_quadratic, touching_x, R"(,"closest_feature":true)") +
                request("vertex_face", "unsigned", log_barrier, in_face_x, R"(,"closest_feature":true)") +
                request("vertex_face", "unsigned", wide_quadratic, in_face_x, R"(,"closest_feature":true)"));
  ASSERT_EQ(run.lines.size(), 3u);
  const json a = parsed(run.lines[0]), b = parsed(run.lines[1]), c = parsed(run.lines[2]);
  EXPECT_EQ(a["status"], "degenerate") << run.lines[0];
  EXPECT_NE(a["message"].get<std::string>().find("closest features"), std::string::npos) << run.lines[0];
  EXPECT_EQ(b["status"], "out_of_domain") << run.lines[1];
  EXPECT_NE(b["message"].get<std::string>().find("(L = 0)"), std::string::npos) << run.lines[1];
  EXPECT_EQ(c["status"], "ok") << run.lines[2];
  EXPECT_EQ(c["feature"], "point_plane");
  EXPECT_EQ(c["length"], 0);
}

TEST(ProbeClosestFeature, BadRequestsAreInvalidRequestNamingTheField) {
  const std::string cf = R"(,"closest_feature":true)";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {request("vertex_face", "signed", wide_quadratic, beyond_corner_x, cf), "\"closest_feature\""},
      {request("edge_edge", "signed", wide_quadratic, parallel_x, cf + R"(,"side":-1)"), "\"closest_feature\""},
      {request("vertex_face", "unsigned", wide_quadratic, beyond_corner_x, R"(,"closest_feature":1)"),
       "\"closest_feature\""},
      {request("vertex_face", "unsigned", wide_quadratic, beyond_corner_x, R"(,"closest_feature":"true")"),
       "\"closest_feature\""},
      {request("vertex_face", "unsigned", wide_quadratic, beyond_corner_x, R"(,"closest_feature":null)"),
       "\"closest_feature\""},
      {request("edge_edge", "unsigned", wide_quadratic, parallel_x, cf + mollifier_threshold(1e-3)),
       "\"closest_feature\""},
      {request("point_point", "unsigned", wide_quadratic, point_point_x, cf), "\"closest_feature\""},
  };
  std::string input;
  for (const auto& c : cases) input += c.first;
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const json r = parsed(run.lines[i]);
    EXPECT_EQ(r["status"], "invalid_request") << run.lines[i];
    EXPECT_NE(r["message"].get<std::string>().find(cases[i].second), std::string::npos) << run.lines[i];
  }
  // Signed and mollifier messages also name the other field.
  EXPECT_NE(parsed(run.lines[0])["message"].get<std::string>().find("\"length\""), std::string::npos);
  EXPECT_NE(parsed(run.lines[5])["message"].get<std::string>().find("\"mollifier\""), std::string::npos);
}

TEST(ProbeExactProjection, VertexFaceExactAgreesWithNumerical) {
  const ProbeRun run =
      run_probe(request("vertex_face", "signed", quadratic, vertex_face_x, R"(,"projection":"exact")") +
                request("vertex_face", "signed", quadratic, vertex_face_x, R"(,"projection":"numerical")") +
                request("vertex_face", "signed", quadratic, vertex_face_x, R"(,"projection":"analytic")"));
  ASSERT_EQ(run.exit_code, 0);
  ASSERT_EQ(run.lines.size(), 3u);
  const json r = parsed(run.lines[0]);
  ASSERT_EQ(r["status"], "ok") << run.lines[0];
  EXPECT_EQ(r["projection"], "exact");
  const std::vector<double> exact = numbers_of(run.lines[0], "projected_hessian");
  const std::vector<double> numerical = numbers_of(run.lines[1], "projected_hessian");
  const std::vector<double> analytic = numbers_of(run.lines[2], "projected_hessian");
  ASSERT_EQ(exact.size(), 144u);
  ASSERT_EQ(numerical.size(), 144u);
  ASSERT_EQ(analytic.size(), 144u);
  double scale = 0;
  for (double v : numerical) scale = std::max(scale, std::abs(v));
  ASSERT_GT(scale, 0.0);
  double to_analytic = 0;
  for (std::size_t i = 0; i < 144; ++i) {
    EXPECT_LE(std::abs(exact[i] - numerical[i]), 1e-12 * scale) << "entry " << i;
    to_analytic = std::max(to_analytic, std::abs(exact[i] - analytic[i]));
  }
  // Not the closed-form clamp: "analytic" is a different matrix here.
  EXPECT_GT(to_analytic, 1e-3 * scale);
  // Everything else is the projection-independent plain response.
  for (const char* key : {"length", "value"}) EXPECT_EQ(r[key], parsed(run.lines[1])[key]) << key;
  EXPECT_EQ(numbers_of(run.lines[0], "hessian"), numbers_of(run.lines[1], "hessian"));
  // Bit for bit the library's Projection::exact.
  pce::PairResult<double> lib;
  pce::QuadraticPenalty pen;
  pen.stiffness = 3.5;
  pen.eps = 0.25;
  ASSERT_EQ(pce::evaluate<pce::VertexFace>(to_vec<double>(vertex_face_x), pce::SignedLength{}, pen,
                                           pce::Projection::exact, lib),
            pce::Status::ok);
  expect_same_bits(exact, row_major(lib.projected_hessian), 144);
}

TEST(ProbeExactProjection, WorksWithTheMollifierInTheBand) {
  const ProbeRun run = run_probe(
      request("edge_edge", "unsigned", quadratic, nearly_parallel_x,
              R"(,"projection":"exact")" + mollifier_threshold(1e-3)) +
      request("edge_edge", "unsigned", quadratic, nearly_parallel_x,
              R"(,"projection":"numerical")" + mollifier_threshold(1e-3)) +
      request("edge_edge", "unsigned", quadratic, parallel_x, R"(,"projection":"exact")" + mollifier_threshold(1e-3)));
  ASSERT_EQ(run.lines.size(), 3u);
  const json r = parsed(run.lines[0]);
  ASSERT_EQ(r["status"], "ok") << run.lines[0];
  EXPECT_GT(r["mollifier"].get<double>(), 0.0);
  EXPECT_LT(r["mollifier"].get<double>(), 1.0);
  const std::vector<double> exact = numbers_of(run.lines[0], "projected_hessian");
  const std::vector<double> numerical = numbers_of(run.lines[1], "projected_hessian");
  ASSERT_EQ(exact.size(), 144u);
  ASSERT_EQ(numerical.size(), 144u);
  double scale = 0;
  for (double v : numerical) scale = std::max(scale, std::abs(v));
  for (std::size_t i = 0; i < 144; ++i) EXPECT_LE(std::abs(exact[i] - numerical[i]), 1e-10 * scale) << i;
  const json zero = parsed(run.lines[2]);  // X = 0: zeros, as for every projection
  ASSERT_EQ(zero["status"], "ok") << run.lines[2];
  for (const json& v : zero["projected_hessian"]) EXPECT_EQ(v, 0);
}

TEST(ProbeNewKinds, OutputNeverContainsNanOrInf) {
  Coordinates huge_point = point_point_x;
  huge_point[0] = 1e300;
  Coordinates far_edge = point_edge_x;
  far_edge[2] = 1e30;
  X huge = beyond_corner_x;
  huge[3] = 1e300;
  std::string input;
  for (const char* s : {"double", "float", "long_double"})
    for (const char* p : {"analytic", "exact", "numerical"}) {
      const std::string extra = std::string(R"(,"scalar":")") + s + R"(","projection":")" + p + "\"";
      const std::string cf = extra + R"(,"closest_feature":true)";
      input += request("point_point", "unsigned", log_barrier, point_point_x, extra);
      input += request("point_point", "unsigned", quadratic, huge_point, extra);
      input += request("point_edge", "unsigned", quadratic, far_edge, extra);
      input += request("point_edge", "unsigned", log_barrier, point_edge_x, extra);
      input += request("vertex_face", "unsigned", quadratic, huge, cf);
      input += request("vertex_face", "unsigned", log_barrier, beyond_corner_x, cf);
      input += request("edge_edge", "unsigned", quadratic, parallel_x, cf);
      input += request("edge_edge", "unsigned", log_barrier, nearly_parallel_x, cf);
    }
  const ProbeRun run = run_probe(input);
  ASSERT_EQ(run.exit_code, 0);
  EXPECT_EQ(run.lines.size(), 72u);
  expect_no_nan_or_inf(run);
  for (const std::string& line : run.lines) EXPECT_NO_THROW(static_cast<void>(parsed(line))) << line;
  EXPECT_EQ(parsed(run.lines[1])["status"], "invalid_input");  // 1e300 is beyond max_coordinate
  EXPECT_NE(parsed(run.lines[1])["message"].get<std::string>().find("\"x\"[0]"), std::string::npos);
  EXPECT_EQ(parsed(run.lines[4])["status"], "invalid_input");
  EXPECT_NE(parsed(run.lines[4])["message"].get<std::string>().find("\"x\"[3]"), std::string::npos);
}

TEST(Probe, UnknownFlagIsUsageError) { EXPECT_EQ(run_probe("", "--bogus").exit_code, 2); }

TEST(Probe, HelpPrintsUsage) {
  const ProbeRun run = run_probe("", "--help");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.output.find("Usage"), std::string::npos);
}

}  // namespace
