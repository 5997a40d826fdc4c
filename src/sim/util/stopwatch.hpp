// SPDX-License-Identifier: MIT
/// @file
/// Wall-clock milliseconds for the frame statistics (internal): the one clock every stage
/// time in `stats.json` is read from.
#pragma once

#include <chrono>

namespace pce::sim {

/// The clock of every stage time (monotonic).
using Clock = std::chrono::steady_clock;

/// Milliseconds from `t0` to now.
inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace pce::sim
