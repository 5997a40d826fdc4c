// SPDX-License-Identifier: MIT
// Start-state validation (pce/sim/start_state.hpp).
#include <pce/sim/intersections.hpp>
#include <pce/sim/mesh.hpp>
#include <pce/sim/start_state.hpp>

#include <algorithm>
#include <cstring>

namespace pce::sim {

namespace {

/// The triangles of meshes `a` and `b` (b = a: of mesh a alone), as columns.
Eigen::Matrix3Xi triangles_of(const Model& model, std::size_t a, std::size_t b) {
  const MeshRange &ra = model.meshes[a], &rb = model.meshes[b];
  const int n = ra.triangle_count + (a == b ? 0 : rb.triangle_count);
  Eigen::Matrix3Xi t(3, n);
  t.leftCols(ra.triangle_count) = model.triangles.middleCols(ra.first_triangle, ra.triangle_count);
  if (a != b) t.rightCols(rb.triangle_count) = model.triangles.middleCols(rb.first_triangle, rb.triangle_count);
  return t;
}

std::string quoted(const std::string& name) { return "\"" + name + "\""; }

bool declares(const Simulation& sim, const char* effect) {
  for (const auto& e : sim.effects)
    if (std::strcmp(e->name(), effect) == 0) return true;
  return false;
}

}  // namespace

StartStateReport check_start_state(Simulation& sim) {
  sim.check();
  StartStateReport report;
  const Model& model = sim.model;
  const std::size_t M = model.meshes.size();

  // Intersections within each mesh, then between each pair of meshes: the count over both
  // meshes less the counts within each (pairs of one mesh are counted by both calls alike).
  std::vector<long> within(M, 0);
  for (std::size_t a = 0; a < M; ++a) {
    if (model.meshes[a].triangle_count < 2) continue;
    within[a] = intersecting_triangle_pairs(sim.x, triangles_of(model, a, a));
    if (within[a] > 0)
      report.refusals.push_back("the start state has " + std::to_string(within[a]) +
                                " intersecting triangle pairs within mesh " + quoted(model.meshes[a].name));
  }
  for (std::size_t a = 0; a < M; ++a)
    for (std::size_t b = a + 1; b < M; ++b) {
      if (model.meshes[a].triangle_count == 0 || model.meshes[b].triangle_count == 0) continue;
      const long between = intersecting_triangle_pairs(sim.x, triangles_of(model, a, b)) - within[a] - within[b];
      if (between > 0)
        report.refusals.push_back("the start state has " + std::to_string(between) +
                                  " intersecting triangle pairs between meshes " + quoted(model.meshes[a].name) +
                                  " and " + quoted(model.meshes[b].name));
    }

  // Obstacles, at their pose at t = sim.time, when contact with them is simulated.
  if (declares(sim, "obstacle_contact"))
    for (const Obstacle& o : sim.obstacles) {
      const Eigen::Isometry3d pose = o.pose(sim.time);
      for (std::size_t a = 0; a < M; ++a) {
        const MeshRange& r = model.meshes[a];
        long count = 0;
        if (o.kind == ShapeKind::mesh) {
          if (r.triangle_count == 0) continue;
          const Eigen::Matrix3Xd world = pose * o.mesh.positions;
          count = intersecting_triangle_pairs(sim.x, triangles_of(model, a, a), world, o.mesh.triangles);
          if (count > 0)
            report.refusals.push_back("the start state has " + std::to_string(count) + " triangles of mesh " +
                                      quoted(r.name) + " intersecting obstacle " + quoted(o.name));
          continue;
        }
        for (int i = r.first_vertex; i < r.first_vertex + r.vertex_count; ++i)
          if (surface_distance(o, pose, sim.x.col(i)).distance < 0) ++count;
        if (count > 0)
          report.refusals.push_back("the start state has " + std::to_string(count) + " vertices of mesh " +
                                    quoted(r.name) + " inside obstacle " + quoted(o.name));
      }
    }

  // Contact already active at the start: each effect's own test, as the first step sees it.
  StepContext ctx;
  ctx.frame = sim.frame + 1;
  ctx.dt = sim.solver.dt / sim.solver.steps_per_frame();  // the first step's
  ctx.time = sim.time + ctx.dt;
  ctx.model = &sim.model;
  const Eigen::Matrix3Xd x = sim.x, v = sim.v;
  ctx.x_start = &x;
  ctx.v_start = &v;
  for (const auto& e : sim.effects) {
    e->begin_step(ctx);
    e->evaluate(x, nullptr, nullptr);
    EffectCounters c;
    e->report(c);
    const std::pair<Counter, const char*> kinds[] = {
        {Counter::vertex_face_contacts, "vertex-face pairs are within the contact distance at the start"},
        {Counter::edge_edge_contacts, "edge-edge pairs are within the contact distance at the start"},
        {Counter::obstacle_contacts, "vertices are within the contact distance of an obstacle at the start"}};
    for (const auto& [key, what] : kinds) {
      if (!c.has(key) || !(c.at(key) > 0)) continue;
      report.warnings.push_back("effect " + quoted(e->name()) + ": " + std::to_string(static_cast<long>(c.at(key))) +
                                " " + what + " (their forces act from the first step" +
                                (key == Counter::obstacle_contacts
                                     ? ")"
                                     : "; within one mesh: the distance exceeds the mesh's own spacing)"));
    }
  }
  return report;
}

}  // namespace pce::sim
