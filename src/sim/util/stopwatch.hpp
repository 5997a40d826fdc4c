// SPDX-License-Identifier: MIT
/// @file
/// Wall-clock milliseconds for the frame statistics (internal): the one clock every stage
/// time in `stats.json` is read from, and the scoped timer that measures a stage.
#pragma once

#include <pce/sim/counters.hpp>

#include <chrono>

namespace pce::sim {

/// The clock of every stage time (monotonic).
using Clock = std::chrono::steady_clock;

/// Milliseconds from `t0` to now.
inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// Adds the milliseconds of its lifetime to a total when it ends: a stage's time, measured
/// over the scope the timer is declared in. The total is a `double` (a `FrameStats` field, an
/// effect's per-frame time) or a `*_ms` counter, by its enumerator.
class ScopedTimer {
 public:
  /// Times into `total`.
  explicit ScopedTimer(double& total) : total_(&total) {}
  /// Times into the counter `counter` of `counters` (reporting it).
  ScopedTimer(Counters& counters, Counter counter) : total_(&counters[counter]) {}
  ~ScopedTimer() { *total_ += ms_since(start_); }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  double* total_;
  Clock::time_point start_ = Clock::now();
};

}  // namespace pce::sim
