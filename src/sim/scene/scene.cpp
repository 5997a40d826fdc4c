// SPDX-License-Identifier: MIT
// Scene parsing, validation and building (scene.hpp). Parsing and validation finish before
// anything is built, and building never writes files.
#include <pce/sim/scene.hpp>

#include "../effects/arguments.hpp"
#include "params.hpp"
#include "registry.hpp"
#include "scene_names.hpp"

#include <pce/sim/generators.hpp>
#include <pce/sim/obj.hpp>
#include <pce/sim/tet_io.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace pce::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// The scene's time step dt (s): from a microsecond (beyond any vibration a stiffness
/// ≤ 1e12 on a mass a density ≥ 1e-9 gives needs to resolve) to one second (a frame of a
/// slow-motion sequence; a step's free fall g·dt² stays ≤ kMaxCoordinate). Keeps M/dt²,
/// v = Δx/dt and the time frames·dt (≤ 1e7 s) finite and normal.
constexpr double kMinDt = 1e-6, kMaxDt = 1.0;
/// A transform's uniform scale: [1e-6, 1e6] (a mesh in µm to one in Mm); the transformed
/// coordinates are then checked against `kMaxCoordinate` by `validate`.
constexpr double kMinScale = 1e-6, kMaxScale = 1e6;

/// The number at `key` (finite, `fallback` when absent) passed through a builder's check
/// `check(field, value)` (`args::length`, …): its error names `key`'s JSON path.
template <class Check>
double checked(const Params& p, const std::string& key, Check check, std::optional<double> fallback = std::nullopt) {
  const double v = p.number(key, fallback);
  return p.build([&] { return check(key, v); });
}

/// The 3-vector at `key` passed through `check(field, value)` (`args::position`, …).
template <class Check> Eigen::Vector3d checked_vec3(const Params& p, const std::string& key, Check check,
                                                    std::optional<Eigen::Vector3d> fallback = std::nullopt) {
  const Eigen::Vector3d v = p.vec3(key, fallback);
  return p.build([&] { return Eigen::Vector3d(check(key, v)); });
}

Eigen::Matrix3d parse_rotation(const Params& p) {
  p.only({"axis", "degrees"});
  const Eigen::Vector3d axis = p.vec3("axis");
  const double largest = axis.cwiseAbs().maxCoeff();
  if (!(largest > 0)) p.fail("axis", "expected a non-zero axis");
  const double degrees = p.number("degrees");  // any finite angle: only its sine and cosine are used
  // Scaled by the largest component first: a tiny axis (1e-200) would underflow its norm.
  return Eigen::AngleAxisd(degrees * kPi / 180.0, (axis / largest).normalized()).toRotationMatrix();
}

}  // namespace

Motion parse_motion(const Params& m) {
  Motion motion;
  if (m.has("keyframes")) {
    for (const char* key : {"velocity", "angular_velocity", "start", "stop"})
      if (m.has(key))
        m.fail(key,
               "a motion has either \"keyframes\" or a constant velocity (\"velocity\", \"angular_velocity\", "
               "\"start\", \"stop\"), not both");
    const std::size_t count = m.array("keyframes", true).size();
    if (count == 0) m.fail("keyframes", "expected at least one keyframe");
    for (std::size_t k = 0; k < count; ++k) {
      const Params f = m.element("keyframes", k);
      f.only({"time", "translation", "rotation"});
      Keyframe key;
      key.time = f.number("time");
      key.translation = f.vec3("translation", Eigen::Vector3d::Zero());
      if (f.has("rotation")) key.rotation = parse_rotation(f.object("rotation"));
      motion.keyframes.push_back(key);
    }
    motion.interpolation = m.choice<Interpolation>("interpolation", Interpolation::linear);
    m.build([&] { args::motion("", motion); });  // times, their order, translations: named by their path
    return motion;
  }
  if (m.has("interpolation")) m.fail("interpolation", "an interpolation is between \"keyframes\": give them too");
  motion.velocity = checked_vec3(m, "velocity", args::speed, Eigen::Vector3d::Zero());
  motion.angular_velocity = checked_vec3(m, "angular_velocity", args::speed, Eigen::Vector3d::Zero());
  motion.start = m.nonnegative("start", 0.0);
  motion.stop = m.has("stop") ? m.nonnegative("stop") : std::numeric_limits<double>::infinity();
  if (motion.stop < motion.start) m.fail("stop", "expected stop >= start");
  return motion;
}

namespace {

Transform parse_transform(const Params& p) {
  p.only({"translation", "rotation", "scale"});
  Transform t;
  t.translation = checked_vec3(p, "translation", args::position, Eigen::Vector3d::Zero());
  if (p.has("rotation")) t.rotation = parse_rotation(p.object("rotation"));
  t.scale = p.number("scale", 1.0);
  if (!(t.scale >= kMinScale && t.scale <= kMaxScale))
    p.fail("scale", "expected a number in [" + args::limit_text(kMinScale) + ", " + args::limit_text(kMaxScale) +
                        "] (the scales pce::sim accepts), got " + args::text(t.scale));
  return t;
}

/// Reads a mesh file relative to the scene; errors name the scene field and the mesh file.
Mesh read_mesh(const Params& p, const std::string& key, const std::filesystem::path& base) {
  const std::string rel = p.string(key);
  const std::filesystem::path path = base / rel;
  if (!std::filesystem::exists(path)) p.fail(key, "mesh file not found: " + path.string());
  try {
    return is_tet_mesh_file(path) ? read_tet_mesh(path) : read_obj(path);
  } catch (const InputError& e) {
    p.fail(key, std::string("malformed mesh: ") + e.what());
  }
}

Mesh parse_generator(const Params& g) {
  const GeneratorKind type = g.choice<GeneratorKind>("type");
  try {  // the generators check their own limits too; their errors are named by this field
    // Every case but strands returns; strands is read after the switch.
    switch (type) {
      case GeneratorKind::tet_box: {
        g.only({"type", "size", "n"});
        const Eigen::Vector3d size = checked_vec3(g, "size", args::position);
        if (!(size.minCoeff() > 0)) g.fail("size", "expected three numbers > 0");
        const Eigen::Vector3d nd = g.vec3("n");
        Eigen::Vector3i n;
        for (int k = 0; k < 3; ++k) {
          if (!(nd[k] >= 1 && nd[k] <= 256 && nd[k] == std::floor(nd[k])))
            g.fail("n", "expected three integers in [1, 256] (cubes per side)");
          n[k] = static_cast<int>(nd[k]);
        }
        return tet_box(size, n);
      }
      case GeneratorKind::tet_ball: {
        g.only({"type", "radius", "n"});
        const double radius = checked(g, "radius", args::length);
        const int n = static_cast<int>(g.integer("n", std::nullopt, 1, 127));
        return tet_ball(radius, n);
      }
      case GeneratorKind::grid: {
        g.only({"type", "width", "height", "nx", "ny"});
        const double width = checked(g, "width", args::length), height = checked(g, "height", args::length);
        const int nx = static_cast<int>(g.integer("nx", std::nullopt, 1, 4096));
        const int ny = static_cast<int>(g.integer("ny", std::nullopt, 1, 4096));
        return grid(width, height, nx, ny);
      }
      case GeneratorKind::strands:
        break;
    }
    g.only({"type", "count", "segments", "length", "spacing", "curl"});
    const int count = static_cast<int>(g.integer("count", std::nullopt, 1, 1L << 20));
    const int segments = static_cast<int>(g.integer("segments", std::nullopt, 1, 1L << 16));
    const double length = checked(g, "length", args::length), spacing = checked(g, "spacing", args::length);
    const double curl = checked(
        g, "curl",
        [](const std::string& f, double v) {
          return args::nonnegative_at_most(f, v, kMaxCoordinate, "the largest length pce::sim accepts, in m");
        },
        0.0);
    return strands(count, segments, length, spacing, curl);
  } catch (const InputError& e) {
    if (e.file() == g.file()) throw;  // already names the scene field
    g.fail("type", e.what());
  }
}

ModelMesh parse_mesh(const Params& p, const std::filesystem::path& base) {
  p.only({"name", "file", "generator", "transform", "density", "linear_density"});
  ModelMesh s;
  s.name = p.string("name");
  if (p.has("file") == p.has("generator")) p.fail("file", "expected exactly one of \"file\" or \"generator\"");
  s.mesh = p.has("file") ? read_mesh(p, "file", base) : parse_generator(p.object("generator"));
  if (p.has("transform")) apply(parse_transform(p.object("transform")), s.mesh);
  try {
    validate(s.mesh, p.file());
  } catch (const InputError& e) {
    p.fail(p.has("file") ? "file" : "generator", e.what());
  }
  const bool volume = s.mesh.tetrahedra.cols() > 0;
  if (volume && p.has("linear_density"))
    p.fail("linear_density", "a volume (a mesh with tetrahedra) has no segments: give its \"density\" in kg/m³");
  s.density = p.positive("density", volume ? 1000.0 : 0.1);
  s.linear_density = p.positive("linear_density", 0.005);
  return s;
}

Obstacle parse_obstacle(const Params& p, const std::filesystem::path& base) {
  Obstacle o;
  o.name = p.string("name");
  o.kind = p.choice<ShapeKind>("shape");
  switch (o.kind) {
    case ShapeKind::sphere:
      p.only({"name", "shape", "radius", "position", "rotation", "motion"});
      o.radius = checked(p, "radius", args::length);
      break;
    case ShapeKind::box:
      p.only({"name", "shape", "half_extents", "position", "rotation", "motion"});
      o.half_extents = checked_vec3(p, "half_extents", args::position);
      if (!(o.half_extents.minCoeff() > 0)) p.fail("half_extents", "expected three numbers > 0");
      break;
    case ShapeKind::capsule:
      p.only({"name", "shape", "radius", "half_length", "position", "rotation", "motion"});
      o.radius = checked(p, "radius", args::length);
      o.half_length = checked(p, "half_length", args::length);
      break;
    case ShapeKind::mesh:
      p.only({"name", "shape", "file", "transform", "position", "rotation", "motion"});
      o.mesh = read_mesh(p, "file", base);
      if (p.has("transform")) apply(parse_transform(p.object("transform")), o.mesh);
      try {
        validate(o.mesh, p.file());
      } catch (const InputError& e) {
        p.fail("file", e.what());
      }
      if (o.mesh.triangles.cols() == 0) p.fail("file", "a mesh obstacle needs triangles");
      break;
  }
  o.position = checked_vec3(p, "position", args::position, Eigen::Vector3d::Zero());
  if (p.has("rotation")) o.rotation = parse_rotation(p.object("rotation"));
  if (p.has("motion")) {
    const Params m = p.object("motion");
    m.only({"velocity", "angular_velocity", "start", "stop", "keyframes", "interpolation"});
    o.motion = parse_motion(m);
  }
  return o;
}

/// The top level's numbers and `solver` (then the command line's overrides) into `scene`;
/// returns the broad phase the contact effects are to use.
BroadPhaseKind parse_settings(const Params& root, const SceneOverrides& overrides, Scene& scene) {
  Simulation& sim = scene.simulation;
  sim.solver.dt = root.number("dt");
  if (!(sim.solver.dt >= kMinDt && sim.solver.dt <= kMaxDt))
    root.fail("dt", "expected a number in [" + args::limit_text(kMinDt) + ", " + args::limit_text(kMaxDt) +
                        "] (the time steps pce::sim accepts, in s), got " + args::text(sim.solver.dt));
  sim.frames = static_cast<int>(root.integer("frames", std::nullopt, 1, 10000000));
  scene.output_every = static_cast<int>(root.integer("output_every", 1L, 1, 10000000));
  if (root.has("view_direction")) {
    scene.view_direction = root.vec3("view_direction");
    if (!(scene.view_direction.norm() > 0)) root.fail("view_direction", "expected a non-zero direction");
  }
  scene.allow_initial_intersections = root.boolean("allow_initial_intersections", false);
  BroadPhaseKind broad_phase = BroadPhaseKind::fcl;
  if (root.has("solver")) {
    const Params s = root.object("solver");
    s.only({"mode", "iterations", "tolerance", "max_iterations", "linear_solver", "threads", "broad_phase"});
    sim.solver.mode = s.choice<SolverMode>("mode", SolverMode::newton);
    if (s.has("iterations") && sim.solver.mode != SolverMode::block_descent)
      s.fail("iterations",
             "only \"mode\": \"block_descent\" takes a number of iterations (Newton's cap is "
             "\"max_iterations\")");
    sim.solver.iterations = static_cast<int>(s.integer("iterations", long{kDefaultBlockIterations}, 1, 100000));
    sim.solver.tolerance = s.positive("tolerance", sim.solver.tolerance);
    sim.solver.max_iterations = static_cast<int>(s.integer("max_iterations", 50L, 1, 100000));
    sim.solver.linear = s.choice<LinearSolver>("linear_solver", LinearSolver::direct);
    sim.solver.threads = static_cast<int>(s.integer("threads", 0L, 0, 1024));
    broad_phase = s.choice<BroadPhaseKind>("broad_phase", BroadPhaseKind::fcl);
  }
  if (overrides.frames) sim.frames = *overrides.frames;
  if (overrides.threads) sim.solver.threads = *overrides.threads;
  if (overrides.single_solve && *overrides.single_solve) sim.solver.mode = SolverMode::single_solve;
  if (overrides.mode) sim.solver.mode = *overrides.mode;
  if (overrides.iterations) {  // an override (--iterations): named at the key it replaces
    if (sim.solver.mode != SolverMode::block_descent)
      root.fail("solver.iterations",
                "a number of sweeps (--iterations) needs the block_descent mode, and this "
                "scene's is " +
                    std::string(name_of(sim.solver.mode)) + " (--mode block_descent selects it)");
    if (*overrides.iterations < 1) root.fail("solver.iterations", "expected an integer >= 1 (--iterations)");
    sim.solver.iterations = *overrides.iterations;
  }
  if (overrides.tolerance) sim.solver.tolerance = *overrides.tolerance;
  if (overrides.broad_phase) broad_phase = *overrides.broad_phase;
  return broad_phase;
}

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

/// The listed effects, each built by its registered loader (only the listed ones are built),
/// into `sim`; a contact effect's `hessian` is the override's when there is one.
void build_effects(const Params& root, const std::string& name, const SceneOverrides& overrides,
                   BroadPhaseKind broad_phase, Simulation& sim) {
  BuildContext ctx;
  ctx.model = &sim.model;
  ctx.obstacles = &sim.obstacles;
  ctx.dt = sim.solver.dt;
  ctx.broad_phase = broad_phase;
  ctx.threads = sim.solver.threads;
  nlohmann::json effects = root.array("effects", true);  // a copy: overrides are applied to it
  if (effects.empty()) root.fail("effects", "expected at least one effect");
  std::set<std::string> declared;
  for (std::size_t k = 0; k < effects.size(); ++k) {
    const Params p(effects[k], name, "effects[" + std::to_string(k) + "]");
    const std::string type = p.string("type");
    const RegisteredEffect* reg = nullptr;
    std::string known;
    for (const auto& r : effect_registry()) {
      if (type == r.name) reg = &r;
      known += (known.empty() ? "" : ", ") + std::string(r.name);
    }
    if (!reg) p.fail("type", "unknown effect \"" + type + "\" (expected one of: " + known + ")");
    if (!declared.insert(type).second) p.fail("type", "effect \"" + type + "\" is declared twice");
    if (reg->pair_contact && overrides.hessian) effects[k]["hessian"] = std::string(name_of(*overrides.hessian));
    const Params q(effects[k], name, "effects[" + std::to_string(k) + "]");
    sim.effects.push_back(reg->make(q, ctx));
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
  const BroadPhaseKind broad_phase = parse_settings(root, overrides, *scene);
  parse_bodies(root, base, scene->simulation);
  build_effects(root, name, overrides, broad_phase, scene->simulation);
  scene->simulation.start_at_rest();
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
