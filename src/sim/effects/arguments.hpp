// SPDX-License-Identifier: MIT
/// @file
/// Argument checks of the typed effect builders (`pce/sim/effects.hpp`): each throws
/// `ArgumentError(field, expected)` with the scene key's name for the field. Internal.
///
/// **Limits.** Every number a scene or a builder gives must be one the simulator can compute
/// with: finite, and small enough that the products a time step forms (k·d², m/h², boxes
/// grown by a query radius, squared distances, forces times h²) stay hundreds of orders of
/// magnitude below overflow. The limits are physical upper bounds in SI units, each defined
/// once: lengths and coordinates (`kMaxCoordinate`, pce/sim/mesh.hpp), stiffnesses,
/// accelerations, damping rates and speeds here, densities in pce/sim/model.hpp, the
/// scene's time step in scene/solver_settings.cpp and its transform scale in
/// scene/motion.cpp (docs/fuzzing.md, "Limits").
#pragma once

#include <pce/sim/input_error.hpp>
#include <pce/sim/mesh.hpp>
#include <pce/sim/obstacle.hpp>

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>

namespace pce::sim::args {

/// `v` with 17 significant digits (what the error shows was given).
inline std::string text(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

/// `v` with the fewest significant digits (up to 17) that read back as `v` (0.4, not
/// 0.40000000000000002).
inline std::string shortest(double v) {
  for (int digits = 1;; ++digits) {
    std::ostringstream s;
    s.precision(digits);
    s << v;
    if (digits >= 17 || std::strtod(s.str().c_str(), nullptr) == v) return s.str();
  }
}

/// Largest stiffness, in the effect's own SI unit (N/m, N, N·m, N·m², J/m², J/m³): above any
/// material (diamond's Young's modulus is 1.2e12 Pa), and with lengths ≤ `kMaxCoordinate`
/// an energy k·L² (k·L³ for the cubic penalty) stays below 1e30.
inline constexpr double kMaxStiffness = 1e12;
/// Largest |component| of gravity (m/s²): 1e5 g. A step's free fall g·h² stays ≤ 1e6 m.
inline constexpr double kMaxAcceleration = 1e6;
/// Largest damping coefficient (1/s): a drag that stops a body within a microsecond.
inline constexpr double kMaxDamping = 1e6;
/// Largest |component| of a prescribed velocity (m/s) or angular velocity (rad/s): with the
/// scene's time ≤ 1e7 s a target moves at most 1e13 m, its squared distance stays finite.
inline constexpr double kMaxSpeed = 1e6;

/// `v` with 6 significant digits (the limits in messages).
inline std::string limit_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

/// Throws unless v is finite and in (0, hi]; `what` says why hi. Returns v.
inline double positive_at_most(const std::string& field, double v, double hi, const char* what) {
  if (!(std::isfinite(v) && v > 0 && v <= hi))
    throw ArgumentError(field, "expected a number > 0 and <= " + limit_text(hi) + " (" + what + "), got " + text(v));
  return v;
}

/// Throws unless v is finite and in [0, hi]; `what` says why hi. Returns v.
inline double nonnegative_at_most(const std::string& field, double v, double hi, const char* what) {
  if (!(std::isfinite(v) && v >= 0 && v <= hi))
    throw ArgumentError(field, "expected a number >= 0 and <= " + limit_text(hi) + " (" + what + "), got " + text(v));
  return v;
}

/// Throws unless every coordinate of v is finite with |vᵢ| ≤ hi; returns v.
inline const Eigen::Vector3d& bounded(const std::string& field, const Eigen::Vector3d& v, double hi, const char* what) {
  if (!(v.allFinite() && v.cwiseAbs().maxCoeff() <= hi))
    throw ArgumentError(field, "expected three numbers with |value| <= " + limit_text(hi) + " (" + what + "), got [" +
                                   text(v[0]) + ", " + text(v[1]) + ", " + text(v[2]) + "]");
  return v;
}

/// A stiffness: finite, > 0 and ≤ `kMaxStiffness`.
inline double stiffness(const std::string& field, double v) {
  return positive_at_most(field, v, kMaxStiffness, "the largest stiffness pce::sim accepts");
}

/// A length (size, radius, distance): finite, > 0 and ≤ `kMaxCoordinate`.
inline double length(const std::string& field, double v) {
  return positive_at_most(field, v, kMaxCoordinate, "the largest length and coordinate pce::sim accepts, in m");
}

/// A position: three finite numbers with |xᵢ| ≤ `kMaxCoordinate`.
inline const Eigen::Vector3d& position(const std::string& field, const Eigen::Vector3d& v) {
  return bounded(field, v, kMaxCoordinate, "the largest coordinate pce::sim accepts, in m");
}

/// A velocity or angular velocity: three finite numbers with |vᵢ| ≤ `kMaxSpeed`.
inline const Eigen::Vector3d& speed(const std::string& field, const Eigen::Vector3d& v) {
  return bounded(field, v, kMaxSpeed, "the largest speed pce::sim accepts, in m/s or rad/s");
}

/// Throws unless v is finite and > 0; returns v.
inline double positive(const std::string& field, double v) {
  if (!(std::isfinite(v) && v > 0)) throw ArgumentError(field, "expected a finite number > 0, got " + text(v));
  return v;
}

/// Throws unless v is finite and ≥ 0; returns v.
inline double nonnegative(const std::string& field, double v) {
  if (!(std::isfinite(v) && v >= 0)) throw ArgumentError(field, "expected a finite number >= 0, got " + text(v));
  return v;
}

/// Throws unless every coordinate of v is finite; returns v.
inline const Eigen::Vector3d& finite(const std::string& field, const Eigen::Vector3d& v) {
  if (!v.allFinite())
    throw ArgumentError(
        field, "expected three finite numbers, got [" + text(v[0]) + ", " + text(v[1]) + ", " + text(v[2]) + "]");
  return v;
}

/// Throws unless `R` is a rotation matrix (finite, orthonormal to 1e-9, determinant 1).
inline const Eigen::Matrix3d& rotation(const std::string& field, const Eigen::Matrix3d& R) {
  if (!(R.allFinite() && (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-9 && R.determinant() > 0))
    throw ArgumentError(field, "expected a rotation matrix (orthonormal, determinant 1)");
  return R;
}

/// Checks a `Motion` whose fields are named `at`.velocity, `at`.keyframes[k].time, … (bare
/// when `at` is empty). Constant velocity: speeds within `kMaxSpeed`, start ≥ 0, stop ≥ start.
/// Keyframed: the constant-velocity fields at their defaults; times finite, ≥ 0 and strictly
/// increasing; translations positions; rotations rotation matrices; a known interpolation.
inline void motion(const std::string& at, const Motion& m) {
  const auto field = [&](const std::string& key) { return at.empty() ? key : at + "." + key; };
  if (m.keyframes.empty()) {
    speed(field("velocity"), m.velocity);
    speed(field("angular_velocity"), m.angular_velocity);
    nonnegative(field("start"), m.start);
    if (!(m.stop >= m.start)) throw ArgumentError(field("stop"), "expected stop >= start");
    return;
  }
  const char* const both =
      "a motion has either \"keyframes\" or a constant velocity (\"velocity\", \"angular_velocity\", \"start\", "
      "\"stop\"), not both";
  if (!(m.velocity.array() == 0).all()) throw ArgumentError(field("velocity"), both);
  if (!(m.angular_velocity.array() == 0).all()) throw ArgumentError(field("angular_velocity"), both);
  if (m.start != 0) throw ArgumentError(field("start"), both);
  if (m.stop != std::numeric_limits<double>::infinity()) throw ArgumentError(field("stop"), both);
  for (std::size_t k = 0; k < m.keyframes.size(); ++k) {
    const Keyframe& key = m.keyframes[k];
    const std::string name = "keyframes[" + std::to_string(k) + "]";
    if (!(std::isfinite(key.time) && key.time >= 0))
      throw ArgumentError(field(name + ".time"), "expected a finite time >= 0, got " + shortest(key.time));
    if (k > 0 && !(key.time > m.keyframes[k - 1].time))
      throw ArgumentError(field(name + ".time"), "expected a time greater than keyframes[" + std::to_string(k - 1) +
                                                     "]'s (" + shortest(m.keyframes[k - 1].time) + "), got " +
                                                     shortest(key.time));
    position(field(name + ".translation"), key.translation);
    rotation(field(name + ".rotation"), key.rotation);
  }
  if (m.interpolation != Interpolation::linear && m.interpolation != Interpolation::smooth)
    throw ArgumentError(field("interpolation"), "expected linear or smooth");
}

}  // namespace pce::sim::args
