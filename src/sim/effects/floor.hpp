// SPDX-License-Identifier: MIT
/// @file
/// The minimum separation (internal; docs/simulation.md §4.6), one mechanism for both
/// contact kinds: self contact (contact/step_bound.*, contact/separation_floor.*) and
/// obstacle contact (obstacle/obstacle_bounds.*, obstacle/obstacle_floor.*).
///
/// Every pair has a floor F (`min_separation` f times its activation distance d). When a
/// Newton line search begins, the step bound keeps every pair that starts the step at or
/// above F at least F apart along the whole step (and one that starts closer no closer): a
/// pair whose tenth of its distance d₀ would be below twice its floor keeps `floor_gap`
/// instead, bounded along its separating direction by `advance_to_gap`, so that a pair
/// sliding along its floor or parting does not limit the step. The pairs whose limit the
/// floor set are listed (`FloorLimit`); when the line search has ended, each listed pair
/// the step pressed in (`pressed_in`) is *held*: its penalty's stiffness is multiplied by
/// kFloorStiffening (`stiffen_factor`), so a penalty too soft for its load grows until it carries
/// it. The factor stays while the pair is within reach at a step's start; checkpoints keep
/// it. Block descent keeps the same floor through its per-vertex bounds.
#pragma once

#include <algorithm>
#include <cstddef>

namespace pce::sim {

/// The factor by which holding a pair at its minimum separation multiplies its penalty's
/// stiffness. Sixteenfold per hold: on the test scenes that needed it, fewer holds and
/// Newton iterations than fourfold.
inline constexpr double kFloorStiffening = 16;
/// The largest stiffening factor, 2³⁰.
inline constexpr double kLargestFloorStiffening = 1073741824.0;
/// A pair closer than this many times its floor after a line search is held there; the step
/// bound stops a pressed pair at two.
inline constexpr double kHeldWithin = 3;
/// The floor's rounding allowance δ, relative to max(|x|, 1): thousands of times the
/// rounding error of a distance or a separation, so a pair whose computed separation the
/// step keeps at least floor + δ − δ is at least its floor apart.
inline constexpr double kFloorRounding = 1e-12;

/// A pair whose limit in a line search's step bound its floor set: the pair, the gap g it
/// was to keep and its distance d₀ at the step's start.
struct FloorLimit {
  std::size_t k = 0;
  double gap = 0, start = 0;
};

/// The gap a pair at distance d0 with floor F > 0 keeps along a step (δ the rounding
/// allowance): 2F + 2δ when it is farther, else F + δ; 0 when its floor does not limit it
/// (its tenth, what every bounded pair keeps, is at least 2F + 2δ).
inline double floor_gap(double d0, double floor, double slack) {
  const double above = 2 * floor + 2 * slack;
  if (!(floor > 0) || !(0.1 * d0 < above)) return 0;
  return d0 > above ? above : floor + slack;
}

/// Whether the step that ended with the listed pair `h` at distance `now` pressed it in: it
/// is closer than kHeldWithin floors, and within a quarter floor of the gap it was to keep
/// or at least halfway there from its start (not merely limited).
inline bool pressed_in(double now, const FloorLimit& h, double floor) {
  return now < kHeldWithin * floor && now - h.gap <= std::max(0.5 * (h.start - h.gap), 0.25 * floor);
}

/// Holds a pair: multiplies its factor by kFloorStiffening, up to the largest factor; true
/// when it grew.
inline bool stiffen_factor(double& factor) {
  if (factor >= kLargestFloorStiffening) return false;
  factor = std::min(factor * kFloorStiffening, kLargestFloorStiffening);
  return true;
}

/// The largest t ≤ `cap` found for which a pair stays at least g − `slack` apart along a
/// step (a pair already closer: comes no closer), from its separation: `separation(t, S, r)`
/// gives at step fraction t a lower bound S on the distance that holds along a direction,
/// and r, the rate at which that bound shrinks per unit of t (false: not measurable; the
/// pair then stops the step at t). From tᵢ the whole rest of the step is kept when rᵢ ≤ 0
/// or Sᵢ − rᵢ (cap − tᵢ) ≥ g − slack, else each round advances 0.9 (Sᵢ − g)/rᵢ and measures
/// again, until an advance below 1e-3 t, or 32 rounds.
template <class Separation> double advance_to_gap(const Separation& separation, double g, double slack, double cap) {
  double t = 0;
  for (int round = 0; round < 32; ++round) {
    double S = 0, r = 0;
    if (!separation(t, S, r)) return t;
    // The separation never shrinks (a pair below g, too, comes no closer), or stays above
    // g − slack for the rest of the step (it shrinks by at most r (cap − t)): neither can
    // the distance come lower.
    if (!(r > 0) || !(r * (cap - t) > S - g + slack)) return cap;
    const double step = 0.9 * (S - g) / r;
    if (!(step > 0)) return t;
    t += step;
    if (t >= cap) return cap;
    if (step <= 1e-3 * t) return t;
  }
  return t;
}

}  // namespace pce::sim
