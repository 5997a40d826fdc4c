// SPDX-License-Identifier: MIT
/// @file
/// Process-wide counters that let tests prove a scene costs only what it declares: how many
/// broad phases were built and queried, how many vertex-face and edge-edge pairs were
/// evaluated, how many bending hinges were allocated. Incremented once per query or
/// evaluation pass (never per pair), so they cost nothing measurable.
#pragma once

#include <atomic>

namespace pce::sim {

struct Instrumentation {
  std::atomic<long> broad_phases_built{0};
  std::atomic<long> broad_phase_queries{0};
  std::atomic<long> vertex_face_pairs_evaluated{0};
  std::atomic<long> edge_edge_pairs_evaluated{0};
  std::atomic<long> bending_hinges_allocated{0};
};

/// The process's counters.
Instrumentation& instrumentation();

}  // namespace pce::sim
