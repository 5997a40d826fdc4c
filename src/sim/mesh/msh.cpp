// SPDX-License-Identifier: MIT
// The Gmsh .msh reader (ASCII 2.x, 4.0, 4.1) of tet_io.hpp: nodes and tetrahedra line by
// line, every error naming the file and the line.
#include "tet_text.hpp"

#include <limits>
#include <unordered_map>
#include <utility>

namespace pce::sim::tet_text {

namespace {

namespace fs = std::filesystem;

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

}  // namespace

Mesh read_msh(const std::filesystem::path& path) {
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

}  // namespace pce::sim::tet_text
