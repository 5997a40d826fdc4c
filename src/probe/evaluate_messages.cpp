// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: see `evaluate_messages.hpp`.
#include "evaluate_messages.hpp"

#include <cmath>
#include <utility>

namespace pce_probe {

namespace {

std::string nonnegative_problem(const char* field, double v) {
  if (std::isfinite(v) && v >= 0) return {};
  return std::string("field \"") + field + "\" must be finite and >= 0 (got " + describe(v) + ")";
}

std::string finite_problem(const char* field, double v) {
  if (std::isfinite(v)) return {};
  return std::string("field \"") + field + "\" must be finite (got " + describe(v) + ")";
}

}  // namespace

std::string describe(double v) { return std::isfinite(v) ? format_number(v) : "a value beyond the double range"; }

std::string penalty_problem(const pce::QuadraticPenalty& p) {
  std::string s = nonnegative_problem("penalty.stiffness", p.stiffness);
  return s.empty() ? finite_problem("penalty.eps", p.eps) : s;
}
std::string penalty_problem(const pce::CubicPenalty& p) {
  std::string s = nonnegative_problem("penalty.stiffness", p.stiffness);
  if (s.empty()) s = finite_problem("penalty.eps", p.eps);
  return s.empty() ? nonnegative_problem("penalty.delta", p.delta) : s;
}
std::string penalty_problem(const pce::LogBarrierPenalty& p) {
  std::string s = nonnegative_problem("penalty.stiffness", p.stiffness);
  if (!s.empty()) return s;
  if (std::isfinite(p.dhat) && p.dhat > 0) return {};
  return "field \"penalty.dhat\" must be finite and > 0 (got " + describe(p.dhat) + ")";
}

const char* degenerate_message(const Request& req) {
  if (req.closest_feature)
    return "degenerate: the distance between the closest features is exactly 0 on a point-edge or point-point "
           "feature (a point lies on the other primitive's edge or vertex, where the distance has no direction)";
  switch (req.pair) {
    case PairKind::vertex_face:
      return "degenerate frame: zero-area triangle (t0, t1, t2 coincident or collinear)";
    case PairKind::edge_edge:
      return "degenerate frame: parallel or zero-length edges";
    case PairKind::point_edge:
      return "degenerate: zero-length edge (e0 = e1), or the point on the edge's line (distance exactly 0, "
             "which has no direction)";
    case PairKind::point_point:
      return "degenerate: coincident points (distance exactly 0, which has no direction)";
  }
  return "degenerate";
}

Response ok_response(Evaluation e, const Request& req) {
  e.projection = pce::to_string(req.projection);
  e.scalar = to_string(req.scalar);
  Response r;
  r.status = pce::to_string(pce::Status::ok);
  r.evaluation = std::move(e);
  return r;
}

}  // namespace pce_probe
