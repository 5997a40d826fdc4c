// SPDX-License-Identifier: MIT
// The drop scene the linear-solver tests share (test_linear_solver.cpp, test_krylov.cpp).
#pragma once

#include <nlohmann/json.hpp>

namespace pce::sim::fixtures {

/// An upper sheet dropped onto a lower one pinned at two corners, over a sphere: self
/// contact of both kinds and obstacle contact from the third step on.
inline nlohmann::json drop(const char* linear_solver, double tolerance) {
  nlohmann::json j = nlohmann::json::parse(R"({
    "dt": 0.02, "frames": 12,
    "meshes": [
      {"name": "lower", "generator": {"type": "grid", "width": 0.5, "height": 0.5, "nx": 8, "ny": 8},
       "transform": {"translation": [0, 0, 0.12]}},
      {"name": "upper", "generator": {"type": "grid", "width": 0.4, "height": 0.4, "nx": 7, "ny": 7},
       "transform": {"translation": [0.01, 0.02, 0.15]}}
    ],
    "obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.1}],
    "effects": [
      {"type": "gravity"},
      {"type": "stretching", "stiffness": 50},
      {"type": "bending", "stiffness": 0.001},
      {"type": "pins", "groups": [{"mesh": "lower", "vertices": [0, 8]}]},
      {"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 1000, "distance": 0.01}},
      {"type": "self_edge_edge", "penalty": {"type": "quadratic", "stiffness": 1000, "distance": 0.01}},
      {"type": "obstacle_contact", "penalty": {"type": "quadratic", "stiffness": 1000, "distance": 0.01}}
    ]
  })");
  j["solver"] = {{"linear_solver", linear_solver}, {"tolerance", tolerance}, {"threads", 1}};
  return j;
}

}  // namespace pce::sim::fixtures
