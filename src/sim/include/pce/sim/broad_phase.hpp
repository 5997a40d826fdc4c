// SPDX-License-Identifier: MIT
/// @file
/// The broad phase a contact effect queries once per time step (and again only when its
/// candidates go stale): the vertex-face or edge-edge pairs whose boxes, grown by the
/// query distance, overlap, adjacent pairs excluded (`pce/sim/candidates.hpp`). Every
/// implementation returns exactly the set and order of `brute_force_candidates`.
/// Implementations keep their acceleration structure between queries (FCL's dynamic AABB
/// tree and Bullet's `btDbvt` are refitted, not rebuilt, while the topology is unchanged).
#pragma once

#include <pce/core/enum_names.hpp>

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pce::sim {

/// FCL's dynamic AABB tree (`broad_phase/fcl.cpp`), Bullet's `btDbvt`
/// (`broad_phase/bullet.cpp`), or the O(n²) reference `brute_force_candidates`.
enum class BroadPhaseKind { fcl, bullet, brute };

/// The broad phases' names (scene key `solver.broad_phase`, `pce-sim --broad-phase`), in
/// enumerator order.
inline constexpr EnumNames<BroadPhaseKind, 3> kBroadPhaseNames{{
    {BroadPhaseKind::fcl, "fcl"},
    {BroadPhaseKind::bullet, "bullet"},
    {BroadPhaseKind::brute, "brute"},
}};

/// The table of `BroadPhaseKind`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<BroadPhaseKind, 3>& enum_names(BroadPhaseKind) { return kBroadPhaseNames; }

/// `"fcl"`, `"bullet"`, `"brute"` (`kBroadPhaseNames`).
const char* to_string(BroadPhaseKind kind);

/// The kind `to_string` names `name`; nothing for any other string.
std::optional<BroadPhaseKind> broad_phase_kind(const std::string& name);

/// One broad phase: candidate pairs for a query distance, exactly those (and in the order)
/// of `brute_force_candidates`. Contact effects hold one each and query it per time step.
class BroadPhase {
 public:
  virtual ~BroadPhase() = default;
  /// (vertex, triangle) pairs over the sweep from `x0` to `x1` (boxes over both states,
  /// `pce/sim/candidates.hpp`), vertex not in the triangle, sorted. Throws
  /// std::invalid_argument when `x0` and `x1` differ in column count.
  virtual void vertex_face(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix3Xi& triangles,
                           double distance, std::vector<std::array<int, 2>>& out) = 0;
  /// (edge a, edge b) pairs over the sweep from `x0` to `x1`, a < b sharing no vertex, sorted.
  virtual void edge_edge(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1, const Eigen::Matrix2Xi& edges,
                         double distance, std::vector<std::array<int, 2>>& out) = 0;
  /// (vertex, triangle) pairs at one state `x`.
  void vertex_face(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles, double distance,
                   std::vector<std::array<int, 2>>& out) {
    vertex_face(x, x, triangles, distance, out);
  }
  /// (edge a, edge b) pairs at one state `x`.
  void edge_edge(const Eigen::Matrix3Xd& x, const Eigen::Matrix2Xi& edges, double distance,
                 std::vector<std::array<int, 2>>& out) {
    edge_edge(x, x, edges, distance, out);
  }
};

/// A new broad phase of the given kind, with an empty acceleration structure.
std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseKind kind);

}  // namespace pce::sim
