// SPDX-License-Identifier: MIT
// Placeholder until the FCL broad phase lands: falls back to brute force.
#include <pce/sim/broad_phase.hpp>

namespace pce::sim {
std::unique_ptr<BroadPhase> make_fcl_broad_phase() { return make_broad_phase(BroadPhaseKind::brute); }
}  // namespace pce::sim
