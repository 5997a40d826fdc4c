// SPDX-License-Identifier: MIT
// pce-probe: parsing and validation of one request object (field list in docs/probe.md).
#include "request.hpp"

#include "response.hpp"

#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <regex>
#include <string>
#include <variant>
#include <vector>

namespace pce_probe {

namespace {

using nlohmann::json;

[[noreturn]] void fail(const std::string& message) { throw InvalidRequest(message); }

/// Stands in for a number token beyond the double range (nlohmann rejects those), so
/// that the field holding it can be named and reported as not finite.
constexpr const char* overflow_positive = "\x01pce-overflow+";
constexpr const char* overflow_negative = "\x01pce-overflow-";

bool is_number_char(char c) {
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E';
}

/// Whether `token` follows the JSON number grammar (RFC 8259, section 6).
bool is_json_number(const std::string& token) {
  static const std::regex grammar(R"(-?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?)");
  return std::regex_match(token, grammar);
}

/// The replacement text for one number token, or the token itself. `-0` becomes `-0.0`
/// (nlohmann would read it as the integer 0); a token that overflows double becomes a
/// marker string that `number_value` reads as ±infinity.
std::string rewrite_number(const std::string& token) {
  if (token == "-0") return "-0.0";
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size() || std::isfinite(v) || !is_json_number(token)) return token;
  return json(v > 0 ? overflow_positive : overflow_negative).dump();
}

/// Applies `rewrite_number` to every number token outside strings.
std::string rewrite_numbers(const std::string& line) {
  std::string out;
  out.reserve(line.size() + 8);
  bool in_string = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (in_string) {
      out += c;
      if (c == '\\' && i + 1 < line.size())
        out += line[++i];
      else if (c == '"')
        in_string = false;
    } else if (c == '-' || (c >= '0' && c <= '9')) {
      std::size_t j = i;
      while (j < line.size() && is_number_char(line[j])) ++j;
      out += rewrite_number(line.substr(i, j - i));
      i = j - 1;
    } else {
      in_string = c == '"';
      out += c;
    }
  }
  return out;
}

/// Replaces overflow markers inside an echoed value by null.
void clear_overflow_markers(json& v) {
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    if (s == overflow_positive || s == overflow_negative) v = nullptr;
  } else if (v.is_structured()) {
    for (json& child : v) clear_overflow_markers(child);
  }
}

/// A JSON number (or an overflow marker, as ±infinity) as a double; false otherwise.
bool number_value(const json& v, double& out) {
  if (v.is_number()) {
    out = v.get<double>();
    return true;
  }
  if (!v.is_string()) return false;
  const std::string& s = v.get_ref<const std::string&>();
  if (s != overflow_positive && s != overflow_negative) return false;
  out = s == overflow_positive ? HUGE_VAL : -HUGE_VAL;
  return true;
}

/// The member `key` of `obj`, or a "missing field" error naming `path`.
const json& required(const json& obj, const char* key, const std::string& path) {
  const auto it = obj.find(key);
  if (it == obj.end()) fail("missing field \"" + path + "\"");
  return *it;
}

std::string required_string(const json& obj, const char* key, const std::string& path) {
  const json& v = required(obj, key, path);
  if (!v.is_string()) fail("field \"" + path + "\" must be a string");
  return v.get<std::string>();
}

/// A JSON number as a double. nlohmann parses floating-point tokens with strtod (exact,
/// correctly rounded); integer tokens convert exactly up to 2^53 and round to nearest
/// beyond, which is the same double strtod would give.
double required_number(const json& obj, const char* key, const std::string& path) {
  const json& v = required(obj, key, path);
  double out = 0;
  if (!number_value(v, out)) fail("field \"" + path + "\" must be a number");
  return out;
}

/// Quoted, escaped rendering of a user-supplied value for error messages.
std::string quoted(const std::string& s) { return json(s).dump(-1, ' ', false, json::error_handler_t::replace); }

PairKind parse_pair(const json& req) {
  const std::string s = required_string(req, "pair", "pair");
  for (PairKind p : {PairKind::vertex_face, PairKind::edge_edge, PairKind::point_edge, PairKind::point_point})
    if (s == to_string(p)) return p;
  fail("unknown \"pair\" " + quoted(s) +
       " (expected \"vertex_face\", \"edge_edge\", \"point_edge\" or \"point_point\")");
}

/// "side": +1 or −1 (integer or floating-point token), default +1.
pce::Side parse_side(const json& req) {
  const auto it = req.find("side");
  if (it == req.end()) return pce::Side::positive;
  double v = 0;
  if (number_value(*it, v)) {
    if (v == 1.0) return pce::Side::positive;
    if (v == -1.0) return pce::Side::negative;
  }
  fail("field \"side\" must be 1 or -1");
}

/// "length": "signed" (uses "side") or "unsigned" (a valid "side" is accepted and ignored).
/// The point kinds (a distance to a line or a point has no side) accept only "unsigned".
LengthSpec parse_length(const json& req, PairKind pair) {
  const std::string s = required_string(req, "length", "length");
  const pce::Side side = parse_side(req);
  if (s == "signed" && is_point_kind(pair))
    fail("field \"length\" must be \"unsigned\" for \"pair\" " + quoted(to_string(pair)) +
         " (a distance between points and lines has no side)");
  if (s == "signed") return pce::SignedLength{side};
  if (s == "unsigned") return pce::UnsignedLength{};
  fail("unknown \"length\" " + quoted(s) + " (expected \"signed\" or \"unsigned\")");
}

/// "penalty": {"type": ..., parameters}; every parameter of the type is required.
PenaltySpec parse_penalty(const json& req) {
  const json& p = required(req, "penalty", "penalty");
  if (!p.is_object()) fail("field \"penalty\" must be an object");
  const std::string type = required_string(p, "type", "penalty.type");
  if (type == "quadratic") {
    pce::QuadraticPenalty q;
    q.stiffness = required_number(p, "stiffness", "penalty.stiffness");
    q.eps = required_number(p, "eps", "penalty.eps");
    return q;
  }
  if (type == "cubic") {
    pce::CubicPenalty c;
    c.stiffness = required_number(p, "stiffness", "penalty.stiffness");
    c.eps = required_number(p, "eps", "penalty.eps");
    c.delta = required_number(p, "delta", "penalty.delta");
    return c;
  }
  if (type == "log_barrier") {
    pce::LogBarrierPenalty b;
    b.stiffness = required_number(p, "stiffness", "penalty.stiffness");
    b.dhat = required_number(p, "dhat", "penalty.dhat");
    return b;
  }
  fail("unknown \"penalty.type\" " + quoted(type) + " (expected \"quadratic\", \"cubic\" or \"log_barrier\")");
}

/// `obj[key]`: exactly `n` numbers (or overflow markers, as ±infinity); errors name `path`
/// (`hint`, if not empty, is added to the count messages).
std::vector<double> parse_numbers(const json& obj, const char* key, const std::string& path, std::size_t n,
                                  const std::string& hint = "") {
  const json& x = required(obj, key, path);
  const std::string count = std::to_string(n) + " numbers" + hint;
  if (!x.is_array()) fail("field \"" + path + "\" must be an array of " + count);
  if (x.size() != n) fail("field \"" + path + "\" must have " + count + ", got " + std::to_string(x.size()));
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!number_value(x[i], out[i])) fail("field \"" + path + "\"[" + std::to_string(i) + "] must be a number");
  }
  return out;
}

/// "x": exactly 12 numbers (vertex_face, edge_edge), 9 (point_edge) or 6 (point_point).
std::vector<double> parse_coordinates(const json& req, PairKind pair) {
  std::string hint;
  if (pair == PairKind::point_edge) hint = " (p, e0, e1) for \"pair\" \"point_edge\"";
  if (pair == PairKind::point_point) hint = " (p, q) for \"pair\" \"point_point\"";
  return parse_numbers(req, "x", "x", static_cast<std::size_t>(coordinate_count(pair)), hint);
}

pce::Projection parse_projection(const json& req) {
  const auto it = req.find("projection");
  if (it == req.end()) return pce::Projection::analytic;
  if (!it->is_string()) fail("field \"projection\" must be a string");
  const std::string s = it->get<std::string>();
  for (pce::Projection p : {pce::Projection::analytic, pce::Projection::numerical, pce::Projection::exact,
                            pce::Projection::gauss_newton, pce::Projection::abs, pce::Projection::none})
    if (s == pce::to_string(p)) return p;
  fail("unknown \"projection\" " + quoted(s) +
       " (expected \"analytic\", \"numerical\", \"exact\", \"gauss_newton\", \"abs\" or \"none\")");
}

ScalarKind parse_scalar(const json& req) {
  const auto it = req.find("scalar");
  if (it == req.end()) return ScalarKind::double_;
  if (!it->is_string()) fail("field \"scalar\" must be a string");
  const std::string s = it->get<std::string>();
  for (ScalarKind k : {ScalarKind::double_, ScalarKind::float_, ScalarKind::long_double})
    if (s == to_string(k)) return k;
  fail("unknown \"scalar\" " + quoted(s) + " (expected \"double\", \"float\" or \"long_double\")");
}

/// A number for a message; never prints a bare non-finite token.
std::string describe(double v) { return std::isfinite(v) ? format_number(v) : "a value beyond the double range"; }

/// X̂ = factor |e0|²|e1|² of the rest pair, in double (`pce::mollifier_threshold`).
double rest_threshold(PairKind pair, const std::vector<double>& rest, double factor) {
  pce::Vec12<double> r;
  for (int i = 0; i < 12; ++i) r[i] = rest[static_cast<std::size_t>(i)];
  return pair == PairKind::edge_edge ? pce::mollifier_threshold<pce::EdgeEdge>(r, factor)
                                     : pce::mollifier_threshold<pce::VertexFace>(r, factor);
}

/// "mollifier" (optional): either {"threshold": X̂} or {"rest": [12 numbers], "factor": f}
/// (f defaults to 1e-3); exactly one of "threshold" and "rest". X̂ must come out finite and
/// > 0, f must be finite and > 0, the rest coordinates finite.
std::optional<pce::Mollifier> parse_mollifier(const json& req, PairKind pair) {
  const auto it = req.find("mollifier");
  if (it == req.end()) return std::nullopt;
  if (is_point_kind(pair))
    fail("field \"mollifier\" is only for \"pair\" \"vertex_face\" or \"edge_edge\" (got " + quoted(to_string(pair)) +
         ")");
  const json& m = *it;
  if (!m.is_object())
    fail("field \"mollifier\" must be an object: {\"threshold\":X} or {\"rest\":[12 numbers],\"factor\":f}");
  const bool has_threshold = m.contains("threshold");
  const bool has_rest = m.contains("rest");
  if (has_threshold && has_rest)
    fail("field \"mollifier\" must have either \"mollifier.threshold\" or \"mollifier.rest\", not both");
  if (!has_threshold && !has_rest) fail("missing field \"mollifier.threshold\" (or \"mollifier.rest\")");
  pce::Mollifier out;
  if (has_threshold) {
    if (m.contains("factor")) fail("field \"mollifier.factor\" is only allowed with \"mollifier.rest\"");
    out.threshold = required_number(m, "threshold", "mollifier.threshold");
    if (!out.valid())
      fail("field \"mollifier.threshold\" must be finite and > 0 (got " + describe(out.threshold) + ")");
    return out;
  }
  const std::vector<double> rest = parse_numbers(m, "rest", "mollifier.rest", 12);
  for (std::size_t i = 0; i < 12; ++i)
    if (!std::isfinite(rest[i])) fail("field \"mollifier.rest\"[" + std::to_string(i) + "] must be finite");
  double factor = 1e-3;
  if (m.contains("factor")) {
    factor = required_number(m, "factor", "mollifier.factor");
    if (!std::isfinite(factor) || !(factor > 0))
      fail("field \"mollifier.factor\" must be finite and > 0 (got " + describe(factor) + ")");
  }
  out.threshold = rest_threshold(pair, rest, factor);
  if (!out.valid())
    fail("field \"mollifier.rest\" gives the threshold factor*|e0|^2*|e1|^2 = " + describe(out.threshold) +
         ", which must be finite and > 0 (a zero-length rest edge, or a product that underflows or overflows)");
  return out;
}

/// "closest_feature" (optional, default false): a boolean; `true` only for vertex_face and
/// edge_edge, with an unsigned length and without "mollifier".
bool parse_closest_feature(const json& req, const Request& r) {
  const auto it = req.find("closest_feature");
  if (it == req.end()) return false;
  if (!it->is_boolean()) fail("field \"closest_feature\" must be true or false");
  if (!it->get<bool>()) return false;
  if (is_point_kind(r.pair))
    fail("field \"closest_feature\" is only for \"pair\" \"vertex_face\" or \"edge_edge\" (got " +
         quoted(to_string(r.pair)) + ")");
  if (std::holds_alternative<pce::SignedLength>(r.length))
    fail("field \"closest_feature\" requires \"length\":\"unsigned\" (closest-feature distances have no side)");
  if (r.mollifier)
    fail(
        "field \"closest_feature\" cannot be combined with \"mollifier\" (the mollifier applies to the plain "
        "plane-distance energy only)");
  return true;
}

}  // namespace

const char* to_string(PairKind p) {
  switch (p) {
    case PairKind::vertex_face:
      return "vertex_face";
    case PairKind::edge_edge:
      return "edge_edge";
    case PairKind::point_edge:
      return "point_edge";
    case PairKind::point_point:
      return "point_point";
  }
  return "unknown";
}

int coordinate_count(PairKind p) {
  switch (p) {
    case PairKind::point_edge:
      return pce::PointEdge::dofs;
    case PairKind::point_point:
      return pce::PointPoint::dofs;
    case PairKind::vertex_face:
      return pce::VertexFace::dofs;
    case PairKind::edge_edge:
      return pce::EdgeEdge::dofs;
  }
  return 12;
}

bool is_point_kind(PairKind p) { return p == PairKind::point_edge || p == PairKind::point_point; }

const char* to_string(ScalarKind s) {
  switch (s) {
    case ScalarKind::float_:
      return "float";
    case ScalarKind::double_:
      return "double";
    case ScalarKind::long_double:
      return "long_double";
  }
  return "unknown";
}

std::optional<nlohmann::json> request_id(const nlohmann::json& request) {
  if (!request.is_object()) return std::nullopt;
  const auto it = request.find("id");
  if (it == request.end()) return std::nullopt;
  nlohmann::json id = *it;
  clear_overflow_markers(id);
  return id;
}

Request parse_request(const nlohmann::json& request) {
  if (!request.is_object()) fail("request must be a JSON object");
  Request r;
  r.pair = parse_pair(request);
  r.length = parse_length(request, r.pair);
  r.penalty = parse_penalty(request);
  r.x = parse_coordinates(request, r.pair);
  r.projection = parse_projection(request);
  r.scalar = parse_scalar(request);
  r.mollifier = parse_mollifier(request, r.pair);
  r.closest_feature = parse_closest_feature(request, r);
  return r;
}

nlohmann::json parse_json_line(const std::string& line) {
  try {
    return nlohmann::json::parse(rewrite_numbers(line));
  } catch (const nlohmann::json::parse_error& e) {
    fail(std::string("line is not valid JSON: ") + e.what());
  }
}

}  // namespace pce_probe
