// SPDX-License-Identifier: MIT
/// @file
/// A contact effect's penalty (`ContactPenalty`, pce/sim/effects.hpp): its checks, and the
/// dispatch to pce's penalty types (the only place the simulator names them). The scene's
/// `penalty` object is read by the scene loaders (effect_loaders.cpp). Internal.
#pragma once

#include "arguments.hpp"

#include <pce/sim/effects.hpp>

#include <pce/penalties/cubic.hpp>
#include <pce/penalties/log_barrier.hpp>
#include <pce/penalties/quadratic.hpp>

namespace pce::sim {

/// Throws ArgumentError (fields `<prefix>stiffness`, …) unless `s` is a valid penalty.
/// Limits: the stiffness ≤ `args::kMaxStiffness` (in J/m², J/m³ for the cubic), the
/// activation distance ≤ `kMaxCoordinate` (a self-contact query grows boxes by 2d, and
/// 1e308 overflowed them), δ ≤ `kMaxCoordinate`² (a squared length).
inline void check_penalty(const ContactPenalty& s, const std::string& prefix) {
  args::stiffness(prefix + "stiffness", s.stiffness);
  args::length(prefix + "distance", s.distance);
  args::nonnegative_at_most(prefix + "delta", s.delta, kMaxCoordinate * kMaxCoordinate,
                            "the square of the largest length pce::sim accepts, in m²");
  if (s.kind != ContactPenalty::Kind::cubic && s.delta != 0)
    throw ArgumentError(prefix + "delta", "only the cubic penalty has a delta");
  if (s.kind != ContactPenalty::Kind::quadratic && s.kind != ContactPenalty::Kind::cubic &&
      s.kind != ContactPenalty::Kind::log_barrier)
    throw ArgumentError(prefix + "type", "expected quadratic, cubic or log_barrier");
}

/// Throws ArgumentError (`min_separation`) unless `fraction` is in [0, kMaxMinSeparation].
inline void check_min_separation(double fraction) {
  args::nonnegative_at_most("min_separation", fraction, kMaxMinSeparation,
                            "the largest minimum separation, as a fraction of the activation distance");
}

/// The largest self-contact activation distance, as a fraction of the diagonal of the
/// model's rest bounding box: a self-contact query grows every box by 2d, so at d = ½·diagonal
/// every pair of the model is a candidate at every step — contact is no longer a thin
/// layer but an all-pairs force, and the candidate lists grow as n².
inline constexpr double kMaxContactDistanceFraction = 0.5;

/// Throws ArgumentError (`<prefix>distance`) unless `s.distance` ≤
/// `kMaxContactDistanceFraction` × the diagonal of `model`'s rest bounding box (the check a
/// self-contact effect needs beyond `check_penalty`).
inline void check_penalty_for_model(const ContactPenalty& s, const Model& model, const std::string& prefix) {
  if (model.rest.cols() == 0) return;
  const double diagonal = (model.rest.rowwise().maxCoeff() - model.rest.rowwise().minCoeff()).norm();
  if (!(s.distance <= kMaxContactDistanceFraction * diagonal))
    throw ArgumentError(prefix + "distance",
                        "expected a number <= " + args::text(kMaxContactDistanceFraction * diagonal) +
                            " (half the diagonal " + args::text(diagonal) +
                            " m of the model's rest bounding box: beyond, every pair is a "
                            "contact candidate at every step), got " +
                            args::text(s.distance));
}

/// `p` with its stiffness multiplied by `w`: w ψ, since every penalty is linear in its
/// stiffness (area-weighted contact).
template <class Penalty> Penalty scaled(Penalty p, double w) {
  p.stiffness *= w;
  return p;
}

/// Calls `f(penalty)` with the pce penalty object the spec describes.
template <class F> decltype(auto) visit_penalty(const ContactPenalty& s, F&& f) {
  switch (s.kind) {
    case ContactPenalty::Kind::cubic:
      return f(CubicPenalty{s.stiffness, s.distance, s.delta});
    case ContactPenalty::Kind::log_barrier:
      return f(LogBarrierPenalty{s.stiffness, s.distance});
    case ContactPenalty::Kind::quadratic:
      break;
  }
  return f(QuadraticPenalty{s.stiffness, s.distance});
}

}  // namespace pce::sim
