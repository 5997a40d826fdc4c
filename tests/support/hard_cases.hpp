// SPDX-License-Identifier: MIT
/// @file
/// The hard-case families of docs/stability.md, each swept over severities, shared by the
/// stability tests (tests/test_stability.cpp) and the table generator
/// (tests/stability_table.cpp). Every case is a double-precision input; references are
/// computed at exactly that input in 50 digits.
#pragma once

#include "conformance.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace pce_test {

struct HardCase {
  std::string family;    ///< e.g. "vf_plane"
  std::string severity;  ///< e.g. "-1e-08"
  PairKind pair;
  LengthKind length;
  PenaltySpec penalty;
  pce::Vec12<double> x;
  bool degenerate;  ///< the plain energy has no frame here (status `degenerate` expected)
};

inline std::string sev_label(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.0e", v);
  return v == 0 ? std::string(std::signbit(v) ? "-0" : "0") : std::string(b);
}

/// A fixed, "irrational" rotation so that no coordinate of the local construction stays exact.
inline Eigen::Matrix3d hard_case_rotation() {
  return (Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()) *
          Eigen::AngleAxisd(0.45, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// Rotates (unless `exact`: degenerate constructions must stay exactly degenerate), scales
/// and offsets a local construction.
inline pce::Vec12<double> place(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                                const Eigen::Vector3d& d, double scale = 1.0, double offset = 0.0, bool exact = false) {
  const Eigen::Matrix3d R = exact ? Eigen::Matrix3d::Identity() : hard_case_rotation();
  const Eigen::Vector3d o = offset * Eigen::Vector3d(0.6, -0.48, 0.64);
  pce::Vec12<double> x;
  x << R * (scale * a) + o, R * (scale * b) + o, R * (scale * c) + o, R * (scale * d) + o;
  return x;
}

/// Severities 1e-2 … 1e-14 with both signs, and exactly 0.
inline std::vector<double> signed_severities() {
  std::vector<double> v;
  for (int k = 2; k <= 14; k += 2) {
    v.push_back(std::pow(10.0, -k));
    v.push_back(-std::pow(10.0, -k));
  }
  v.push_back(0.0);
  return v;
}

inline PenaltySpec quadratic_for(double L, double size) {
  return {PenaltyKind::quadratic, 1.0, std::fabs(L) + 0.5 * size, 0, 0, 0};
}

inline std::vector<HardCase> hard_cases() {
  std::vector<HardCase> out;
  const auto add = [&](const std::string& fam, double sev, PairKind pair, const pce::Vec12<double>& x,
                       const PenaltySpec& pen, bool degenerate = false, bool both_lengths = true) {
    out.push_back({fam, sev_label(sev), pair, LengthKind::signed_positive, pen, x, degenerate});
    if (both_lengths) out.push_back({fam, sev_label(sev), pair, LengthKind::unsigned_, pen, x, degenerate});
  };
  using V = Eigen::Vector3d;
  const V t0(0, 0, 0), t1(1, 0, 0), t2(0.3, 0.9, 0);
  // Vertex on / crossing the face plane, above the interior, a corner, an edge's line, far away.
  for (double h : signed_severities()) {
    add("vf_plane", h, PairKind::vertex_face, place(V(0.3, 0.3, h), t0, t1, t2), quadratic_for(h, 1));
    add("vf_corner", h, PairKind::vertex_face, place(V(0, 0, h), t0, t1, t2), quadratic_for(h, 1));
    add("vf_edge_line", h, PairKind::vertex_face, place(V(2.5, 0, h), t0, t1, t2), quadratic_for(h, 1));
    add("vf_far", h, PairKind::vertex_face, place(V(1e3, 2e3, h), t0, t1, t2), quadratic_for(h, 1));
    // Crossing edges (L = 0 exactly at severity 0) and edges sharing an endpoint.
    add("ee_crossing", h, PairKind::edge_edge, place(V(-1, 0, 0), V(1, 0, 0), V(-0.3, -0.866, h), V(0.7, 0.866, h)),
        quadratic_for(h, 1));
    add("ee_shared_endpoint", h, PairKind::edge_edge, place(V(0, 0, 0), V(1, 0, 0), V(0, 0, h), V(0.3, 0.8, h)),
        quadratic_for(h, 1));
  }
  // Nearly parallel edges at angle θ (offset 0.1 across, 0.3 sideways), and exactly parallel.
  for (int k = 2; k <= 12; ++k) {
    const double th = std::pow(10.0, -k);
    add("ee_near_parallel", th, PairKind::edge_edge,
        place(V(-1, 0, 0), V(1, 0, 0), V(-std::cos(th), 0.3 - std::sin(th), 0.1),
              V(std::cos(th), 0.3 + std::sin(th), 0.1)),
        quadratic_for(0.1, 1));
  }
  add("ee_near_parallel", 0.0, PairKind::edge_edge,
      place(V(-1, 0, 0), V(1, 0, 0), V(-1, 0.3, 0.1), V(1, 0.3, 0.1), 1, 0, true), quadratic_for(0.1, 1), true);
  // Sliver triangles of aspect a, and collinear ones.
  for (int k = 2; k <= 12; ++k) {
    const double a = std::pow(10.0, -k);
    add("vf_sliver", a, PairKind::vertex_face, place(V(0.3, 0.05, 0.1), t0, t1, V(0.4, a, 0)), quadratic_for(0.1, 1));
  }
  add("vf_sliver", 0.0, PairKind::vertex_face, place(V(0.3, 0.05, 0.1), t0, t1, V(0.4, 0, 0), 1, 0, true),
      quadratic_for(0.1, 1), true);
  // Zero-length edges and coincident points: no frame.
  add("zero_length", 0.0, PairKind::edge_edge, place(V(0, 0, 0), V(0, 0, 0), V(0, -1, 0.1), V(0, 1, 0.1), 1, 0, true),
      quadratic_for(0.1, 1), true);
  add("zero_length", 0.0, PairKind::vertex_face, place(V(0.3, 0.3, 0.1), t0, t0, t2, 1, 0, true), quadratic_for(0.1, 1),
      true);
  add("coincident", 0.0, PairKind::vertex_face, place(V(0, 0, 0), t0, t0, t0, 1, 0, true), quadratic_for(0.1, 1), true);
  // Extreme scales (feature size s, vertex at 0.1 s), and a large offset with small features.
  for (int k = -8; k <= 8; k += 2) {
    const double s = std::pow(10.0, k);
    add("scale_vf", s, PairKind::vertex_face, place(V(0.3, 0.3, 0.1), t0, t1, t2, s), quadratic_for(0.1 * s, s));
    add("scale_ee", s, PairKind::edge_edge, place(V(-1, 0, 0), V(1, 0, 0), V(-0.3, -0.866, 0.1), V(0.7, 0.866, 0.1), s),
        quadratic_for(0.1 * s, s));
  }
  add("offset_1e6_vf", 1e-3, PairKind::vertex_face, place(V(0.3, 0.3, 0.1), t0, t1, t2, 1e-3, 1e6),
      quadratic_for(1e-4, 1e-3));
  add("offset_1e6_ee", 1e-3, PairKind::edge_edge,
      place(V(-1, 0, 0), V(1, 0, 0), V(-0.3, -0.866, 0.1), V(0.7, 0.866, 0.1), 1e-3, 1e6), quadratic_for(1e-4, 1e-3));
  // Log barrier near d̂ (L/d̂ = 1 − r) and near 0 (L/d̂ = r); cubic with tiny δ.
  for (int k = 2; k <= 14; k += 2) {
    const double r = std::pow(10.0, -k);
    const double h = 0.1;
    add("barrier_near_dhat", r, PairKind::vertex_face, place(V(0.3, 0.3, h), t0, t1, t2),
        {PenaltyKind::log_barrier, 1.0, 0, 0, h / (1 - r), 0});
    add("barrier_near_zero", r, PairKind::vertex_face, place(V(0.3, 0.3, 0.1 * r), t0, t1, t2),
        {PenaltyKind::log_barrier, 1.0, 0, 0, 0.1, 0});
  }
  for (int k = 2; k <= 16; k += 2) {
    const double d = std::pow(10.0, -k);
    add("cubic_tiny_delta", d, PairKind::vertex_face, place(V(0.3, 0.3, 0.05), t0, t1, t2),
        {PenaltyKind::cubic, 1.0, 0.1, d, 0, 0});
  }
  return out;
}

}  // namespace pce_test
