// SPDX-License-Identifier: MIT
/// @file
/// The obstacles one obstacle-contact effect meets (internal; docs/simulation.md §3): their
/// shapes, their poses at the step's end (where the penalties push out of them) and start
/// (friction's surface motion), which vertices take part, and the one near-pair visitor every
/// pass of the effect goes through: per vertex, per obstacle, culled by a bounding sphere,
/// then the surface distance.
///
/// Culling: with cₖ obstacle k's origin and Rₖ the radius of a sphere about it that bounds
/// the shape, d ≥ |xᵢ − cₖ| − Rₖ for every shape, so a pass that needs nothing of a pair
/// whose distance is at least some value skips it on that lower bound alone.
#pragma once

#include <pce/sim/model.hpp>
#include <pce/sim/obstacle.hpp>

#include <Eigen/Geometry>

#include <cstddef>
#include <vector>

namespace pce::sim::obstacle {

/// Vertices per chunk of every parallel pass of an obstacle-contact effect.
inline constexpr long kChunk = 1024;

/// A pair (vertex i, obstacle k) is numbered i·K + k, K the effect's obstacle count.
using PairIndex = std::size_t;

/// The obstacles of one effect (see the file comment).
class ObstacleSet {
 public:
  /// `surface`: per vertex, 0 inside a volume (no contact); empty: every vertex takes part.
  ObstacleSet(std::vector<Obstacle> obstacles, std::vector<char> surface);

  /// Once per step: the poses at the step's end (ctx.time) and, when `with_start`, at its
  /// start, of the simulation's obstacles of the same names (`StepContext::obstacles`, which
  /// hold the poses put between steps) or of the effect's own copies.
  void place(const StepContext& ctx, bool with_start);

  /// K, the number of obstacles.
  std::size_t size() const { return obstacles_.size(); }
  /// Whether vertex i takes part in contact (every vertex but those inside a volume).
  bool takes_part(Eigen::Index i) const { return surface_.empty() || surface_[static_cast<std::size_t>(i)]; }
  /// The pair of vertex i and obstacle k.
  PairIndex pair(Eigen::Index i, std::size_t k) const { return static_cast<std::size_t>(i) * size() + k; }
  /// Whether obstacle k is convex (a sphere, box or capsule; a mesh is not).
  bool convex(std::size_t k) const { return obstacles_[k].kind != ShapeKind::mesh; }

  /// For each obstacle k: `skip(lower)` with the lower bound |p − cₖ| − Rₖ on the distance
  /// from p (at the end poses, or the start poses when `at_start`); unless it returns true,
  /// `visit(k, surface distance)`.
  template <class Skip, class Visit>
  void near(const Eigen::Vector3d& p, const Skip& skip, const Visit& visit, bool at_start = false) const {
    const std::vector<Eigen::Isometry3d>& poses = at_start ? start_poses_ : poses_;
    for (std::size_t k = 0; k < obstacles_.size(); ++k) {
      if (skip((p - poses[k].translation()).norm() - radius_[k])) continue;
      visit(k, surface_distance(obstacles_[k], poses[k], p));
    }
  }
  /// The signed distance and normal from p to obstacle k at its end pose.
  SurfaceDistance distance(std::size_t k, const Eigen::Vector3d& p) const {
    return surface_distance(obstacles_[k], poses_[k], p);
  }
  /// The signed distance at x of pair j, the obstacle at its end pose.
  double pair_distance(const Eigen::Matrix3Xd& x, PairIndex j) const {
    return distance(j % size(), x.col(static_cast<Eigen::Index>(j / size()))).distance;
  }
  /// Obstacle k's pose at the step's end, or at its start when `at_start`.
  const Eigen::Isometry3d& pose(std::size_t k, bool at_start) const { return at_start ? start_poses_[k] : poses_[k]; }

 private:
  std::vector<Obstacle> obstacles_;
  std::vector<char> surface_;
  std::vector<double> radius_;                  ///< per obstacle, Rₖ
  std::vector<Eigen::Isometry3d> poses_;        ///< at the end of the step
  std::vector<Eigen::Isometry3d> start_poses_;  ///< at its start (friction)
};

}  // namespace pce::sim::obstacle
