// SPDX-License-Identifier: MIT
// The obstacles of an obstacle-contact effect (obstacle_set.hpp).
#include "obstacle_set.hpp"

#include "util/names.hpp"

#include <algorithm>
#include <limits>

namespace pce::sim::obstacle {

namespace {

/// Radius of a sphere about the obstacle's origin containing the whole shape.
double bounding_radius(const Obstacle& o) {
  switch (o.kind) {
    case ShapeKind::sphere:
      return o.radius;
    case ShapeKind::box:
      return o.half_extents.norm();
    case ShapeKind::capsule:
      return o.half_length + o.radius;
    case ShapeKind::mesh: {
      double r = 0;
      for (Eigen::Index v = 0; v < o.mesh.positions.cols(); ++v) r = std::max(r, o.mesh.positions.col(v).norm());
      return r;
    }
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

ObstacleSet::ObstacleSet(std::vector<Obstacle> obstacles, std::vector<char> surface)
    : obstacles_(std::move(obstacles)), surface_(std::move(surface)) {
  radius_.reserve(obstacles_.size());
  for (const Obstacle& o : obstacles_) radius_.push_back(bounding_radius(o));
  poses_.assign(obstacles_.size(), Eigen::Isometry3d::Identity());
  for (std::size_t k = 0; k < obstacles_.size(); ++k) poses_[k] = obstacles_[k].pose(0.0);
  start_poses_ = poses_;
}

void ObstacleSet::place(const StepContext& ctx, bool with_start) {
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    const Obstacle* found = ctx.obstacles ? find_named(*ctx.obstacles, obstacles_[k].name) : nullptr;
    const Obstacle* posed = found ? found : &obstacles_[k];
    poses_[k] = posed->pose(ctx.time);
    if (with_start) start_poses_[k] = posed->pose(ctx.time - ctx.dt);
  }
}

}  // namespace pce::sim::obstacle
