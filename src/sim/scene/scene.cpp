// SPDX-License-Identifier: MIT
// Loading a scene (pce/sim/scene.hpp): the top-level sequence. In order: the JSON text, the
// settings (solver_settings.cpp), the meshes and the model built from them
// (mesh_sources.cpp), the obstacles (obstacles.cpp), then every effect entry's type and
// what it covers, checked between the entries of each type (coverage.cpp); only then is
// each effect built by its registered loader (registry.cpp, effect_loaders.cpp), which
// checks its own fields as it reads them. The first error ends the load; building never
// writes files.
#include <pce/sim/scene.hpp>

#include "../util/names.hpp"
#include "coverage.hpp"
#include "mesh_sources.hpp"
#include "obstacles.hpp"
#include "params.hpp"
#include "registry.hpp"
#include "solver_settings.hpp"

#include <fstream>
#include <memory>
#include <set>
#include <sstream>

namespace pce::sim {

namespace {

/// The meshes (unique names), the model built from them, and the obstacles (names unique
/// among meshes and obstacles) into `sim`.
void parse_bodies(const Params& root, const std::filesystem::path& base, Simulation& sim) {
  const nlohmann::json& meshes = root.array("meshes", true);
  if (meshes.empty()) root.fail("meshes", "expected at least one mesh");
  std::vector<ModelMesh> specs;
  std::set<std::string> names;
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    const Params p = root.element("meshes", k);
    specs.push_back(parse_mesh(p, base));
    if (!names.insert(specs.back().name).second) p.fail("name", "duplicate mesh name \"" + specs.back().name + "\"");
  }
  sim.model = root.build([&] { return build_model(specs); });
  const nlohmann::json& obstacles = root.array("obstacles");
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    const Params p = root.element("obstacles", k);
    sim.obstacles.push_back(parse_obstacle(p, base));
    if (!names.insert(sim.obstacles.back().name).second)
      p.fail("name", "duplicate name \"" + sim.obstacles.back().name + "\"");
  }
}

/// The JSON path of `effects[k]`.
std::string entry_path(std::size_t k) { return "effects[" + std::to_string(k) + "]"; }

/// Every entry of `effects`, read before anything is built: its registered
/// type, the command line's `hessian` written into a contact entry that takes it, and what
/// it covers (its `meshes`; an obstacle_contact entry's `obstacles`).
std::vector<EffectEntry> read_entries(nlohmann::json& effects, const std::string& file, const SceneOverrides& overrides,
                                      const Simulation& sim) {
  std::vector<EffectEntry> entries;
  for (std::size_t k = 0; k < effects.size(); ++k) {
    const Params p(effects[k], file, entry_path(k));  // points at effects[k]: sees the override below
    EffectEntry e;
    e.index = k;
    const std::string type = p.string("type");
    e.type = find_named(effect_registry(), type);
    if (!e.type)
      p.fail("type", "unknown effect \"" + type + "\" (expected one of: " + names_of(effect_registry(), "") + ")");
    if (e.type->pair_contact && overrides.hessian) effects[k]["hessian"] = std::string(name_of(*overrides.hessian));
    if (e.type->coverage != Coverage::none)
      e.meshes = read_meshes(p, sim.model, e.type->coverage == Coverage::mesh_pairs);
    if (e.type->coverage == Coverage::meshes_and_obstacles) e.obstacles = listed_obstacles(p, sim.obstacles);
    entries.push_back(std::move(e));
  }
  return entries;
}

/// Builds each of `entries` (read from `effects`) by its registered loader, in scene order,
/// into `scene`: an entry with `meshes` on the model restricted to them (kept in
/// `Simulation::effect_models`), a self-contact entry with its named mesh pairs.
void build_effects(const nlohmann::json& effects, const std::vector<EffectEntry>& entries, const std::string& file,
                   BroadPhaseKind broad_phase, Scene& scene) {
  Simulation& sim = scene.simulation;
  const auto mesh_name = [&](int m) { return sim.model.meshes[static_cast<std::size_t>(m)].name; };
  for (const EffectEntry& e : entries) {
    BuildContext ctx;
    ctx.model = &sim.model;
    ctx.obstacles = &sim.obstacles;
    ctx.broad_phase = broad_phase;
    if (e.meshes.given) {
      std::vector<std::string> names;
      for (const int m : e.meshes.meshes) names.push_back(mesh_name(m));
      sim.effect_models.push_back(std::make_unique<Model>(restrict_to_meshes(sim.model, names)));
      ctx.model = sim.effect_models.back().get();
      for (const auto& [a, b] : e.meshes.pairs) ctx.mesh_pairs.push_back({mesh_name(a), mesh_name(b)});
    }
    sim.effects.push_back(e.type->make(Params(effects[e.index], file, entry_path(e.index)), ctx));
  }
}

}  // namespace

std::unique_ptr<Scene> load_scene_text(const std::string& text, const std::string& name,
                                       const std::filesystem::path& base, const SceneOverrides& overrides) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // syntax errors, numbers beyond double's range
    throw InputError(name, "", std::string("not valid JSON: ") + e.what());
  }
  const Params root(j, name, "");
  root.only({"description", "dt", "frames", "solver", "meshes", "obstacles", "effects", "output_every",
             "view_direction", "allow_initial_intersections"});
  auto scene = std::make_unique<Scene>();
  Simulation& sim = scene->simulation;
  const BroadPhaseKind broad_phase = parse_settings(root, overrides, *scene);
  parse_bodies(root, base, sim);
  nlohmann::json effects = root.array("effects", true);  // a copy: the overrides are written into it
  if (effects.empty()) root.fail("effects", "expected at least one effect");
  const std::vector<EffectEntry> entries = read_entries(effects, name, overrides, sim);
  check_coverage(entries, name, sim.model, sim.obstacles);
  build_effects(effects, entries, name, broad_phase, *scene);
  sim.start_at_rest();
  return scene;
}

std::unique_ptr<Scene> load_scene(const std::filesystem::path& file, const SceneOverrides& overrides) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "", "cannot open the scene file");
  std::stringstream text;
  text << in.rdbuf();
  auto scene = load_scene_text(text.str(), file.string(), file.parent_path(), overrides);
  scene->file = file;
  return scene;
}

}  // namespace pce::sim
