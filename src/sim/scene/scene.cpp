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

#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>

namespace pce::sim {

namespace {

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
  return axis_rotation(axis, degrees);
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
    // qualified: a unity build (tests/fuzz) also sees registry.cpp's strands(MeshRange, MeshRange)
    return sim::strands(count, segments, length, spacing, curl);
  } catch (const InputError& e) {
    if (e.file() == g.file()) throw;  // already names the scene field
    g.fail("type", e.what());
  }
}

/// The rows of the array `key` (absent: none), each an array of N vertex indices in
/// [0, `vertices`) with no vertex twice, as the columns of a matrix; `what` names a row
/// ("triangle"). Errors name the row or the index (`triangles[4][2]`).
template <int N> Eigen::Matrix<int, N, Eigen::Dynamic> index_rows(const Params& p, const std::string& key,
                                                                  Eigen::Index vertices, const char* what) {
  const nlohmann::json& rows = p.array(key);
  const std::string range = "[0, " + std::to_string(vertices) + ")";
  Eigen::Matrix<int, N, Eigen::Dynamic> out(N, static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::string row = "[" + std::to_string(r) + "]";
    if (!rows[r].is_array() || rows[r].size() != N)
      p.fail(key + row, "expected a " + std::string(what) + ": an array of " + std::to_string(N) + " vertex indices");
    for (int k = 0; k < N; ++k) {
      const nlohmann::json& v = rows[r][static_cast<std::size_t>(k)];
      const std::string at = key + row + "[" + std::to_string(k) + "]";
      if (!v.is_number_integer()) p.fail(at, "expected a vertex index (an integer) in " + range + ", got " + v.dump());
      // an unsigned beyond int64's range is out of range too: its text, not a wrapped value
      const std::int64_t i = v.is_number_unsigned() && v.get<std::uint64_t>() > std::uint64_t{1} << 62
                                 ? std::numeric_limits<std::int64_t>::max()
                                 : v.get<std::int64_t>();
      if (i < 0 || i >= vertices) p.fail(at, "expected a vertex index in " + range + ", got " + v.dump());
      out(k, static_cast<Eigen::Index>(r)) = static_cast<int>(i);
      for (int m = 0; m < k; ++m)
        if (out(m, static_cast<Eigen::Index>(r)) == i)
          p.fail(key + row, "the " + std::string(what) + " uses vertex " + std::to_string(i) + " twice");
    }
  }
  return out;
}

/// A mesh written in the scene (`vertices` and `triangles`, `segments` or `tetrahedra`):
/// every coordinate a number within ±kMaxCoordinate, every index in range and no element
/// repeating a vertex, errors naming the element (`vertices[3][1]`, `triangles[4][2]`). A
/// volume's triangles are its boundary faces; `validate`'s checks of the tetrahedra
/// (orientation, size, shared faces) name `tetrahedra`.
Mesh parse_inline_mesh(const Params& p) {
  const nlohmann::json& rows = p.array("vertices", true);
  if (rows.empty()) p.fail("vertices", "expected at least one vertex");
  if (static_cast<long>(rows.size()) > kMaxVertices)
    p.fail("vertices",
           "expected at most " + std::to_string(kMaxVertices) + " vertices, got " + std::to_string(rows.size()));
  Mesh m;
  m.positions.resize(3, static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::string row = "vertices[" + std::to_string(r) + "]";
    if (!rows[r].is_array() || rows[r].size() != 3) p.fail(row, "expected a vertex: an array of 3 numbers [x, y, z]");
    for (int k = 0; k < 3; ++k) {
      const nlohmann::json& c = rows[r][static_cast<std::size_t>(k)];
      const std::string at = row + "[" + std::to_string(k) + "]";
      const double v = c.is_number() ? c.get<double>() : std::numeric_limits<double>::quiet_NaN();
      if (!(std::abs(v) <= kMaxCoordinate))
        p.fail(at, "expected a number in [-" + args::limit_text(kMaxCoordinate) + ", " +
                       args::limit_text(kMaxCoordinate) + "] (the coordinates pce::sim accepts, in m), got " +
                       (c.is_number() ? args::text(v) : c.dump()));
      m.positions(k, static_cast<Eigen::Index>(r)) = v;
    }
  }
  const Eigen::Index n = m.vertex_count();
  m.triangles = index_rows<3>(p, "triangles", n, "triangle");
  m.segments = index_rows<2>(p, "segments", n, "segment");
  m.tetrahedra = index_rows<4>(p, "tetrahedra", n, "tetrahedron");
  if (m.tetrahedra.cols() > 0) {
    for (const char* key : {"triangles", "segments"})
      if (p.has(key))
        p.fail(key, std::string("a mesh with \"tetrahedra\" is a volume: its triangles are its boundary faces, and "
                                "it has no segments; leave \"") +
                        key + "\" out");
    m.triangles = boundary_faces(m.tetrahedra);
    try {
      validate(m, p.file());
    } catch (const InputError& e) {
      p.fail("tetrahedra", e.what());
    }
  } else if (m.triangles.cols() + m.segments.cols() == 0) {
    p.fail("vertices", "expected \"triangles\", \"segments\" or \"tetrahedra\" with the vertices");
  }
  return m;
}

ModelMesh parse_mesh(const Params& p, const std::filesystem::path& base) {
  p.only({"name", "file", "generator", "vertices", "triangles", "segments", "tetrahedra", "transform", "density",
          "linear_density"});
  ModelMesh s;
  s.name = p.string("name");
  const int sources = int{p.has("file")} + int{p.has("generator")} + int{p.has("vertices")};
  const char* const source = p.has("file") ? "file" : p.has("generator") ? "generator" : "vertices";
  if (sources != 1)
    p.fail(sources == 0        ? "file"
           : p.has("vertices") ? "vertices"
                               : "generator",
           "expected exactly one of \"file\", \"generator\" or \"vertices\"");
  if (!p.has("vertices"))
    for (const char* key : {"triangles", "segments", "tetrahedra"})
      if (p.has(key)) p.fail(key, "the elements of a mesh given by its \"vertices\": give them too");
  if (p.has("file"))
    s.mesh = read_mesh(p, "file", base);
  else if (p.has("generator"))
    s.mesh = parse_generator(p.object("generator"));
  else
    s.mesh = parse_inline_mesh(p);
  if (p.has("transform")) apply(parse_transform(p.object("transform")), s.mesh);
  try {
    validate(s.mesh, p.file());
  } catch (const InputError& e) {
    p.fail(source, e.what());
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

/// An entry's `meshes`, read: the mesh indices it names (sorted), or its pairs (a ≤ b).
struct MeshSelection {
  bool given = false;                     ///< the entry has `meshes`
  std::vector<int> meshes;                ///< named meshes (the union of its pairs when pairs)
  std::vector<std::array<int, 2>> pairs;  ///< named pairs, when given as pairs
};

/// Reads entry `p`'s `meshes` (names, or for self contact pairs of names) against `model`.
MeshSelection parse_meshes(const Params& p, const Model& model, Coverage coverage) {
  MeshSelection s;
  if (!p.has("meshes")) return s;
  s.given = true;
  const nlohmann::json& list = p.array("meshes");
  if (list.empty()) p.fail("meshes", "expected at least one mesh name (leave the field out for every mesh)");
  std::string known;
  for (const MeshRange& r : model.meshes) known += (known.empty() ? "" : ", ") + ("\"" + r.name + "\"");
  const auto index = [&](const nlohmann::json& name, const std::string& where) {
    if (!name.is_string()) throw InputError(p.file(), where, "expected a mesh name (a string)");
    for (std::size_t k = 0; k < model.meshes.size(); ++k)
      if (model.meshes[k].name == name.get<std::string>()) return static_cast<int>(k);
    throw InputError(p.file(), where,
                     "unknown mesh \"" + name.get<std::string>() + "\" (the scene's meshes: " + known + ")");
  };
  const bool pairs = list[0].is_array();
  if (pairs && coverage != Coverage::mesh_pairs)
    throw InputError(p.file(), p.path_of("meshes") + "[0]", "expected a mesh name (pairs are for self contact)");
  std::set<int> named;
  std::set<std::array<int, 2>> seen;
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string where = p.path_of("meshes") + "[" + std::to_string(k) + "]";
    if (!pairs) {
      const int m = index(list[k], where);
      if (!named.insert(m).second)
        throw InputError(p.file(), where,
                         "mesh \"" + model.meshes[static_cast<std::size_t>(m)].name + "\" named twice");
      continue;
    }
    if (!list[k].is_array() || list[k].size() != 2)
      throw InputError(p.file(), where, "expected a pair of mesh names, [\"a\", \"b\"] (or every entry a name)");
    const int a = index(list[k][0], where + "[0]"), b = index(list[k][1], where + "[1]");
    const std::array<int, 2> pair{std::min(a, b), std::max(a, b)};
    if (!seen.insert(pair).second) throw InputError(p.file(), where, "pair named twice");
    s.pairs.push_back(pair);
    named.insert(a);
    named.insert(b);
  }
  s.meshes.assign(named.begin(), named.end());
  return s;
}

/// What one effect entry covers (for the checks between entries of one type): its meshes, or
/// mesh pairs a·M + b (a ≤ b), or (mesh, obstacle) pairs m·O + o.
struct Covered {
  std::size_t entry;
  bool given;
  std::vector<long> units;
};

/// A unit's name in messages.
std::string unit_name(Coverage c, long u, const Model& model, const std::vector<Obstacle>& obstacles) {
  const auto mesh = [&](long m) { return "\"" + model.meshes[static_cast<std::size_t>(m)].name + "\""; };
  const long M = static_cast<long>(model.meshes.size()), O = static_cast<long>(obstacles.size());
  switch (c) {
    case Coverage::mesh_pairs:
      return "the mesh pair [" + mesh(u / M) + ", " + mesh(u % M) + "]";
    case Coverage::meshes_and_obstacles:
      return "mesh " + mesh(u / O) + " against obstacle \"" + obstacles[static_cast<std::size_t>(u % O)].name + "\"";
    default:
      return "mesh " + mesh(u);
  }
}

/// Entries of one type neither overlap (a unit in two) nor leave a gap (a mesh, or mesh
/// pair, that has what the type acts on but no entry covers); entries with `meshes` name only
/// units that have it. Errors name the entry and the other entry involved.
void check_coverage(const RegisteredEffect& reg, const std::vector<Covered>& entries, const std::string& file,
                    const Model& model, const std::vector<Obstacle>& obstacles) {
  const long M = static_cast<long>(model.meshes.size()), O = static_cast<long>(obstacles.size());
  const auto at = [&](const Covered& c) {
    return "effects[" + std::to_string(c.entry) + "]" + (c.given ? ".meshes" : "");
  };
  const auto relevant = [&](long u) {
    const MeshRange* a = nullptr;
    const MeshRange* b = nullptr;
    if (reg.coverage == Coverage::mesh_pairs) {
      a = &model.meshes[static_cast<std::size_t>(u / M)];
      b = &model.meshes[static_cast<std::size_t>(u % M)];
    } else {
      a = b = &model.meshes[static_cast<std::size_t>(reg.coverage == Coverage::meshes_and_obstacles ? u / O : u)];
    }
    return reg.has(*a, *b);
  };
  std::map<long, std::size_t> owner;  // unit → index into entries
  for (std::size_t j = 0; j < entries.size(); ++j) {
    const Covered& c = entries[j];
    for (const long u : c.units) {
      if (c.given && !relevant(u))
        throw InputError(file, at(c),
                         unit_name(reg.coverage, u, model, obstacles) + " has no " + reg.what + " for " + reg.name);
      const auto [it, fresh] = owner.emplace(u, j);
      if (!fresh) {
        const Covered& other = entries[it->second];
        throw InputError(file, at(c),
                         unit_name(reg.coverage, u, model, obstacles) + " is also covered by effects[" +
                             std::to_string(other.entry) + "] (" + reg.name + "): each takes one " + reg.name +
                             " entry (name each entry's \"meshes\")");
      }
    }
  }
  // Gaps: every unit that has what the type acts on (for obstacle contact: every mesh that
  // meets some obstacle in no entry at all).
  std::vector<long> all;
  if (reg.coverage == Coverage::mesh_pairs) {
    for (long a = 0; a < M; ++a)
      for (long b = a; b < M; ++b) all.push_back(a * M + b);
  } else if (reg.coverage == Coverage::meshes) {
    for (long a = 0; a < M; ++a) all.push_back(a);
  }
  for (const long u : all)
    if (relevant(u) && !owner.count(u)) {
      std::string list;
      for (const Covered& c : entries)
        list += (list.empty() ? "" : ", ") + ("effects[" + std::to_string(c.entry) + "]");
      throw InputError(file, at(entries.front()),
                       unit_name(reg.coverage, u, model, obstacles) + " (with " + reg.what + ") is in no " + reg.name +
                           " entry (" + list + "): name it in one");
    }
  if (reg.coverage == Coverage::meshes_and_obstacles)
    for (long m = 0; m < M; ++m) {
      bool met = O == 0;
      for (long o = 0; o < O && !met; ++o) met = owner.count(m * O + o) > 0;
      if (!met)
        throw InputError(
            file, at(entries.front()),
            unit_name(Coverage::meshes, m, model, obstacles) + " is in no obstacle_contact entry: name it in one");
    }
}

/// The obstacles an obstacle_contact entry lists (indices; every obstacle without the key).
/// The loader checks the names; unknown ones are skipped here.
std::vector<long> listed_obstacles(const Params& p, const std::vector<Obstacle>& obstacles) {
  std::vector<long> out;
  if (!p.has("obstacles")) {
    for (std::size_t o = 0; o < obstacles.size(); ++o) out.push_back(static_cast<long>(o));
    return out;
  }
  for (const nlohmann::json& name : p.array("obstacles"))
    for (std::size_t o = 0; o < obstacles.size(); ++o)
      if (name.is_string() && obstacles[o].name == name.get<std::string>()) out.push_back(static_cast<long>(o));
  return out;
}

/// The listed effects, each built by its registered loader (only the listed ones are built),
/// into `scene`; an entry with `meshes` is built on the model restricted to them (kept in
/// `Scene::effect_models`); a contact effect's `hessian` is the override's when there is one.
void build_effects(const Params& root, const std::string& name, const SceneOverrides& overrides,
                   BroadPhaseKind broad_phase, Scene& scene) {
  Simulation& sim = scene.simulation;
  BuildContext ctx;
  ctx.obstacles = &sim.obstacles;
  ctx.dt = sim.solver.dt;
  ctx.broad_phase = broad_phase;
  ctx.threads = sim.solver.threads;
  nlohmann::json effects = root.array("effects", true);  // a copy: overrides are applied to it
  if (effects.empty()) root.fail("effects", "expected at least one effect");
  const long M = static_cast<long>(sim.model.meshes.size()), O = static_cast<long>(sim.obstacles.size());
  std::map<const RegisteredEffect*, std::vector<Covered>> coverage;
  std::vector<const RegisteredEffect*> order;
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
    if (reg->pair_contact && overrides.hessian) effects[k]["hessian"] = std::string(name_of(*overrides.hessian));
    const Params q(effects[k], name, "effects[" + std::to_string(k) + "]");
    const MeshSelection sel =
        reg->coverage == Coverage::none ? MeshSelection{} : parse_meshes(q, sim.model, reg->coverage);
    ctx.model = &sim.model;
    ctx.mesh_pairs.clear();
    if (sel.given) {
      std::vector<std::string> names;
      for (const int m : sel.meshes) names.push_back(sim.model.meshes[static_cast<std::size_t>(m)].name);
      scene.effect_models.push_back(std::make_unique<Model>(restrict_to_meshes(sim.model, names)));
      ctx.model = scene.effect_models.back().get();
      for (const auto& [a, b] : sel.pairs)
        ctx.mesh_pairs.push_back(
            {sim.model.meshes[static_cast<std::size_t>(a)].name, sim.model.meshes[static_cast<std::size_t>(b)].name});
    }
    sim.effects.push_back(reg->make(q, ctx));
    if (reg->coverage == Coverage::none) continue;
    Covered c{k, sel.given, {}};
    std::vector<int> meshes = sel.meshes;
    if (!sel.given)
      for (int m = 0; m < M; ++m) meshes.push_back(m);
    if (reg->coverage == Coverage::meshes) {
      c.units.assign(meshes.begin(), meshes.end());
    } else if (reg->coverage == Coverage::mesh_pairs) {
      if (!sel.pairs.empty()) {
        for (const auto& [a, b] : sel.pairs) c.units.push_back(a * M + b);
      } else {
        for (std::size_t i = 0; i < meshes.size(); ++i)
          for (std::size_t j = i; j < meshes.size(); ++j) c.units.push_back(meshes[i] * M + meshes[j]);
      }
    } else {
      for (const int m : meshes)
        for (const long o : listed_obstacles(q, sim.obstacles)) c.units.push_back(m * O + o);
    }
    if (!coverage.count(reg)) order.push_back(reg);
    coverage[reg].push_back(std::move(c));
  }
  for (const RegisteredEffect* reg : order) check_coverage(*reg, coverage[reg], name, sim.model, sim.obstacles);
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
  build_effects(root, name, overrides, broad_phase, *scene);
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
