// SPDX-License-Identifier: MIT
/// @file
/// Argument checks of the typed effect builders (`pce/sim/effects.hpp`): each throws
/// `ArgumentError(field, expected)` with the scene key's name for the field. Internal.
#pragma once

#include <pce/sim/input_error.hpp>

#include <Eigen/Core>

#include <cmath>
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

}  // namespace pce::sim::args
