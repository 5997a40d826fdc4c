// SPDX-License-Identifier: MIT
/// @file
/// The broad phase a contact effect queries once per time step (and again only when its
/// candidates go stale): the vertex-face or edge-edge pairs whose boxes, grown by the
/// query distance, overlap, adjacent pairs excluded (`pce/sim/candidates.hpp`). Every
/// implementation returns exactly the set and order of `brute_force_candidates`.
/// Implementations keep their acceleration structure between queries (FCL's dynamic AABB
/// tree is refitted, not rebuilt, while the topology is unchanged).
#pragma once

#include <Eigen/Core>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace pce::sim {

enum class BroadPhaseKind { fcl, brute };

/// `"fcl"`, `"brute"`.
const char* to_string(BroadPhaseKind kind);

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

std::unique_ptr<BroadPhase> make_broad_phase(BroadPhaseKind kind);

}  // namespace pce::sim
