// SPDX-License-Identifier: MIT
// The scene's obstacles (obstacles.hpp): each shape's keys and sizes, a mesh obstacle's file
// (with its transform, checked by `validate`, and triangles required), the placement and the
// motion; and the names an obstacle_contact entry lists, looked up among them.
#include "obstacles.hpp"

#include "../effects/arguments.hpp"
#include "../util/names.hpp"
#include "mesh_sources.hpp"
#include "motion.hpp"

#include <set>
#include <string>

namespace pce::sim {

Obstacle parse_obstacle(const Params& p, const std::filesystem::path& base) {
  Obstacle o;
  o.name = p.string("name");
  o.kind = p.choice<ShapeKind>("shape");
  switch (o.kind) {
    case ShapeKind::sphere:
      p.only({"name", "shape", "radius", "position", "rotation", "motion"});
      o.radius = p.checked("radius", args::length);
      break;
    case ShapeKind::box:
      p.only({"name", "shape", "half_extents", "position", "rotation", "motion"});
      o.half_extents = p.checked_vec3("half_extents", args::position);
      if (!(o.half_extents.minCoeff() > 0)) p.fail("half_extents", "expected three numbers > 0");
      break;
    case ShapeKind::capsule:
      p.only({"name", "shape", "radius", "half_length", "position", "rotation", "motion"});
      o.radius = p.checked("radius", args::length);
      o.half_length = p.checked("half_length", args::length);
      break;
    case ShapeKind::mesh:
      p.only({"name", "shape", "file", "transform", "position", "rotation", "motion"});
      o.mesh = read_mesh_file(p, "file", base);
      if (p.has("transform")) apply(parse_transform(p.object("transform")), o.mesh);
      try {
        validate(o.mesh, p.file());
      } catch (const InputError& e) {
        p.fail("file", e.what());
      }
      if (o.mesh.triangles.cols() == 0) p.fail("file", "a mesh obstacle needs triangles");
      break;
  }
  o.position = p.checked_vec3("position", args::position, Eigen::Vector3d::Zero());
  if (p.has("rotation")) o.rotation = parse_rotation(p.object("rotation"));
  if (p.has("motion")) {
    const Params m = p.object("motion");
    m.only({"velocity", "angular_velocity", "start", "stop", "keyframes", "interpolation"});
    o.motion = parse_motion(m);
  }
  return o;
}

std::vector<int> listed_obstacles(const Params& p, const std::vector<Obstacle>& obstacles) {
  std::vector<int> listed;
  if (!p.has("obstacles")) {
    for (std::size_t k = 0; k < obstacles.size(); ++k) listed.push_back(static_cast<int>(k));
    return listed;
  }
  const nlohmann::json& names = p.array("obstacles");
  if (names.empty()) p.fail("obstacles", "expected at least one obstacle name (leave the field out for all)");
  std::set<std::string> seen;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const std::string where = p.path_of("obstacles") + "[" + std::to_string(k) + "]";
    if (!names[k].is_string()) throw InputError(p.file(), where, "expected an obstacle name (a string)");
    const std::string name = names[k].get<std::string>();
    const Obstacle* o = find_named(obstacles, name);
    if (!o) {
      const std::string known = names_of(obstacles);
      throw InputError(
          p.file(), where,
          "unknown obstacle \"" + name + "\" (the scene's obstacles: " + (known.empty() ? "none" : known) + ")");
    }
    if (!seen.insert(name).second) throw InputError(p.file(), where, "obstacle \"" + name + "\" listed twice");
    listed.push_back(static_cast<int>(o - obstacles.data()));
  }
  return listed;
}

}  // namespace pce::sim
