// SPDX-License-Identifier: MIT
// The effects' scene loaders (effect_loaders.hpp): each reads its effect object, in the
// registry's order of effects, and calls the public builder `make_<name>`
// (pce/sim/effects.hpp) inside `Params::build`, so the builder's ArgumentError becomes an
// InputError at the field's JSON path.
#include "effect_loaders.hpp"

#include "../effects/arguments.hpp"
#include "../util/names.hpp"
#include "coverage.hpp"
#include "motion.hpp"
#include "obstacles.hpp"
#include "scene_names.hpp"

#include <pce/sim/effects.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace pce::sim {

namespace {

/// A contact effect's `penalty` object.
ContactPenalty parse_penalty(const Params& p) {
  ContactPenalty s;
  s.kind = p.choice<ContactPenalty::Kind>("type");
  if (s.kind == ContactPenalty::Kind::cubic)
    p.only({"type", "stiffness", "distance", "delta"});
  else
    p.only({"type", "stiffness", "distance"});
  s.stiffness = p.positive("stiffness");
  s.distance = p.positive("distance");
  s.delta = s.kind == ContactPenalty::Kind::cubic ? p.nonnegative("delta", 0.0) : 0.0;
  return s;
}

/// A contact effect's `friction` object.
FrictionSettings parse_friction(const Params& p) {
  p.only({"coefficient", "slip_velocity", "lagged_iterations"});
  FrictionSettings f;
  f.coefficient = p.nonnegative("coefficient");
  f.slip_velocity = p.positive("slip_velocity", f.slip_velocity);
  f.lagged_iterations = static_cast<int>(p.integer("lagged_iterations", 1, 1, 100));
  return f;
}

/// A self-contact effect's object (`self_vertex_face`, `self_edge_edge`); the broad phase
/// is the scene's.
ContactSettings parse_contact(const Params& p, const BuildContext& ctx) {
  if (p.has("exclude_rest_neighbours"))
    p.fail("exclude_rest_neighbours",
           "this option was removed: pairs of one mesh closer than 2d at rest are left out of the energy and "
           "kept in the step bound, so a sheet cannot fold through itself (delete the key)");
  p.only({"type", "meshes", "penalty", "length", "hessian", "closest_features", "ccd", "area_weighted",
          "min_separation", "friction"});
  ContactSettings s;
  s.penalty = parse_penalty(p.object("penalty"));
  s.signed_length = p.choice<LengthKind>("length", LengthKind::unsigned_length) == LengthKind::signed_length;
  s.closest_features = p.boolean("closest_features", false);
  s.ccd = p.boolean("ccd", true);
  s.hessian = p.choice_among("hessian", kContactHessians, Projection::analytic);
  s.broad_phase = ctx.broad_phase;
  s.area_weighted = p.boolean("area_weighted", false);
  s.min_separation = p.number("min_separation", kDefaultMinSeparation, 0.0, kMaxMinSeparation);
  if (p.has("friction")) s.friction = parse_friction(p.object("friction"));
  s.mesh_pairs = ctx.mesh_pairs;
  return s;
}

}  // namespace

std::unique_ptr<Effect> load_gravity(const Params& params, const BuildContext& ctx) {
  params.only({"type", "meshes", "acceleration"});
  const Eigen::Vector3d g = params.vec3("acceleration", Eigen::Vector3d(0, 0, -9.81));
  return params.build([&] { return make_gravity(*ctx.model, g); });
}

std::unique_ptr<Effect> load_stretching(const Params& params, const BuildContext& ctx) {
  params.only({"type", "meshes", "model", "stiffness"});
  params.choice<StretchingModel>("model", StretchingModel::arap);
  const double mu = params.positive("stiffness");
  return params.build([&] { return make_stretching(*ctx.model, mu); });
}

std::unique_ptr<Effect> load_volume_elasticity(const Params& params, const BuildContext& ctx) {
  params.only({"type", "meshes", "model", "young_modulus", "poisson_ratio", "mu", "lambda", "hessian"});
  params.choice<VolumeModel>("model", VolumeModel::stable_neo_hookean);
  const bool young = params.has("young_modulus") || params.has("poisson_ratio");
  const bool lame = params.has("mu") || params.has("lambda");
  if (young == lame)
    params.fail(young ? "mu" : "young_modulus",
                "expected either \"young_modulus\" and \"poisson_ratio\" or the Lamé parameters \"mu\" and "
                "\"lambda\", not both and not neither");
  StableNeoHookean material;
  if (young) {
    const double E = params.positive("young_modulus");
    const double nu = params.number("poisson_ratio");
    if (!(nu > -1 && nu < 0.5)) params.fail("poisson_ratio", "expected a number in (-1, 0.5), got " + args::text(nu));
    material = StableNeoHookean::from_young_poisson(E, nu);
  } else {
    const double mu = params.positive("mu");
    const double lambda = params.number("lambda");
    if (!(lambda > -mu))
      params.fail("lambda",
                  "expected the Lamé parameter lambda > -mu (a positive bulk modulus), got " + args::text(lambda));
    material = StableNeoHookean::from_lame(mu, lambda);
  }
  if (!material.valid()) params.fail(young ? "young_modulus" : "mu", "the material's moduli overflow");
  const VolumeProjection how = params.choice_among("hessian", kVolumeHessians, VolumeProjection::analytic);
  return params.build([&] { return make_volume_elasticity(*ctx.model, material, how); });
}

std::unique_ptr<Effect> load_bending(const Params& params, const BuildContext& ctx) {
  params.only({"type", "meshes", "stiffness"});
  const double k = params.positive("stiffness");
  return params.build([&] { return make_bending(*ctx.model, k); });
}

std::unique_ptr<Effect> load_strand_stretching(const Params& params, const BuildContext& ctx) {
  params.only({"type", "meshes", "stiffness"});
  const double k = params.positive("stiffness");
  return params.build([&] { return make_strand_stretching(*ctx.model, k); });
}

std::unique_ptr<Effect> load_strand_bending(const Params& params, const BuildContext& ctx) {
  params.only({"type", "meshes", "stiffness"});
  const double k = params.positive("stiffness");
  return params.build([&] { return make_strand_bending(*ctx.model, k); });
}

std::unique_ptr<Effect> load_pins(const Params& params, const BuildContext& ctx) {
  params.only({"type", "meshes", "stiffness", "groups"});
  const double k = params.positive("stiffness", 1e5);
  const Model& model = *ctx.model;
  // `meshes`: the meshes its groups may pin (every mesh without the key), read as the scene
  // loader reads the other types' `meshes`.
  std::vector<MeshRange> allowed;
  for (const int m : read_meshes(params, model, false).meshes)
    allowed.push_back(model.meshes[static_cast<std::size_t>(m)]);
  const std::string allowed_names = names_of(allowed);
  const auto pinnable = [&](int v) {
    if (allowed.empty()) return true;
    for (const MeshRange& r : allowed)
      if (v >= r.first_vertex && v < r.first_vertex + r.vertex_count) return true;
    return false;
  };
  const std::size_t group_count = params.array("groups", true).size();
  if (group_count == 0) params.fail("groups", "expected at least one pin group");
  std::vector<PinGroup> groups;
  for (std::size_t gi = 0; gi < group_count; ++gi) {
    const Params g = params.element("groups", gi);
    g.only({"vertices", "box", "mesh", "release_frame", "motion"});
    PinGroup group;
    if (g.has("release_frame"))
      group.release_frame = static_cast<int>(g.integer("release_frame", std::nullopt, 1));  // ≥ 1
    // The vertex range a group may name: one mesh's (local indices) or the whole model's.
    int first = 0, size = model.vertex_count();
    const std::string mesh = g.has("mesh") ? g.string("mesh") : std::string();
    if (g.has("mesh")) {
      const MeshRange* r = find_named(model.meshes, mesh);
      if (!r) g.fail("mesh", "no mesh named \"" + mesh + "\"");
      if (!pinnable(r->first_vertex))
        g.fail("mesh", "mesh \"" + mesh + "\" is not one of the entry's meshes (" + allowed_names + ")");
      first = r->first_vertex, size = r->vertex_count;
    }
    if (g.has("vertices") == g.has("box"))
      g.fail(g.has("box") ? "box" : "vertices", "expected exactly one of \"vertices\" and \"box\"");
    if (g.has("vertices")) {
      for (int i : g.indices("vertices", size)) group.vertices.push_back(first + i);
      if (group.vertices.empty()) g.fail("vertices", "expected at least one vertex index");
      for (const int v : group.vertices)
        if (!pinnable(v))
          g.fail("vertices",
                 "vertex " + std::to_string(v) + " is in none of the entry's meshes (" + allowed_names + ")");
    } else {
      const Params box = g.object("box");
      box.only({"min", "max"});
      const Eigen::Vector3d lo = box.vec3("min"), hi = box.vec3("max");
      group.vertices = box.build([&] { return vertices_in_box(model, lo, hi, mesh); });
      group.vertices.erase(
          std::remove_if(group.vertices.begin(), group.vertices.end(), [&](int v) { return !pinnable(v); }),
          group.vertices.end());
      if (group.vertices.empty())
        g.fail("box", allowed.empty()
                          ? "the box contains no vertex of the rest shape"
                          : "the box contains no vertex of the entry's meshes (" + allowed_names + ") at rest");
    }
    if (g.has("motion")) {
      const Params m = g.object("motion");
      m.only({"velocity", "angular_velocity", "center", "start", "stop", "keyframes", "interpolation"});
      group.motion = parse_motion(m);
      if (m.has("center")) group.centre = m.vec3("center");  // checked by make_pins (motion.center)
    }
    groups.push_back(std::move(group));
  }
  return params.build([&] { return make_pins(model, std::move(groups), k); });
}

std::unique_ptr<Effect> load_damping(const Params& params, const BuildContext& ctx) {
  params.only({"type", "meshes", "coefficient"});
  const double c = params.nonnegative("coefficient");
  return params.build([&] { return make_damping(*ctx.model, c); });
}

std::unique_ptr<Effect> load_self_vertex_face(const Params& params, const BuildContext& ctx) {
  const ContactSettings s = parse_contact(params, ctx);
  return params.build([&] { return make_self_vertex_face(*ctx.model, s); });
}

std::unique_ptr<Effect> load_self_edge_edge(const Params& params, const BuildContext& ctx) {
  const ContactSettings s = parse_contact(params, ctx);
  return params.build([&] { return make_self_edge_edge(*ctx.model, s); });
}

std::unique_ptr<Effect> load_obstacle_contact(const Params& params, const BuildContext& ctx) {
  params.only({"type", "meshes", "penalty", "obstacles", "area_weighted", "min_separation", "friction"});
  ObstacleContactSettings spec;
  spec.penalty = parse_penalty(params.object("penalty"));
  spec.area_weighted = params.boolean("area_weighted", false);
  spec.min_separation = params.number("min_separation", kDefaultMinSeparation, 0.0, kMaxMinSeparation);
  if (params.has("friction")) spec.friction = parse_friction(params.object("friction"));
  static const std::vector<Obstacle> none;
  const std::vector<Obstacle>& all = ctx.obstacles ? *ctx.obstacles : none;
  std::vector<Obstacle> chosen;  // its `obstacles`, already checked by the scene loader before any effect was built
  for (const int o : listed_obstacles(params, all)) chosen.push_back(all[static_cast<std::size_t>(o)]);
  return params.build([&] { return make_obstacle_contact(*ctx.model, chosen, spec); });
}

}  // namespace pce::sim
