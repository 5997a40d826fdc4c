// SPDX-License-Identifier: MIT
/// @file
/// Process-wide counters that let tests prove a scene costs only what it declares, where no
/// frame counter can (`pce/sim/counters.hpp` counts what an effect does, not whether something
/// was built at all): how many broad phases were built, how many vertex-face and edge-edge
/// pairs were evaluated, how many bending hinges were allocated. (Queries are the frame
/// counter `broad_phase_queries`.) Incremented once per query or
/// evaluation pass (never per pair), so they cost nothing measurable.
#pragma once

#include <atomic>

namespace pce::sim {

/// The counters (see the file comment); all start at 0.
struct Instrumentation {
  /// Broad phases constructed (`make_broad_phase`).
  std::atomic<long> broad_phases_built{0};
  /// Vertex-face pairs visited by contact effects' energy passes (every candidate, or the
  /// pairs of a pass that reuses an earlier one's list).
  std::atomic<long> vertex_face_pairs_evaluated{0};
  /// Edge-edge pairs visited by contact effects' energy passes (as vertex_face_pairs_evaluated).
  std::atomic<long> edge_edge_pairs_evaluated{0};
  /// Bending hinges allocated.
  std::atomic<long> bending_hinges_allocated{0};
};

/// The process's counters.
Instrumentation& instrumentation();

}  // namespace pce::sim
