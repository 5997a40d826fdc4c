// SPDX-License-Identifier: MIT
// Tetrahedral mesh files (tet_io.hpp): Gmsh .msh (ASCII 2.x, 4.0, 4.1), TetGen .node/.ele
// and the plain .tet form. Each reader collects positions and tetrahedra line by line (every
// error names the file and the line), turns each tetrahedron positive as it is read, then
// `finish` adds the boundary faces and validates the mesh.
#include "tet_text.hpp"

#include <pce/sim/input_error.hpp>
#include <pce/sim/tet_io.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace pce::sim {

namespace {

namespace fs = std::filesystem;
using namespace tet_text;

// --- TetGen .node / .ele ------------------------------------------------------------------

Mesh read_tetgen(const fs::path& path, bool given_ele) {
  const fs::path node_path = fs::path(path).replace_extension(".node");
  const fs::path ele_path = fs::path(path).replace_extension(".ele");
  Collected c;
  std::vector<std::string> t;
  long base = 0;
  {
    Lines in(
        node_path, true,
        given_ele ? "cannot open the .node file that " + ele_path.string() + " needs" : "cannot open the mesh file");
    in.need(t, "the header '<points> <dimension> <attributes> <boundary markers>'");
    if (t.size() > 4) in.fail("expected the header '<points> <dimension> <attributes> <boundary markers>'");
    const long count = parse_integer(t[0], 1, kMaxVertices, "the point count", in);
    if (t.size() > 1 && t[1] != "3") in.fail("expected dimension 3, found '" + t[1] + "'");
    const long attributes = t.size() > 2 ? parse_integer(t[2], 0, 1000, "the attribute count", in) : 0;
    const long markers = t.size() > 3 ? parse_integer(t[3], 0, 1, "the boundary marker flag", in) : 0;
    c.x.reserve(static_cast<std::size_t>(count));
    for (long i = 0; i < count; ++i) {
      in.need(t, "point " + std::to_string(i + 1) + " of " + std::to_string(count));
      require_tokens(t, 4 + static_cast<std::size_t>(attributes + markers), "'index x y z [attributes] [marker]'", in);
      if (i == 0) base = parse_integer(t[0], 0, 1, "the first point's index", in);
      if (parse_integer(t[0], 0, kMaxVertices, "the point index", in) != base + i)
        in.fail("expected point index " + std::to_string(base + i) + ", found " + t[0] +
                " (points are numbered consecutively)");
      c.x.emplace_back(parse_real(t[1], in), parse_real(t[2], in), parse_real(t[3], in));
    }
    if (in.next(t)) in.fail("more points than the " + std::to_string(count) + " the header declares");
  }
  Lines in(ele_path, true,
           given_ele ? "cannot open the mesh file" : "cannot open the .ele file that " + node_path.string() + " needs");
  in.need(t, "the header '<tetrahedra> <nodes per tetrahedron> <attributes>'");
  if (t.size() > 3) in.fail("expected the header '<tetrahedra> <nodes per tetrahedron> <attributes>'");
  const long count = parse_integer(t[0], 1, kMaxElements, "the tetrahedron count", in);
  const long corners = t.size() > 1 ? parse_integer(t[1], 4, 10, "the nodes per tetrahedron", in) : 4;
  if (corners != 4 && corners != 10) in.fail("expected 4 or 10 nodes per tetrahedron, found " + t[1]);
  const long attributes = t.size() > 2 ? parse_integer(t[2], 0, 1000, "the attribute count", in) : 0;
  const long last = base + static_cast<long>(c.x.size()) - 1;
  c.tets.reserve(static_cast<std::size_t>(std::min(count, 8 * static_cast<long>(c.x.size()))));
  for (long i = 0; i < count; ++i) {
    in.need(t, "tetrahedron " + std::to_string(i + 1) + " of " + std::to_string(count));
    require_tokens(t, 1 + static_cast<std::size_t>(corners + attributes), "'index a b c d [more nodes] [attributes]'",
                   in);
    parse_integer(t[0], std::numeric_limits<long>::min(), std::numeric_limits<long>::max(), "the tetrahedron index",
                  in);
    std::array<int, 4> v{};
    std::array<std::string, 4> names;
    for (int k = 0; k < 4; ++k) {  // a 10-node tetrahedron lists its corners first
      names[k] = t[1 + k];
      v[k] = static_cast<int>(parse_integer(names[k], base, last, "vertex index", in) - base);
    }
    c.add(v, names, in);
  }
  if (in.next(t)) in.fail("more tetrahedra than the " + std::to_string(count) + " the header declares");
  return finish(c, ele_path.string());
}

// --- .tet ---------------------------------------------------------------------------------

Mesh read_plain(const fs::path& path) {
  Lines in(path, true);
  Collected c;
  std::vector<std::string> t;
  while (in.next(t)) {
    if (t[0] == "v") {
      require_tokens(t, 4, "'v x y z'", in);
      if (static_cast<long>(c.x.size()) >= kMaxVertices)
        in.fail("more than " + std::to_string(kMaxVertices) + " vertices");
      c.x.emplace_back(parse_real(t[1], in), parse_real(t[2], in), parse_real(t[3], in));
    } else if (t[0] == "t") {
      require_tokens(t, 5, "'t a b c d'", in);
      std::array<int, 4> v{};
      std::array<std::string, 4> names;
      for (int k = 0; k < 4; ++k) {
        names[k] = t[1 + k];
        const long i = parse_integer(names[k], std::numeric_limits<long>::min(), std::numeric_limits<long>::max(),
                                     "vertex index", in);
        if (i < 1 || i > static_cast<long>(c.x.size()))
          in.fail("vertex index " + names[k] + " out of range (" + std::to_string(c.x.size()) +
                  " vertices so far, numbered from 1)");
        v[k] = static_cast<int>(i - 1);
      }
      c.add(v, names, in);
    } else {
      in.fail("expected 'v x y z' or 't a b c d', found '" + t[0] + "'");
    }
  }
  return finish(c, in.file());
}

std::string lower_extension(const fs::path& path) {
  std::string e = path.extension().string();
  for (char& ch : e) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return e;
}

}  // namespace

bool is_tet_mesh_file(const std::filesystem::path& path) {
  const std::string e = lower_extension(path);
  return e == ".msh" || e == ".ele" || e == ".node" || e == ".tet";
}

Mesh read_tet_mesh(const std::filesystem::path& path) {
  const std::string e = lower_extension(path);
  if (e == ".msh") return read_msh(path);
  if (e == ".ele" || e == ".node") return read_tetgen(path, e == ".ele");
  if (e == ".tet") return read_plain(path);
  throw InputError(path.string(), "", "not a tetrahedral mesh file (expected .msh, .ele, .node or .tet)");
}

void write_tet(const std::filesystem::path& path, const Mesh& mesh) {
  const std::string file = path.string();
  std::FILE* out = std::fopen(file.c_str(), "w");
  if (!out) throw InputError(file, "", "cannot open the file for writing");
  bool ok = std::fprintf(out, "# %ld vertices (v x y z), %ld tetrahedra (t a b c d, from 1)\n",
                         static_cast<long>(mesh.positions.cols()), static_cast<long>(mesh.tetrahedra.cols())) > 0;
  for (Eigen::Index i = 0; i < mesh.positions.cols(); ++i)
    ok = ok && std::fprintf(out, "v %.17g %.17g %.17g\n", mesh.positions(0, i), mesh.positions(1, i),
                            mesh.positions(2, i)) > 0;
  for (Eigen::Index i = 0; i < mesh.tetrahedra.cols(); ++i)
    ok = ok && std::fprintf(out, "t %d %d %d %d\n", mesh.tetrahedra(0, i) + 1, mesh.tetrahedra(1, i) + 1,
                            mesh.tetrahedra(2, i) + 1, mesh.tetrahedra(3, i) + 1) > 0;
  ok = (std::fclose(out) == 0) && ok;
  if (!ok) throw InputError(file, "", "write error");
}

}  // namespace pce::sim
