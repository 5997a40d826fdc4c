// SPDX-License-Identifier: MIT
/// @file
/// Kinematic obstacles: a sphere, a box, a capsule or a triangle mesh whose pose follows a
/// prescribed path. They are not unknowns of the solve; the `obstacle_contact` effect pushes
/// the deformable vertices out of them and the renderer draws them.
#pragma once

#include <pce/core/enum_names.hpp>
#include <pce/sim/mesh.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <string>

namespace pce::sim {

/// An obstacle's shape: closed-form `sphere`, `box` and `capsule`, or a triangle `mesh`.
enum class ShapeKind { sphere, box, capsule, mesh };

/// The shapes' names (scene key `obstacles[i].shape`), in enumerator order.
inline constexpr EnumNames<ShapeKind, 4> kShapeNames{{
    {ShapeKind::sphere, "sphere"},
    {ShapeKind::box, "box"},
    {ShapeKind::capsule, "capsule"},
    {ShapeKind::mesh, "mesh"},
}};

/// The table of `ShapeKind`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<ShapeKind, 4>& enum_names(ShapeKind) { return kShapeNames; }

/// A rigid path: from `start` to `stop` (s) a body translates with `velocity` (m/s) and
/// rotates about its centre with `angular_velocity` (rad/s, axis × rate); it rests before
/// `start` and after `stop`. Obstacles move by it, and so do pin groups' targets.
struct Motion {
  /// Translation velocity v (m/s).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// Angular velocity ω (rad/s, axis × rate), about the body's centre.
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  /// Time (s) the motion starts.
  double start = 0;
  /// Time (s) the motion stops (never, by default).
  double stop = std::numeric_limits<double>::infinity();

  /// Time spent moving by time t: τ = clamp(t − start, 0, stop − start).
  double elapsed(double t) const;
  /// The rotation so far, exp([ω]× τ) (Rodrigues' formula).
  Eigen::Matrix3d spin(double t) const;
  /// Where a point at `p` at rest is at time t, turning about `centre`:
  /// centre + v τ + exp([ω]× τ)(p − centre).
  Eigen::Vector3d apply(double t, const Eigen::Vector3d& centre, const Eigen::Vector3d& p) const {
    return centre + velocity * elapsed(t) + spin(t) * (p - centre);
  }
};

/// A rigid obstacle of the scene: its shape in local coordinates, its pose at t = 0 and
/// its `Motion`.
struct Obstacle {
  /// The scene's obstacle name.
  std::string name;
  /// Which of the shape fields below apply.
  ShapeKind kind = ShapeKind::sphere;
  double radius = 0;                                       ///< sphere, capsule
  double half_length = 0;                                  ///< capsule: half its axis, along local z
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  ///< box
  Mesh mesh;                                               ///< kind mesh: triangles in local coordinates
  Eigen::Vector3d position = Eigen::Vector3d::Zero();      ///< centre at t = 0
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  ///< orientation at t = 0
  /// Its path after t = 0.
  Motion motion;

  /// World pose at time `t` (s): x_world = pose * x_local.
  Eigen::Isometry3d pose(double t) const;
};

/// Signed distance from world point `p` to the obstacle's surface at pose `pose` (negative
/// inside) with the outward unit normal at the closest surface point. Closed forms for
/// sphere, box and capsule; for a mesh, the unsigned distance to the nearest triangle.
struct SurfaceDistance {
  /// Signed distance, negative inside (unsigned for a mesh).
  double distance = 0;
  /// Outward unit normal at the closest surface point.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};
/// The `SurfaceDistance` of world point `p` to obstacle `o` at `pose`.
SurfaceDistance surface_distance(const Obstacle& o, const Eigen::Isometry3d& pose, const Eigen::Vector3d& p);

/// A triangle mesh of the obstacle's surface in world coordinates at `pose`, for drawing
/// and for mesh obstacles' contact (spheres and capsules tessellated, `resolution` segments
/// around).
Mesh surface_mesh(const Obstacle& o, const Eigen::Isometry3d& pose, int resolution = 24);

}  // namespace pce::sim
