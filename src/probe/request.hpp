// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: one parsed request line (docs/probe.md) and the parser that turns a JSON
/// object into it. Malformed requests throw `InvalidRequest` with a message naming the
/// offending field.
#pragma once

#include <pce/pce.hpp>

#include <nlohmann/json.hpp>

#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace pce_probe {

/// Pair kinds the probe knows, by their request names.
enum class PairKind { vertex_face, edge_edge, point_edge, point_point };

/// Request spelling of a pair kind ("vertex_face", "edge_edge", "point_edge", "point_point").
const char* to_string(PairKind p);

/// Number of coordinates in "x" for a pair kind: 12, 12, 9, 6.
int coordinate_count(PairKind p);

/// Whether the pair kind is one of the point kinds (point_edge, point_point): unsigned only,
/// no mollifier, no closest-feature classification.
bool is_point_kind(PairKind p);

/// Scalar type the library is instantiated with.
enum class ScalarKind { float_, double_, long_double };

/// Request spelling of a scalar kind ("float", "double", "long_double").
const char* to_string(ScalarKind s);

using LengthSpec = std::variant<pce::SignedLength, pce::UnsignedLength>;
using PenaltySpec = std::variant<pce::QuadraticPenalty, pce::CubicPenalty, pce::LogBarrierPenalty>;

/// Everything one request asks for, validated for shape (not for numeric ranges: those
/// are the library's job and come back as a status; the one exception is the opt-in
/// mollifier, whose threshold is checked here).
struct Request {
  PairKind pair = PairKind::vertex_face;
  LengthSpec length;
  PenaltySpec penalty;
  /// `coordinate_count(pair)` numbers (12, 9 or 6), vertex by vertex.
  std::vector<double> x;
  pce::Projection projection = pce::Projection::analytic;
  ScalarKind scalar = ScalarKind::double_;
  /// Opt-in mollified energy (`"mollifier"` field): set only when the request has the
  /// field; its threshold is then finite and > 0 (given, or computed from `"rest"`).
  std::optional<pce::Mollifier> mollifier;
  /// `"closest_feature": true`: classify a vertex_face / edge_edge pair by its closest
  /// features and evaluate that kind (`pce::closest_feature_energy`). Only set for those two
  /// pairs with an unsigned length and no mollifier.
  bool closest_feature = false;
};

/// A request that cannot be evaluated: reported as status "invalid_request".
class InvalidRequest : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The request's "id" member (any JSON value), if it has one and is an object.
std::optional<nlohmann::json> request_id(const nlohmann::json& request);

/// Parses a request object; throws `InvalidRequest` naming the field on any problem.
Request parse_request(const nlohmann::json& request);

/// Parses one line of text as JSON. Unlike a plain `nlohmann::json::parse`, the number
/// token `-0` keeps its sign (it becomes the double −0.0), and a number beyond the double
/// range (e.g. `1e400`) does not fail the whole line: `parse_request` reads it as ±infinity
/// and `request_id` echoes it as null. Throws `InvalidRequest` when the line is not
/// valid JSON.
nlohmann::json parse_json_line(const std::string& line);

}  // namespace pce_probe
