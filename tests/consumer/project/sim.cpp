// SPDX-License-Identifier: MIT
// The consumer tests' pce::sim user: a 6 × 6 sheet falls onto a box with self contact,
// three steps with FCL's broad phase and three with Bullet's (so the link pulls in both),
// then the same scene written with the C++ builders (pce/sim/effects.hpp). Exits non-zero
// unless every step stays finite, the sheet moves down and the C++ run equals the scene's.
#include <pce/sim/effects.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/scene.hpp>

#include <cstdio>
#include <exception>

namespace {

const char* const scene = R"({
  "dt": 0.02, "frames": 3,
  "solver": {"tolerance": 0.05, "max_iterations": 20},
  "meshes": [{"name": "sheet", "generator": {"type": "grid", "width": 0.5, "height": 0.5, "nx": 6, "ny": 6},
              "transform": {"translation": [0, 0, 0.02]}, "density": 0.1}],
  "obstacles": [{"name": "floor", "shape": "box", "half_extents": [1, 1, 0.05], "position": [0, 0, -0.05]}],
  "effects": [
    {"type": "gravity"},
    {"type": "stretching", "model": "arap", "stiffness": 60},
    {"type": "obstacle_contact", "penalty": {"type": "quadratic", "stiffness": 80, "distance": 0.01}},
    {"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 20, "distance": 0.01}}
  ]
})";

Eigen::Matrix3Xd fcl_end;  // the FCL scene run's final positions

/// The scene above through the C++ builders; true when its 3 frames end where the scene's did.
bool run_cpp() {
  using namespace pce::sim;
  Mesh sheet = grid(0.5, 0.5, 6, 6);
  sheet.positions.row(2).array() += 0.02;
  Simulation sim;
  sim.model = build_model({{"sheet", sheet, 0.1}});
  Obstacle floor;
  floor.name = "floor";
  floor.kind = ShapeKind::box;
  floor.half_extents = {1, 1, 0.05};
  floor.position = {0, 0, -0.05};
  sim.obstacles = {floor};
  sim.solver.dt = 0.02;
  sim.solver.tolerance = 0.05;
  sim.solver.max_iterations = 20;
  sim.solver.threads = 1;
  ContactSettings self;
  self.penalty = {ContactPenalty::Kind::quadratic, 20, 0.01, 0};
  sim.effects.push_back(make_gravity(sim.model));
  sim.effects.push_back(make_stretching(sim.model, 60));
  sim.effects.push_back(make_obstacle_contact(sim.obstacles, {ContactPenalty::Kind::quadratic, 80, 0.01, 0}));
  sim.effects.push_back(make_self_vertex_face(sim.model, self));
  sim.start_at_rest();
  for (int f = 0; f < 3; ++f) sim.step();
  std::printf("c++ builders: %s the scene's final state\n", sim.x == fcl_end ? "equal to" : "DIFFERENT from");
  return sim.x == fcl_end;
}

bool run(pce::sim::BroadPhaseKind broad_phase, const char* name) {
  pce::sim::SceneOverrides overrides;
  overrides.broad_phase = broad_phase;
  overrides.threads = 1;
  const auto s = pce::sim::load_scene_text(scene, "consumer.json", ".", overrides);
  pce::sim::Simulation& sim = s->simulation;
  const double z0 = sim.x.row(2).mean();
  for (int f = 0; f < sim.frames; ++f) {
    const pce::sim::FrameStats stats = sim.step();
    std::printf("%s frame %d: %d Newton iterations, energy %.6g\n", name, stats.frame, stats.newton_iterations,
                stats.energy);
  }
  const double z = sim.x.row(2).mean();
  if (broad_phase == pce::sim::BroadPhaseKind::fcl) fcl_end = sim.x;
  return sim.x.allFinite() && z < z0;
}

}  // namespace

int main() {
  try {
    const bool ok =
        run(pce::sim::BroadPhaseKind::fcl, "fcl") && run(pce::sim::BroadPhaseKind::bullet, "bullet") && run_cpp();
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("error: %s\n", e.what());
    return 1;
  }
}
