// SPDX-License-Identifier: MIT
// Tetrahedral mesh files (tet_io.hpp): Gmsh .msh (ASCII 2.x, 4.0, 4.1), TetGen .node/.ele
// and the plain .tet form. Each reader collects positions and tetrahedra line by line (every
// error names the file and the line), turns each tetrahedron positive as it is read, then
// `finish` adds the boundary faces and validates the mesh.
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

/// Largest element count a file may declare: a tetrahedral mesh has about six tetrahedra per
/// vertex, and a Gmsh file also lists its boundary triangles, lines and points. Counts above
/// are refused before anything is allocated.
constexpr long kMaxElements = 8 * kMaxVertices;

/// A text file read line by line, split into whitespace-separated tokens; blank lines (and,
/// with `comments`, everything from `#` on) are skipped. Errors name the file and the line.
class Lines {
 public:
  Lines(const fs::path& path, bool comments, const std::string& cannot_open = "cannot open the mesh file")
      : file_(path.string()), in_(path), comments_(comments) {
    if (!in_) throw InputError(file_, "", cannot_open);
  }

  /// The next non-blank line's tokens; false at the end of the file.
  bool next(std::vector<std::string>& tokens) {
    std::string text, token;
    while (std::getline(in_, text)) {
      ++line_;
      if (comments_) text = text.substr(0, text.find('#'));
      std::istringstream s(text);
      tokens.clear();
      while (s >> token) tokens.push_back(token);
      if (!tokens.empty()) return true;
    }
    if (in_.bad()) throw InputError(file_, "", "read error");
    return false;
  }

  /// `next`, or an error naming the line after the last one if the file ends before `expected`.
  void need(std::vector<std::string>& tokens, const std::string& expected) {
    if (!next(tokens)) {
      ++line_;
      fail("unexpected end of the file (expected " + expected + ")");
    }
  }

  /// An `InputError` naming the file and the current line.
  [[noreturn]] void fail(const std::string& what) const { fail_at(line_, what); }

  /// An `InputError` naming the file and line `line`.
  [[noreturn]] void fail_at(int line, const std::string& what) const {
    throw InputError(file_, "line " + std::to_string(line), what);
  }

  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  std::ifstream in_;
  bool comments_;
  int line_ = 0;
};

double parse_real(const std::string& token, const Lines& in) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE) in.fail("expected a number, found '" + token + "'");
  if (!std::isfinite(v)) in.fail("non-finite coordinate '" + token + "'");
  return v;
}

/// A decimal integer in [lo, hi]; `what` names it in the errors.
long parse_integer(const std::string& token, long lo, long hi, const std::string& what, const Lines& in) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(token.c_str(), &end, 10);
  if (end == token.c_str() || *end != '\0' || errno == ERANGE)
    in.fail("expected " + what + " (an integer), found '" + token + "'");
  if (v < lo || v > hi)
    in.fail(what + " " + token + " out of range (expected " + std::to_string(lo) + " to " + std::to_string(hi) + ")");
  return v;
}

/// Checks that `t` has `count` tokens; `what` says what the line holds.
void require_tokens(const std::vector<std::string>& t, std::size_t count, const std::string& what, const Lines& in) {
  if (t.size() != count)
    in.fail("expected " + what + " (" + std::to_string(count) + " values), found " + std::to_string(t.size()) +
            " values");
}

/// Positions and positive tetrahedra as a reader collects them.
struct Collected {
  std::vector<Eigen::Vector3d> x;
  std::vector<std::array<int, 4>> tets;

  /// Adds tetrahedron `v` (indices into `x`; `names` are the file's words for them),
  /// swapping c and d when its signed volume is negative. A repeated vertex or a flat
  /// tetrahedron (by `validate`'s measure) is an error at the current line.
  void add(std::array<int, 4> v, const std::array<std::string, 4>& names, const Lines& in) {
    const std::string which = "tetrahedron " + std::to_string(tets.size());
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < i; ++j)
        if (v[i] == v[j]) in.fail(which + " uses vertex " + names[i] + " twice");
    const Eigen::Vector3d e1 = x[v[1]] - x[v[0]], e2 = x[v[2]] - x[v[0]], e3 = x[v[3]] - x[v[0]];
    const double volume = e1.dot(e2.cross(e3)) / 6.0;
    const double longest = std::max({e1.norm(), e2.norm(), e3.norm(), (x[v[2]] - x[v[1]]).norm(),
                                     (x[v[3]] - x[v[1]]).norm(), (x[v[3]] - x[v[2]]).norm()});
    // Coordinates so large that these overflow are refused by `validate`, by vertex.
    if (std::isfinite(volume) && std::isfinite(longest) && !(std::abs(volume) > 1e-12 * longest * longest * longest)) {
      std::ostringstream s;
      s.precision(17);
      s << which << " (vertices " << names[0] << ", " << names[1] << ", " << names[2] << ", " << names[3]
        << ") is flat: volume " << volume << ", expected a volume above 1e-12 of its longest edge cubed";
      in.fail(s.str());
    }
    if (volume < 0) std::swap(v[2], v[3]);
    tets.push_back(v);
  }
};

/// The mesh of `c`: boundary faces as its triangles, no segments, validated as `source`.
Mesh finish(const Collected& c, const std::string& source) {
  if (c.tets.empty()) throw InputError(source, "", "no tetrahedra in the file");
  Mesh m;
  m.positions.resize(3, static_cast<Eigen::Index>(c.x.size()));
  for (std::size_t i = 0; i < c.x.size(); ++i) m.positions.col(static_cast<Eigen::Index>(i)) = c.x[i];
  m.tetrahedra.resize(4, static_cast<Eigen::Index>(c.tets.size()));
  for (std::size_t i = 0; i < c.tets.size(); ++i)
    m.tetrahedra.col(static_cast<Eigen::Index>(i)) << c.tets[i][0], c.tets[i][1], c.tets[i][2], c.tets[i][3];
  m.triangles = boundary_faces(m.tetrahedra);
  m.segments.resize(2, 0);
  validate(m, source);
  return m;
}

// --- Gmsh .msh ----------------------------------------------------------------------------

/// The layouts of `$Nodes` and `$Elements`: 2.x, 4.0 or 4.1.
enum class MshVersion { v2, v40, v41 };

/// Reads the rest of `$MeshFormat` (its first line, `version file-type data-size`, in `t`).
MshVersion read_mesh_format(Lines& in, std::vector<std::string>& t) {
  require_tokens(t, 3, "'version file-type data-size'", in);
  const std::string& v = t[0];
  MshVersion version;
  if (v == "2" || (v.size() > 2 && v.compare(0, 2, "2.") == 0 && std::isdigit(static_cast<unsigned char>(v[2]))))
    version = MshVersion::v2;
  else if (v == "4" || v == "4.0")
    version = MshVersion::v40;
  else if (v == "4.1")
    version = MshVersion::v41;
  else
    in.fail("unsupported .msh format version '" + v + "' (2.x, 4.0 and 4.1 are read)");
  if (t[1] == "1") in.fail("binary .msh is not supported, save as ASCII");
  if (t[1] != "0") in.fail("expected file-type 0 (ASCII), found '" + t[1] + "'");
  parse_integer(t[2], 1, 16, "data-size", in);
  in.need(t, "$EndMeshFormat");
  if (t.size() != 1 || t[0] != "$EndMeshFormat") in.fail("expected $EndMeshFormat, found '" + t[0] + "'");
  return version;
}

/// The next data line of `section` (which declared `count` items and has read `done`).
void need_data(Lines& in, std::vector<std::string>& t, const std::string& section, const std::string& expected,
               long count, long done) {
  in.need(t, expected + " in $" + section);
  if (t[0][0] == '$')
    in.fail("the $" + section + " section ends after " + std::to_string(done) + " of its " + std::to_string(count) +
            " entries (found '" + t[0] + "')");
}

/// Expects the `$End<section>` line.
void need_end(Lines& in, std::vector<std::string>& t, const std::string& section, long count) {
  in.need(t, "$End" + section);
  if (t.size() != 1 || t[0] != "$End" + section)
    in.fail("expected $End" + section + " after the " + std::to_string(count) +
            " entries the section declares, found '" + t[0] + "'");
}

struct MshNodes {
  Collected c;
  std::unordered_map<long, int> index_of_tag;  // node tag → index into c.x (file order)
};

/// One node: its tag and coordinates (`x`, `y`, `z` tokens).
void add_node(MshNodes& nodes, const std::string& tag, const std::string* xyz, Lines& in) {
  const long id = parse_integer(tag, 1, std::numeric_limits<long>::max(), "node tag", in);
  if (!nodes.index_of_tag.emplace(id, static_cast<int>(nodes.c.x.size())).second)
    in.fail("node tag " + tag + " appears twice");
  nodes.c.x.emplace_back(parse_real(xyz[0], in), parse_real(xyz[1], in), parse_real(xyz[2], in));
}

void read_msh_nodes(Lines& in, MshVersion version, MshNodes& nodes) {
  std::vector<std::string> t;
  in.need(t, "the node count");
  const int header = in.line();
  long count = 0, blocks = 1;
  if (version == MshVersion::v2) {
    require_tokens(t, 1, "the node count", in);
  } else {
    require_tokens(
        t, version == MshVersion::v41 ? 4 : 2,
        version == MshVersion::v41 ? "'numEntityBlocks numNodes minNodeTag maxNodeTag'" : "'numEntityBlocks numNodes'",
        in);
    blocks = parse_integer(t[0], 0, kMaxVertices, "numEntityBlocks", in);
  }
  count = parse_integer(t[version == MshVersion::v2 ? 0 : 1], 0, kMaxVertices, "the node count", in);
  nodes.c.x.reserve(static_cast<std::size_t>(count));
  nodes.index_of_tag.reserve(static_cast<std::size_t>(count));
  if (version == MshVersion::v2) {
    for (long i = 0; i < count; ++i) {
      need_data(in, t, "Nodes", "a node", count, i);
      require_tokens(t, 4, "'node-number x y z'", in);
      add_node(nodes, t[0], &t[1], in);
    }
  } else {
    long done = 0;
    std::vector<std::string> tags;
    for (long b = 0; b < blocks; ++b) {
      need_data(in, t, "Nodes", "an entity block", count, done);
      require_tokens(t, 4,
                     version == MshVersion::v41 ? "'entityDim entityTag parametric numNodesInBlock'"
                                                : "'entityTag entityDim parametric numNodes'",
                     in);
      const long dim = parse_integer(t[version == MshVersion::v41 ? 0 : 1], 0, 3, "entityDim", in);
      const long parametric = parse_integer(t[2], 0, 1, "parametric", in);
      const long n = parse_integer(t[3], 0, kMaxVertices, "numNodesInBlock", in);
      if (n > count - done)
        in.fail("the entity blocks hold more than the " + std::to_string(count) + " nodes the section declares");
      const std::size_t values = 3 + static_cast<std::size_t>(parametric * dim);
      if (version == MshVersion::v41) {
        tags.clear();
        for (long i = 0; i < n; ++i) {
          need_data(in, t, "Nodes", "a node tag", count, done);
          require_tokens(t, 1, "a node tag", in);
          tags.push_back(t[0]);
        }
        for (long i = 0; i < n; ++i, ++done) {
          need_data(in, t, "Nodes", "node coordinates", count, done);
          require_tokens(t, values, parametric ? "'x y z' and the parametric coordinates" : "'x y z'", in);
          add_node(nodes, tags[static_cast<std::size_t>(i)], &t[0], in);
        }
      } else {
        for (long i = 0; i < n; ++i, ++done) {
          need_data(in, t, "Nodes", "a node", count, done);
          require_tokens(t, values + 1, parametric ? "'tag x y z' and the parametric coordinates" : "'tag x y z'", in);
          add_node(nodes, t[0], &t[1], in);
        }
      }
    }
    if (done != count)
      in.fail_at(header, "the $Nodes section declares " + std::to_string(count) + " nodes, its blocks hold " +
                             std::to_string(done));
  }
  need_end(in, t, "Nodes", count);
}

/// A tetrahedron line's four node tags, from `t[first]` on.
void add_msh_tet(MshNodes& nodes, const std::vector<std::string>& t, std::size_t first, Lines& in) {
  std::array<int, 4> v{};
  std::array<std::string, 4> names;
  for (int k = 0; k < 4; ++k) {
    names[k] = t[first + k];
    const long tag = parse_integer(names[k], 1, std::numeric_limits<long>::max(), "node tag", in);
    const auto it = nodes.index_of_tag.find(tag);
    if (it == nodes.index_of_tag.end()) in.fail("unknown node tag " + names[k] + " (not in $Nodes)");
    v[k] = it->second;
  }
  nodes.c.add(v, names, in);
}

void read_msh_elements(Lines& in, MshVersion version, MshNodes& nodes) {
  std::vector<std::string> t;
  in.need(t, "the element count");
  const int header = in.line();
  long count = 0, blocks = 1;
  if (version == MshVersion::v2) {
    require_tokens(t, 1, "the element count", in);
  } else {
    require_tokens(t, version == MshVersion::v41 ? 4 : 2,
                   version == MshVersion::v41 ? "'numEntityBlocks numElements minElementTag maxElementTag'"
                                              : "'numEntityBlocks numElements'",
                   in);
    blocks = parse_integer(t[0], 0, kMaxElements, "numEntityBlocks", in);
  }
  count = parse_integer(t[version == MshVersion::v2 ? 0 : 1], 0, kMaxElements, "the element count", in);
  if (version == MshVersion::v2) {
    for (long i = 0; i < count; ++i) {
      need_data(in, t, "Elements", "an element", count, i);
      if (t.size() < 3) in.fail("expected 'elm-number elm-type number-of-tags tags… nodes…'");
      const long type = parse_integer(t[1], 1, std::numeric_limits<int>::max(), "the element type", in);
      if (type != 4) continue;
      const long tags = parse_integer(t[2], 0, 1000, "number-of-tags", in);
      require_tokens(t, 3 + static_cast<std::size_t>(tags) + 4, "a tetrahedron: number, type, tags and 4 nodes", in);
      add_msh_tet(nodes, t, 3 + static_cast<std::size_t>(tags), in);
    }
  } else {
    long done = 0;
    for (long b = 0; b < blocks; ++b) {
      need_data(in, t, "Elements", "an entity block", count, done);
      require_tokens(t, 4,
                     version == MshVersion::v41 ? "'entityDim entityTag elementType numElementsInBlock'"
                                                : "'entityTag entityDim elementType numElements'",
                     in);
      const long type = parse_integer(t[2], 1, std::numeric_limits<int>::max(), "the element type", in);
      const long n = parse_integer(t[3], 0, kMaxElements, "numElementsInBlock", in);
      if (n > count - done)
        in.fail("the entity blocks hold more than the " + std::to_string(count) + " elements the section declares");
      for (long i = 0; i < n; ++i, ++done) {
        need_data(in, t, "Elements", "an element", count, done);
        if (type != 4) continue;
        require_tokens(t, 5, "'elementTag' and 4 node tags", in);
        add_msh_tet(nodes, t, 1, in);
      }
    }
    if (done != count)
      in.fail_at(header, "the $Elements section declares " + std::to_string(count) + " elements, its blocks hold " +
                             std::to_string(done));
  }
  need_end(in, t, "Elements", count);
}

/// Skips a section this reader does not use, up to its `$End` line.
void skip_section(Lines& in, const std::string& name) {
  std::vector<std::string> t;
  do in.need(t, "$End" + name + " (the section starts on an earlier line)");
  while (t[0] != "$End" + name);
}

Mesh read_msh(const fs::path& path) {
  Lines in(path, false);
  std::vector<std::string> t;
  bool have_format = false, have_nodes = false, have_elements = false;
  MshVersion version = MshVersion::v41;
  MshNodes nodes;
  while (in.next(t)) {
    if (t[0].size() < 2 || t[0][0] != '$') in.fail("expected a section such as $Nodes, found '" + t[0] + "'");
    const std::string name = t[0].substr(1);
    if (!have_format && name != "MeshFormat") in.fail("expected $MeshFormat first, found '" + t[0] + "'");
    if (name == "MeshFormat") {
      if (have_format) in.fail("a second $MeshFormat section");
      have_format = true;
      in.need(t, "'version file-type data-size'");
      version = read_mesh_format(in, t);
    } else if (name == "Nodes") {
      if (have_nodes) in.fail("a second $Nodes section");
      have_nodes = true;
      read_msh_nodes(in, version, nodes);
    } else if (name == "Elements") {
      if (!have_nodes) in.fail("$Elements before $Nodes");
      if (have_elements) in.fail("a second $Elements section");
      have_elements = true;
      read_msh_elements(in, version, nodes);
    } else if (name.compare(0, 3, "End") == 0) {
      in.fail("'" + t[0] + "' without its section");
    } else {
      skip_section(in, name);  // $PhysicalNames, $Entities, $Periodic, $NodeData, …
    }
  }
  const std::string& file = in.file();
  if (!have_format) throw InputError(file, "", "no $MeshFormat section (not a Gmsh .msh file)");
  if (!have_nodes) throw InputError(file, "", "no $Nodes section");
  if (!have_elements) throw InputError(file, "", "no $Elements section");
  if (nodes.c.tets.empty()) throw InputError(file, "", "no tetrahedra (element type 4) in the file");
  // Drop the nodes no tetrahedron uses (points, curve ends…), keeping the others' order.
  std::vector<int> renumber(nodes.c.x.size(), -1);
  for (const auto& tet : nodes.c.tets)
    for (int v : tet) renumber[static_cast<std::size_t>(v)] = 0;
  Collected used;
  for (std::size_t i = 0; i < renumber.size(); ++i)
    if (renumber[i] == 0) {
      renumber[i] = static_cast<int>(used.x.size());
      used.x.push_back(nodes.c.x[i]);
    }
  used.tets = std::move(nodes.c.tets);
  for (auto& tet : used.tets)
    for (int& v : tet) v = renumber[static_cast<std::size_t>(v)];
  return finish(used, file);
}

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
