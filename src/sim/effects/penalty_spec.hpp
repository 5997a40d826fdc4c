// SPDX-License-Identifier: MIT
/// @file
/// A contact effect's penalty as the scene gives it, and the dispatch to pce's penalty
/// types (the only place the simulator names them). Internal.
///
/// Scene form: `"penalty": {"type": "quadratic" | "cubic" | "log_barrier",
///   "stiffness": k > 0, "distance": activation distance (ε, or d̂ for the barrier) > 0,
///   "delta": δ ≥ 0 (cubic only, default 0)}`.
#pragma once

#include "../scene/params.hpp"

#include <pce/penalties/cubic.hpp>
#include <pce/penalties/log_barrier.hpp>
#include <pce/penalties/quadratic.hpp>

namespace pce::sim {

struct PenaltySpec {
  enum class Kind { quadratic, cubic, log_barrier } kind = Kind::quadratic;
  double stiffness = 0;
  double distance = 0;  ///< activation distance: ε (quadratic, cubic) or d̂ (log barrier)
  double delta = 0;     ///< cubic smoothing δ
  bool barrier() const { return kind == Kind::log_barrier; }
};

inline PenaltySpec parse_penalty(const Params& p) {
  PenaltySpec s;
  const std::string type = p.choice("type", {"quadratic", "cubic", "log_barrier"});
  s.kind = type == "quadratic" ? PenaltySpec::Kind::quadratic
           : type == "cubic"   ? PenaltySpec::Kind::cubic
                               : PenaltySpec::Kind::log_barrier;
  if (s.kind == PenaltySpec::Kind::cubic)
    p.only({"type", "stiffness", "distance", "delta"});
  else
    p.only({"type", "stiffness", "distance"});
  s.stiffness = p.positive("stiffness");
  s.distance = p.positive("distance");
  s.delta = s.kind == PenaltySpec::Kind::cubic ? p.nonnegative("delta", 0.0) : 0.0;
  return s;
}

/// Calls `f(penalty)` with the pce penalty object the spec describes.
template <class F> decltype(auto) visit_penalty(const PenaltySpec& s, F&& f) {
  switch (s.kind) {
    case PenaltySpec::Kind::cubic:
      return f(CubicPenalty{s.stiffness, s.distance, s.delta});
    case PenaltySpec::Kind::log_barrier:
      return f(LogBarrierPenalty{s.stiffness, s.distance});
    case PenaltySpec::Kind::quadratic:
      break;
  }
  return f(QuadraticPenalty{s.stiffness, s.distance});
}

}  // namespace pce::sim
