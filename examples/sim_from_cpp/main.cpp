// SPDX-License-Identifier: MIT
// Driving pce::sim from C++ instead of a scene file: a model built from a generated cloth,
// the built-in effects made by the typed builders a scene's effects use (pce/sim/effects.hpp),
// and Simulation::step. A cloth pinned along one edge swings down onto a sphere.
// Check: the state stays finite, the cloth touches the ball and never passes through it.
#include <pce/sim/effects.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/simulation.hpp>

#include <algorithm>
#include <cstdio>
#include <exception>

int main() try {
  using namespace pce::sim;
  Mesh cloth = grid(0.6, 0.6, 12, 12);  // 169 vertices in z = 0, lifted above the ball
  cloth.positions.row(2).array() += 0.15;

  Simulation sim;  // the model first: effects keep a pointer to sim.model
  sim.model = build_model({{"cloth", cloth, /*density kg/m²*/ 0.1}});
  Obstacle ball;  // a sphere of radius 0.1 at the origin
  ball.name = "ball";
  ball.radius = 0.1;
  sim.obstacles = {ball};
  sim.solver.dt = 1.0 / 50;

  const Model& m = sim.model;
  const ContactPenalty penalty{ContactPenalty::Kind::quadratic, /*k*/ 1e3, /*ε*/ 0.005};
  ContactSettings self;  // pce's pair energies between the cloth's own triangles and edges
  self.penalty = penalty;
  self.hessian = pce::Projection::analytic;
  PinGroup edge;  // the row of vertices at y = 0.3 stays where it is
  edge.vertices = vertices_in_box(m, {-1, 0.29, 0}, {1, 1, 1});
  sim.effects.push_back(make_gravity(m));
  sim.effects.push_back(make_stretching(m, /*μ N/m*/ 50));
  sim.effects.push_back(make_bending(m, /*k N·m*/ 1e-4));
  sim.effects.push_back(make_pins(m, {edge}));
  sim.effects.push_back(make_self_vertex_face(m, self));
  sim.effects.push_back(make_self_edge_edge(m, self));
  sim.effects.push_back(make_obstacle_contact(sim.obstacles, penalty));
  sim.start_at_rest();

  double closest = 1e9, touching = 0;  // closest vertex to the ball's centre over all frames
  for (int f = 0; f < 30; ++f) {
    const FrameStats st = sim.step();  // throws if the state turns non-finite
    closest = std::min(closest, sim.x.colwise().norm().minCoeff());
    touching = std::max(touching, st.counters.at("obstacle_contacts"));
    if (st.frame % 5 == 0)
      std::printf("frame %2d: %2d Newton its, %3.0f ball contacts, %3.0f self contacts, lowest z %.4f, %.1f ms\n",
                  st.frame, st.newton_iterations, st.counters.at("obstacle_contacts"),
                  st.counters.at("vertex_face_contacts") + st.counters.at("edge_edge_contacts"),
                  sim.x.row(2).minCoeff(), st.wall_ms);
  }
  const bool ok = sim.x.allFinite() && touching > 0 && closest > 0.1 - 0.005 && edge.vertices.size() == 13;
  std::printf("closest to the ball's centre: %.4f m (radius 0.1)\n%s\n", closest,
              ok ? "ok: draped on the ball" : "FAILED");
  return ok ? 0 : 1;
} catch (const std::exception& e) {  // ArgumentError names the field; runtime_error a non-finite frame
  std::fprintf(stderr, "error: %s\n", e.what());
  return 1;
}
