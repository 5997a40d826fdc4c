// SPDX-License-Identifier: MIT
#include <pce/sim/broad_phase.hpp>
#include <pce/sim/candidates.hpp>
#include <pce/sim/instrumentation.hpp>

namespace pce::sim {

const char* to_string(BroadPhaseKind kind) {
  const std::string_view name = name_of(kind);
  return name.empty() ? "unknown" : name.data();
}

std::optional<BroadPhaseKind> broad_phase_kind(const std::string& name) { return parse<BroadPhaseKind>(name); }

namespace {
/// The O(n²) reference (`brute_force_candidates`), one primitive kind at a time.
class BruteForce final : public BroadPhase {
 public:
  using BroadPhase::edge_edge;
  using BroadPhase::vertex_face;
  void vertex_face(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix3Xi& triangles,
                   double distance, std::vector<std::array<int, 2>>& out) override {
    out = brute_force_candidates(x0, x1, triangles, Eigen::Matrix2Xi(2, 0), distance).vertex_face;
  }
  void edge_edge(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix2Xi& edges, double distance,
                 std::vector<std::array<int, 2>>& out) override {
    out = brute_force_candidates(x0, x1, Eigen::Matrix3Xi(3, 0), edges, distance).edge_edge;
  }
};
}  // namespace

std::unique_ptr<BroadPhase> make_fcl_broad_phase();     // broad_phase/fcl.cpp
std::unique_ptr<BroadPhase> make_bullet_broad_phase();  // broad_phase/bullet.cpp

Instrumentation& instrumentation() {
  static Instrumentation counters;
  return counters;
}

std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseKind kind) {
  ++instrumentation().broad_phases_built;
  switch (kind) {
    case BroadPhaseKind::brute:
      return std::make_unique<BruteForce>();
    case BroadPhaseKind::bullet:
      return make_bullet_broad_phase();
    case BroadPhaseKind::fcl:
      break;
  }
  return make_fcl_broad_phase();
}

}  // namespace pce::sim
