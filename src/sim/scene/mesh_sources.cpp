// SPDX-License-Identifier: MIT
// The scene's meshes (mesh_sources.hpp): read from a file, made by a generator, or written
// in the scene, then transformed and checked. The generators and `validate` check their own
// limits; their errors are named by the scene field that gave the mesh.
#include "mesh_sources.hpp"

#include "../effects/arguments.hpp"
#include "motion.hpp"
#include "scene_names.hpp"

#include <pce/sim/generators.hpp>
#include <pce/sim/obj.hpp>
#include <pce/sim/tet_io.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace pce::sim {

namespace {

/// A `generator` object: `tet_box`, `tet_ball`, `grid` or `strands`, with its sizes and
/// counts. A generator's own error is named by the generator's `type`.
Mesh parse_generator(const Params& g) {
  const GeneratorKind type = g.choice<GeneratorKind>("type");
  try {
    // Every case but strands returns; strands is read after the switch.
    switch (type) {
      case GeneratorKind::tet_box: {
        g.only({"type", "size", "n"});
        const Eigen::Vector3d size = g.checked_vec3("size", args::position);
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
        const double radius = g.checked("radius", args::length);
        const int n = static_cast<int>(g.integer("n", std::nullopt, 1, 127));
        return tet_ball(radius, n);
      }
      case GeneratorKind::grid: {
        g.only({"type", "width", "height", "nx", "ny"});
        const double width = g.checked("width", args::length), height = g.checked("height", args::length);
        const int nx = static_cast<int>(g.integer("nx", std::nullopt, 1, 4096));
        const int ny = static_cast<int>(g.integer("ny", std::nullopt, 1, 4096));
        return grid(width, height, nx, ny);
      }
      case GeneratorKind::strands:
        break;
    }
    g.only({"type", "count", "segments", "length", "spacing", "curl"});
    const int strand_count = static_cast<int>(g.integer("count", std::nullopt, 1, 1L << 20));
    const int segments = static_cast<int>(g.integer("segments", std::nullopt, 1, 1L << 16));
    const double length = g.checked("length", args::length), spacing = g.checked("spacing", args::length);
    const double curl = g.checked(
        "curl",
        [](const std::string& f, double v) {
          return args::nonnegative_at_most(f, v, kMaxCoordinate, "the largest length pce::sim accepts, in m");
        },
        0.0);
    // qualified: a unity build (tests/fuzz) also sees registry.cpp's strands(MeshRange, MeshRange)
    return sim::strands(strand_count, segments, length, spacing, curl);
  } catch (const InputError& e) {
    if (e.file() == g.file()) throw;  // already names the scene field
    g.fail("type", e.what());
  }
}

/// The rows of the array `key` (absent: none), each an array of N vertex indices in
/// [0, `vertex_count`) with no vertex twice, as the columns of a matrix; `what` names a row
/// ("triangle"). Errors name the row or the index (`triangles[4][2]`).
template <int N> Eigen::Matrix<int, N, Eigen::Dynamic> index_rows(const Params& p, const std::string& key,
                                                                  Eigen::Index vertex_count, const char* what) {
  const nlohmann::json& rows = p.array(key);
  const std::string range = "[0, " + std::to_string(vertex_count) + ")";
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
      if (i < 0 || i >= vertex_count) p.fail(at, "expected a vertex index in " + range + ", got " + v.dump());
      out(k, static_cast<Eigen::Index>(r)) = static_cast<int>(i);
      for (int m = 0; m < k; ++m)
        if (out(m, static_cast<Eigen::Index>(r)) == i)
          p.fail(key + row, "the " + std::string(what) + " uses vertex " + std::to_string(i) + " twice");
    }
  }
  return out;
}

/// The `vertices` of a mesh written in the scene: at least one, at most `kMaxVertices`, each
/// three numbers within ±kMaxCoordinate; errors name the coordinate (`vertices[3][1]`).
Eigen::Matrix3Xd inline_vertices(const Params& p) {
  const nlohmann::json& rows = p.array("vertices", true);
  if (rows.empty()) p.fail("vertices", "expected at least one vertex");
  if (static_cast<long>(rows.size()) > kMaxVertices)
    p.fail("vertices",
           "expected at most " + std::to_string(kMaxVertices) + " vertices, got " + std::to_string(rows.size()));
  Eigen::Matrix3Xd positions(3, static_cast<Eigen::Index>(rows.size()));
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
      positions(k, static_cast<Eigen::Index>(r)) = v;
    }
  }
  return positions;
}

/// A mesh written in the scene (`vertices` and `triangles`, `segments` or `tetrahedra`):
/// every index in range and no element repeating a vertex, errors naming the element
/// (`triangles[4][2]`). A volume's triangles are its boundary faces; `validate`'s checks of
/// the tetrahedra (orientation, size, shared faces) name `tetrahedra`.
Mesh parse_inline_mesh(const Params& p) {
  Mesh m;
  m.positions = inline_vertices(p);
  const Eigen::Index vertex_count = m.vertex_count();
  m.triangles = index_rows<3>(p, "triangles", vertex_count, "triangle");
  m.segments = index_rows<2>(p, "segments", vertex_count, "segment");
  m.tetrahedra = index_rows<4>(p, "tetrahedra", vertex_count, "tetrahedron");
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

}  // namespace

Mesh read_mesh_file(const Params& p, const std::string& key, const std::filesystem::path& base) {
  const std::filesystem::path path = base / p.string(key);
  if (!std::filesystem::exists(path)) p.fail(key, "mesh file not found: " + path.string());
  try {
    return is_tet_mesh_file(path) ? read_tet_mesh(path) : read_obj(path);
  } catch (const InputError& e) {
    p.fail(key, std::string("malformed mesh: ") + e.what());
  }
}

ModelMesh parse_mesh(const Params& p, const std::filesystem::path& base) {
  p.only({"name", "file", "generator", "vertices", "triangles", "segments", "tetrahedra", "transform", "density",
          "linear_density"});
  ModelMesh s;
  s.name = p.string("name");
  const int source_count = int{p.has("file")} + int{p.has("generator")} + int{p.has("vertices")};
  const char* const source = p.has("file") ? "file" : p.has("generator") ? "generator" : "vertices";
  if (source_count != 1)
    p.fail(source_count == 0   ? "file"
           : p.has("vertices") ? "vertices"
                               : "generator",
           "expected exactly one of \"file\", \"generator\" or \"vertices\"");
  if (!p.has("vertices"))
    for (const char* key : {"triangles", "segments", "tetrahedra"})
      if (p.has(key)) p.fail(key, "the elements of a mesh given by its \"vertices\": give them too");
  if (p.has("file"))
    s.mesh = read_mesh_file(p, "file", base);
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

}  // namespace pce::sim
