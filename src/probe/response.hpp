// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: one response (an evaluated pair or an error) and its JSON Lines rendering.
/// Numbers are written by hand with 17 significant digits so that every double
/// round-trips exactly; strings and the echoed "id" go through nlohmann's escaping.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace pce_probe {

/// What a mollified evaluation reports in addition to the plain outputs.
struct MollifierOutput {
  double value = 0;      ///< m(X) in [0, 1]
  double threshold = 0;  ///< X̂ used (given, or computed from the rest pair)
};

/// The numeric outputs of a successful evaluation, already converted to double.
/// `gradient` has one entry per coordinate of "x" (12, 9 or 6), the matrices its square,
/// row-major; `eigenvalues` are the frame-space ones of the evaluated kind (9, 6 or 3),
/// ascending.
struct Evaluation {
  std::optional<double> length;  ///< L; absent only for a mollified pair without a frame (X = 0)
  double value = 0;
  std::vector<double> gradient;
  std::vector<double> hessian;
  std::vector<double> projected_hessian;
  std::vector<double> eigenvalues;
  std::string projection;                    ///< strategy used, as spelled in requests
  std::string scalar;                        ///< scalar type used, as spelled in requests
  std::optional<MollifierOutput> mollifier;  ///< set for requests with a "mollifier" field
  std::optional<std::string> feature;        ///< set for "closest_feature" requests: the kind evaluated
};

/// One output line: `status` is "ok" (and `evaluation` is set) or a machine-readable
/// reason with a human-readable `message`.
struct Response {
  std::string status;
  std::string message;
  std::optional<nlohmann::json> id;
  std::optional<Evaluation> evaluation;
};

/// An error response.
Response error_response(std::string status, std::string message);

/// A double as a JSON number with 17 significant digits ("%.17g"); −0 is written "-0.0"
/// so that parsers with an integer type keep its sign. Requires a finite value.
std::string format_number(double v);

/// The response as one JSON object, without the trailing newline.
std::string format_response(const Response& r);

}  // namespace pce_probe
