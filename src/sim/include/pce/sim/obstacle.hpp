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
#include <vector>

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

/// How a keyframed `Motion` passes from one keyframe to the next (scene key
/// `motion.interpolation`): with u ∈ [0, 1] the fraction of the segment's time gone,
/// `linear` moves by u, `smooth` by smoothstep s(u) = 3u² − 2u³ (zero velocity at every
/// keyframe).
enum class Interpolation { linear, smooth };

/// The interpolations' names (scene key `motion.interpolation`), in enumerator order.
inline constexpr EnumNames<Interpolation, 2> kInterpolationNames{{
    {Interpolation::linear, "linear"},
    {Interpolation::smooth, "smooth"},
}};

/// The table of `Interpolation`'s names (for `pce::name_of` and `pce::parse`).
constexpr const EnumNames<Interpolation, 2>& enum_names(Interpolation) { return kInterpolationNames; }

/// One keyframe of a keyframed `Motion`: the body's rigid displacement from its rest pose
/// at `time`, a rotation R about the body's centre c followed by a translation d, so that a
/// point p at rest is at c + d + R (p − c).
struct Keyframe {
  /// Time (s): finite, ≥ 0, and greater than the previous keyframe's.
  double time = 0;
  /// Translation d (m), each coordinate within ±`kMaxCoordinate`.
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  /// Rotation R about the body's centre, in world axes (a rotation matrix).
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

/// A rigid path, either a constant velocity or keyframes. Constant velocity (no keyframes):
/// from `start` to `stop` (s) a body translates with `velocity` (m/s) and rotates about its
/// centre with `angular_velocity` (rad/s, axis × rate); it rests before `start` and after
/// `stop`. Keyframed (`keyframes` not empty; the four constant-velocity fields then keep
/// their defaults): the body holds the first keyframe's displacement before its time and
/// the last's after it, and between two keyframes k and k + 1 its translation is
/// d_k + w (d_{k+1} − d_k) and its rotation R_k exp(w log(R_kᵀ R_{k+1})) (the shortest
/// rotation between them, its angle scaled by w), with w = u (`linear`) or 3u² − 2u³
/// (`smooth`), u = (t − t_k)/(t_{k+1} − t_k). Obstacles move by it, and so do pin groups'
/// targets.
struct Motion {
  /// Translation velocity v (m/s).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// Angular velocity ω (rad/s, axis × rate), about the body's centre.
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  /// Time (s) the motion starts.
  double start = 0;
  /// Time (s) the motion stops (never, by default).
  double stop = std::numeric_limits<double>::infinity();
  /// The keyframes, in strictly increasing time; empty: the constant velocity above.
  std::vector<Keyframe> keyframes{};
  /// How a keyframed motion passes between its keyframes.
  Interpolation interpolation = Interpolation::linear;

  /// Time spent moving by time t: τ = clamp(t − start, 0, stop − start) (constant velocity).
  double elapsed(double t) const;
  /// The translation so far: v τ, or the keyframes' translation at time t.
  Eigen::Vector3d shift(double t) const;
  /// The rotation so far: exp([ω]× τ) (Rodrigues' formula), or the keyframes' rotation at
  /// time t.
  Eigen::Matrix3d spin(double t) const;
  /// Where a point at `p` at rest is at time t, turning about `centre`:
  /// centre + shift(t) + spin(t)(p − centre).
  Eigen::Vector3d apply(double t, const Eigen::Vector3d& centre, const Eigen::Vector3d& p) const {
    return centre + shift(t) + spin(t) * (p - centre);
  }
};

/// A pose an obstacle is put at while the simulation runs, replacing its `Motion`
/// (`Simulation::set_obstacle_pose`): it holds from `from` on, until a later one.
struct PlacedPose {
  /// Time (s) from which it holds. Put between steps at time t for the step to t + h, it is
  /// t + h/2: the step's end (and every later time) sees it, the step's start (t, as t + h − h
  /// rounds) does not.
  double from = 0;
  /// The pose: x_world = pose * x_local.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

/// A rigid obstacle of the scene: its shape in local coordinates, its pose at t = 0, its
/// `Motion` and the poses it was put at while running.
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
  /// Poses it was put at while running, in increasing `from` (not a scene key, not in a
  /// checkpoint): from the first one's `from` on, the last one at or before t replaces the
  /// motion.
  std::vector<PlacedPose> placed{};

  /// Adds `p` to `placed`, after dropping every placed pose whose `from` is not before p's
  /// (a pose put again before the same step replaces the earlier one).
  void place(const PlacedPose& p);

  /// World pose at time `t` (s): x_world = pose * x_local. The last placed pose whose
  /// `from` ≤ t, else by the motion: translation position + shift(t), rotation spin(t) · rotation.
  Eigen::Isometry3d pose(double t) const;
};

/// The rotation of a scene's `{"axis": axis, "degrees": degrees}`: right-handed by `degrees`
/// about `axis` (non-zero and finite, any length; checked by the caller).
Eigen::Matrix3d axis_rotation(const Eigen::Vector3d& axis, double degrees);

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
