// SPDX-License-Identifier: MIT
/// @file
/// The broad phase a contact effect queries once per time step (and again only when its
/// candidates go stale): the vertex-face or edge-edge pairs whose boxes, grown by the
/// query distance, overlap, adjacent pairs excluded (`pce/sim/candidates.hpp`). Every
/// implementation returns exactly the set and order of `brute_force_candidates`.
/// Implementations keep their acceleration structure between queries (FCL's dynamic AABB
/// tree and Bullet's `btDbvt` are refitted, not rebuilt, while the topology is unchanged).
#pragma once

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

/// `"fcl"`, `"bullet"`, `"brute"`.
const char* to_string(BroadPhaseKind kind);

/// The kind `to_string` names `name`; nothing for any other string.
std::optional<BroadPhaseKind> broad_phase_kind(const std::string& name);

/// One broad phase: candidate pairs for a query distance, exactly those (and in the order)
/// of `brute_force_candidates`. Contact effects hold one each and query it per time step.
class BroadPhase {
 public:
  virtual ~BroadPhase() = default;
  /// (vertex, triangle) pairs, vertex not in the triangle, sorted.
  virtual void vertex_face(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles, double distance,
                           std::vector<std::array<int, 2>>& out) = 0;
  /// (edge a, edge b) pairs with a < b sharing no vertex, sorted.
  virtual void edge_edge(const Eigen::Matrix3Xd& x, const Eigen::Matrix2Xi& edges, double distance,
                         std::vector<std::array<int, 2>>& out) = 0;
};

/// A new broad phase of the given kind, with an empty acceleration structure.
std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseKind kind);

}  // namespace pce::sim
