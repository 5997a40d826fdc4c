// SPDX-License-Identifier: MIT
// Tests for the pce-probe executable (contract: design/contracts.md section 1, user doc:
// docs/probe.md). Each test writes a JSON Lines file, runs the built probe on it through
// popen, and checks the answers: order, bit-exact agreement with the library after the
// text round trip, every projection and scalar name, every error status, and the opt-in
// "mollifier" field.
#include <pce/pce.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <array>
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

/// JSON has no NaN or Inf; the probe must never print them (contracts.md §1).
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
  return R"({"pair":")" + pair + R"(","length":")" + length + R"(","penalty":)" + penalty +
         R"(,"x":)" + coordinates(x) + extra + "}\n";
}

const std::string quadratic = R"({"type":"quadratic","stiffness":3.5,"eps":0.25})";
const std::string log_barrier = R"({"type":"log_barrier","stiffness":2,"dhat":0.1})";

/// A vertex 0.1234… above a generic triangle (coordinates with many significant digits).
const X vertex_face_x = {0.3141592653589793,  0.2718281828459045, 0.12345678901234567, 0.01, -0.02, 0.003,
                         1.1, 0.1, -0.05, 0.2, 0.9, 0.07};
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
  expect_same_bits(numbers_of(line, "gradient"), [&g](int i) { return g[i]; }, 12);

  pce::PairResult<double> r;
  ASSERT_EQ(pce::evaluate<pce::VertexFace>(to_vec<double>(vertex_face_x), pce::SignedLength{}, pen,
                                           pce::Projection::analytic, r),
            pce::Status::ok);
  EXPECT_EQ(bits(number_of(line, "length")), bits(r.length));
  EXPECT_EQ(bits(number_of(line, "value")), bits(r.value));
  expect_same_bits(numbers_of(line, "hessian"), row_major(r.hessian), 144);
  expect_same_bits(numbers_of(line, "projected_hessian"), row_major(r.projected_hessian), 144);
  expect_same_bits(numbers_of(line, "eigenvalues"), [&r](int i) { return r.eigen.values[i]; }, 9);
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
  expect_same_bits(numbers_of(line, "gradient"), [&r](int i) { return r.gradient[i]; }, 12);
  expect_same_bits(numbers_of(line, "projected_hessian"), row_major(r.projected_hessian), 144);
}

TEST(Probe, EveryProjectionAndScalarIsAcceptedInOrder) {
  const char* projections[] = {"analytic", "numerical", "gauss_newton", "abs", "none"};
  const char* scalars[] = {"double", "float", "long_double"};
  std::string input;
  int id = 0;
  for (const char* p : projections)
    for (const char* s : scalars)
      input += request("vertex_face", "signed", quadratic, vertex_face_x,
                       std::string(R"(,"projection":")") + p + R"(","scalar":")" + s + R"(","id":)" +
                           std::to_string(id++));
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
      {head + quadratic + R"(,"projection":"exact")" + tail, "projection"},
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

std::string mollifier_threshold(double threshold) {
  return R"(,"mollifier":{"threshold":)" + number(threshold) + "}";
}

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

  const auto check = [&](const std::string& plain, const std::string& line, auto pair, const X& x,
                         const auto& length, double threshold) {
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
    expect_same_bits(numbers_of(line, "gradient"), [&g](int i) { return g[i]; }, 12);
    const pce::Mat12<double> h = pce::energy_hessian(e);
    expect_same_bits(numbers_of(line, "hessian"), row_major(h), 144);
    const pce::Mat12<double> ph = pce::projected_hessian(e, pce::Projection::analytic);
    expect_same_bits(numbers_of(line, "projected_hessian"), row_major(ph), 144);
    const pce::FrameEigensystem<double> es = pce::energy_eigensystem(e);
    expect_same_bits(numbers_of(line, "eigenvalues"), [&es](int i) { return es.values[i]; }, 9);
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

TEST(Probe, UnknownFlagIsUsageError) { EXPECT_EQ(run_probe("", "--bogus").exit_code, 2); }

TEST(Probe, HelpPrintsUsage) {
  const ProbeRun run = run_probe("", "--help");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.output.find("Usage"), std::string::npos);
}

}  // namespace
