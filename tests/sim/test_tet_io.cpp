// SPDX-License-Identifier: MIT
// pce::sim tetrahedral meshes (src/sim/mesh/tet_io.cpp, generators.cpp, mesh.cpp): one cube
// of five tetrahedra written in every format tet_io reads (Gmsh 4.1, 4.0 and 2.2 with sparse
// tags, entity blocks and other element types, TetGen from 0 and from 1, .tet) must read
// back as the same mesh with its inverted tetrahedra turned positive; a write/read round trip
// is exact; each kind of bad input is one InputError naming the file and the line; tet_box
// and tet_ball are closed, outward, positive and of the right volume; validate refuses a face
// shared by three tetrahedra.
#include <pce/sim/generators.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/tet_io.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>

namespace {
namespace fs = std::filesystem;
using pce::sim::InputError;
using pce::sim::Mesh;

fs::path tmp_dir() {
#ifdef PCE_TEST_TMP
  const fs::path dir = fs::path(PCE_TEST_TMP) / "tet_io";
#else
  const fs::path dir = fs::temp_directory_path() / "pce_test_tet_io";
#endif
  fs::create_directories(dir);
  return dir;
}

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path p = tmp_dir() / name;
  std::ofstream(p) << text;
  return p;
}

/// The InputError reading `path` throws: {file, where, what}; all empty if none.
struct Error {
  std::string file, where, what;
};
Error read_error(const fs::path& path) {
  try {
    pce::sim::read_tet_mesh(path);
  } catch (const InputError& e) {
    return {e.file(), e.where(), e.what()};
  }
  return {};
}
Error read_error(const std::string& name, const std::string& text) { return read_error(write_file(name, text)); }

// --- The fixture: the box [0.1, 1.3] × [−0.25, 2] × [0.75, 3.5] as five tetrahedra ---------

/// Corner v = x + 2y + 4z (x, y, z ∈ {0, 1}) as the files write it.
std::string xyz(int v) {
  return std::string(v & 1 ? "1.3" : "0.1") + (v & 2 ? " 2" : " -0.25") + (v & 4 ? " 3.5" : " 0.75");
}
Eigen::Vector3d corner(int v) { return {v & 1 ? 1.3 : 0.1, v & 2 ? 2.0 : -0.25, v & 4 ? 3.5 : 0.75}; }

/// Four corner tetrahedra and the middle one, as the files list them: 1 and 3 inverted.
constexpr int kFileTets[5][4] = {{0, 1, 2, 4}, {3, 1, 2, 7}, {5, 1, 4, 7}, {6, 2, 4, 7}, {1, 2, 4, 7}};
/// What a read gives: 1 and 3 with their last two vertices swapped.
constexpr int kPositiveTets[5][4] = {{0, 1, 2, 4}, {3, 1, 7, 2}, {5, 1, 4, 7}, {6, 2, 7, 4}, {1, 2, 4, 7}};
/// Gmsh node tags of the corners: sparse and unordered.
constexpr int kTag[8] = {101, 7, 55, 3, 1000, 12, 42, 8};

std::string tet_file() {
  std::string s = "# the fixture box\n\n";
  for (int v = 0; v < 8; ++v) s += "v " + xyz(v) + (v == 3 ? "   # a comment\n" : "\n");
  for (const auto& t : kFileTets)
    s += "t " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + " " +
         std::to_string(t[3] + 1) + "\r\n";
  return s;
}

std::string msh_tet_line(int tag, int t, bool v2) {
  std::string s = std::to_string(tag) + (v2 ? " 4 2 7 1" : "");
  for (int k = 0; k < 4; ++k) s += " " + std::to_string(kTag[kFileTets[t][k]]);
  return s + "\n";
}

/// Gmsh 4.1 or 4.0: nodes in two entity blocks (a parametric curve holding an unused node and
/// corner 0, the volume holding the other corners around another unused node), points, lines
/// and triangles among the elements, the tetrahedra in two blocks.
std::string msh4_file(bool v41) {
  const auto block = [&](int dim, int entity, int type_or_parametric, int n) {
    return v41 ? std::to_string(dim) + " " + std::to_string(entity) + " " + std::to_string(type_or_parametric) + " " +
                     std::to_string(n) + "\n"
               : std::to_string(entity) + " " + std::to_string(dim) + " " + std::to_string(type_or_parametric) + " " +
                     std::to_string(n) + "\n";
  };
  std::string s = std::string("$MeshFormat\n") + (v41 ? "4.1" : "4") + " 0 8\n$EndMeshFormat\n";
  s += "$PhysicalNames\n1\n3 1 \"body\"\n$EndPhysicalNames\n";
  s += "$Entities\n1 1 0 2\n1 9 9 9 0\n1 0 0 0 1 1 1 0 0\n2 0 0 0 1 1 1 0 0\n$EndEntities\n";
  s += v41 ? "$Nodes\n2 10 3 1000\n" : "$Nodes\n2 10\n";
  s += block(1, 1, 1, 2);  // parametric: x y z u
  if (v41) {
    s += "999\n101\n9 9 9 0.5\n" + xyz(0) + " 0.25\n";
  } else {
    s += "999 9 9 9 0.5\n101 " + xyz(0) + " 0.25\n";
  }
  s += block(3, 1, 0, 8);
  const int tags[8] = {7, 55, 3, 500, 1000, 12, 42, 8};
  const int corners[8] = {1, 2, 3, -1, 4, 5, 6, 7};
  for (int i = 0; i < 8 && v41; ++i) s += std::to_string(tags[i]) + "\n";
  for (int i = 0; i < 8; ++i)
    s += (v41 ? "" : std::to_string(tags[i]) + " ") + (corners[i] < 0 ? "5 5 5" : xyz(corners[i])) + "\n";
  s += "$EndNodes\n";
  s += v41 ? "$Elements\n5 10 1 24\n" : "$Elements\n5 10\n";
  s += block(0, 1, 15, 1) + "1 999\n";
  s += block(1, 1, 1, 2) + "2 101 7\n3 7 55\n";
  s += block(2, 1, 2, 2) + "4 101 7 55\n5 7 3 55\n";
  s += block(3, 1, 4, 3) + msh_tet_line(20, 0, false) + msh_tet_line(21, 1, false) + msh_tet_line(22, 2, false);
  s += block(3, 2, 4, 2) + msh_tet_line(23, 3, false) + msh_tet_line(24, 4, false);
  s += "$EndElements\n$NodeData\n1\n\"t\"\n1\n0.0\n3\n0\n1\n1\n101 1.5\n$EndNodeData\n";
  return s;
}

/// Gmsh 2.2: the same nodes (node 999 first, node 500 among the corners) and elements.
std::string msh2_file() {
  std::string s = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 7 \"body\"\n$EndPhysicalNames\n";
  s += "$Nodes\n10\n999 9 9 9\n";
  for (int v = 0; v < 8; ++v) s += std::to_string(kTag[v]) + " " + xyz(v) + "\n" + (v == 3 ? "500 5 5 5\n" : "");
  s += "$EndNodes\n$Elements\n10\n1 15 2 0 1 999\n2 1 2 0 1 101 7\n3 1 2 0 1 7 55\n4 2 2 0 1 101 7 55\n";
  s += "5 2 3 0 1 3 7 55 3\n";  // three tags
  for (int t = 0; t < 5; ++t) s += msh_tet_line(20 + t, t, true);
  return s + "$EndElements\n";
}

/// TetGen's pair numbered from `base`, with attributes and boundary markers.
void write_tetgen(const std::string& stem, int base) {
  std::string node = "# TetGen\n8 3 1 1\n";
  for (int v = 0; v < 8; ++v) node += std::to_string(v + base) + "  " + xyz(v) + "  0.5 " + (v % 2 ? "1" : "0") + "\n";
  std::string ele = "5 4 1\n";
  for (int t = 0; t < 5; ++t) {
    ele += std::to_string(t + base);
    for (int k = 0; k < 4; ++k) ele += " " + std::to_string(kFileTets[t][k] + base);
    ele += " 1  # region\n";
  }
  write_file(stem + ".node", node);
  write_file(stem + ".ele", ele);
}

double signed_volume(const Mesh& m, Eigen::Index t) {
  const auto x = [&](int k) { return Eigen::Vector3d(m.positions.col(m.tetrahedra(k, t))); };
  return (x(1) - x(0)).dot((x(2) - x(0)).cross(x(3) - x(0))) / 6.0;
}

/// Volume over the longest edge cubed (a regular tetrahedron: 1 / (6√2) ≈ 0.118).
double quality(const Mesh& m, Eigen::Index t) {
  double longest = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < i; ++j)
      longest = std::max(longest, (m.positions.col(m.tetrahedra(i, t)) - m.positions.col(m.tetrahedra(j, t))).norm());
  return signed_volume(m, t) / (longest * longest * longest);
}

double total_volume(const Mesh& m) {
  double v = 0;
  for (Eigen::Index t = 0; t < m.tetrahedra.cols(); ++t) v += signed_volume(m, t);
  return v;
}

void expect_fixture(const Mesh& m, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(m.vertex_count(), 8);
  for (int v = 0; v < 8; ++v) EXPECT_EQ(m.positions.col(v), corner(v)) << "vertex " << v;
  ASSERT_EQ(m.tetrahedra.cols(), 5);
  for (int t = 0; t < 5; ++t) {
    EXPECT_EQ(m.tetrahedra.col(t),
              Eigen::Vector4i(kPositiveTets[t][0], kPositiveTets[t][1], kPositiveTets[t][2], kPositiveTets[t][3]))
        << "tetrahedron " << t;
    EXPECT_GT(signed_volume(m, t), 0) << "tetrahedron " << t;
  }
  EXPECT_EQ(m.triangles.cols(), 12);  // two per side of the box
  EXPECT_EQ(m.triangles, pce::sim::boundary_faces(m.tetrahedra));
  EXPECT_EQ(m.segments.cols(), 0);
  EXPECT_NEAR(total_volume(m), 1.2 * 2.25 * 2.75, 1e-14);
}

TEST(ReadTetMesh, EveryFormatGivesTheSameMeshWithPositiveTetrahedra) {
  expect_fixture(pce::sim::read_tet_mesh(write_file("box.tet", tet_file())), ".tet");
  expect_fixture(pce::sim::read_tet_mesh(write_file("box41.msh", msh4_file(true))), "msh 4.1");
  expect_fixture(pce::sim::read_tet_mesh(write_file("box40.msh", msh4_file(false))), "msh 4.0");
  expect_fixture(pce::sim::read_tet_mesh(write_file("box22.msh", msh2_file())), "msh 2.2");
  write_tetgen("box1", 1);
  expect_fixture(pce::sim::read_tet_mesh(tmp_dir() / "box1.ele"), "TetGen from 1, by its .ele");
  write_tetgen("box0", 0);
  expect_fixture(pce::sim::read_tet_mesh(tmp_dir() / "box0.node"), "TetGen from 0, by its .node");
  expect_fixture(pce::sim::read_tet_mesh(write_file("BOX.TET", tet_file())), "upper-case extension");
}

TEST(ReadTetMesh, TenNodeTetGenTetrahedraKeepTheirCorners) {
  write_tetgen("quadratic", 1);
  std::string ele = "5 10 0\n";
  for (int t = 0; t < 5; ++t) {
    ele += std::to_string(t + 1);
    for (int k = 0; k < 4; ++k) ele += " " + std::to_string(kFileTets[t][k] + 1);
    ele += " 1 2 3 4 5 6\n";  // edge nodes: not read
  }
  write_file("quadratic.ele", ele);
  expect_fixture(pce::sim::read_tet_mesh(tmp_dir() / "quadratic.ele"), "10-node .ele");
}

TEST(IsTetMeshFile, Extensions) {
  EXPECT_TRUE(pce::sim::is_tet_mesh_file("a/b.msh"));
  EXPECT_TRUE(pce::sim::is_tet_mesh_file("b.ele"));
  EXPECT_TRUE(pce::sim::is_tet_mesh_file("b.node"));
  EXPECT_TRUE(pce::sim::is_tet_mesh_file("b.Tet"));
  EXPECT_FALSE(pce::sim::is_tet_mesh_file("b.obj"));
  EXPECT_FALSE(pce::sim::is_tet_mesh_file("msh"));
}

TEST(WriteTet, RoundTripIsExact) {
  Mesh m = pce::sim::tet_ball(0.7, 3);
  m.positions.col(5) *= 1.0 + 1e-3 / 3.0;  // not a short decimal; the tetrahedra stay positive
  m.positions(2, 7) += 1e-17;
  const fs::path p = tmp_dir() / "ball.tet";
  pce::sim::write_tet(p, m);
  const Mesh r = pce::sim::read_tet_mesh(p);
  EXPECT_EQ(r.positions, m.positions);
  EXPECT_EQ(r.tetrahedra, m.tetrahedra);
  EXPECT_EQ(r.triangles, m.triangles);
  EXPECT_EQ(r.segments.cols(), 0);
  EXPECT_THROW(pce::sim::write_tet(tmp_dir() / "no_such_dir" / "x.tet", m), InputError);
}

// --- Bad input: one InputError each, naming the file and (where there is one) the line ------

void expect_error(const Error& e, const std::string& name, const std::string& where, const std::string& what) {
  EXPECT_EQ(fs::path(e.file).filename().string(), name) << e.what;
  EXPECT_EQ(e.where, where) << e.what;
  EXPECT_NE(e.what.find(what), std::string::npos) << e.what;
  if (!where.empty()) {
    EXPECT_NE(e.what.find(name + ": " + where + ": "), std::string::npos) << e.what;
  }
}

TEST(ReadTetMesh, TruncatedFiles) {
  const std::string msh = msh4_file(true);
  // Cut after the 9th line of $Nodes' data (line 17): the file ends inside the section.
  std::size_t cut = 0;
  for (int i = 0; i < 17; ++i) cut = msh.find('\n', cut) + 1;
  expect_error(read_error("cut.msh", msh.substr(0, cut)), "cut.msh", "line 18", "unexpected end of the file");
  expect_error(read_error("cut2.msh", msh2_file().substr(0, msh2_file().find("$EndElements"))), "cut2.msh", "line 33",
               "unexpected end of the file (expected $EndElements)");
  expect_error(read_error("cut.node", "3 3 0 0\n1 0 0 0\n2 1 0 0\n"), "cut.node", "line 4",
               "unexpected end of the file (expected point 3 of 3)");
  expect_error(read_error("skipped.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 0\n"), "skipped.msh",
               "line 6", "expected $EndEntities");
}

TEST(ReadTetMesh, CountsThatDoNotMatch) {
  std::string fewer = msh2_file();
  fewer.replace(fewer.find("$Nodes\n10"), 9, "$Nodes\n11");
  expect_error(read_error("fewer.msh", fewer), "fewer.msh", "line 20",
               "the $Nodes section ends after 10 of its 11 entries (found '$EndNodes')");
  std::string more = msh2_file();
  more.replace(more.find("$Elements\n10"), 12, "$Elements\n9");
  expect_error(read_error("more.msh", more), "more.msh", "line 32", "expected $EndElements after the 9 entries");
  std::string blocks = msh4_file(true);
  blocks.replace(blocks.find("2 10 3 1000"), 11, "2 11 3 1000");
  expect_error(read_error("blocks.msh", blocks), "blocks.msh", "line 15", "declares 11 nodes, its blocks hold 10");
  expect_error(read_error("extra.node", "1 3 0 0\n1 0 0 0\n2 1 0 0\n"), "extra.node", "line 3",
               "more points than the 1 the header declares");
  expect_error(read_error("absurd.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 99999999999 1 2\n"),
               "absurd.msh", "line 5", "the node count 99999999999 out of range");
  expect_error(read_error("absurd.node", "16777217 3 0 0\n"), "absurd.node", "line 1", "out of range");
}

TEST(ReadTetMesh, BadNumbers) {
  std::string tet = tet_file();
  tet.replace(tet.find("v 1.3 2 0.75"), 12, "v 1.3 2 0.7x");
  expect_error(read_error("number.tet", tet), "number.tet", "line 6", "expected a number, found '0.7x'");
  std::string msh = msh2_file();
  msh.replace(msh.find("7 1.3"), 5, "7 1,3");
  expect_error(read_error("number.msh", msh), "number.msh", "line 12", "expected a number, found '1,3'");
  expect_error(read_error("nan.tet", "v 0 0 0\nv nan 0 0\n"), "nan.tet", "line 2", "non-finite coordinate 'nan'");
  expect_error(read_error("inf.tet", "v 0 0 0\nv 1e999 0 0\n"), "inf.tet", "line 2", "expected a number");
  expect_error(read_error("short.tet", "v 0 0\n"), "short.tet", "line 1", "expected 'v x y z' (4 values)");
  expect_error(read_error("keyword.tet", "v 0 0 0\nf 1 2 3\n"), "keyword.tet", "line 2",
               "expected 'v x y z' or 't a b c d', found 'f'");
  expect_error(read_error("tag.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\nx1 0 0 0\n"), "tag.msh",
               "line 6", "expected node tag (an integer), found 'x1'");
}

TEST(ReadTetMesh, UnknownNodeTagsAndIndicesOutOfRange) {
  std::string msh = msh4_file(true);
  msh.replace(msh.find("24 " + std::to_string(kTag[1])), 4, "24 77");
  expect_error(read_error("tag.msh", msh), "tag.msh", "line 55", "unknown node tag 77 (not in $Nodes)");
  std::string tet = tet_file();
  tet.replace(tet.find("t 7 3 5 8"), 9, "t 7 3 5 9");
  expect_error(read_error("range.tet", tet), "range.tet", "line 14",
               "vertex index 9 out of range (8 vertices so far, numbered from 1)");
  expect_error(read_error("zero.tet", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nt 0 1 2 3\n"), "zero.tet", "line 5",
               "vertex index 0 out of range");
  write_tetgen("range", 1);
  write_file("range.ele", "1 4 0\n1 1 2 3 9\n");
  expect_error(read_error(tmp_dir() / "range.ele"), "range.ele", "line 2",
               "vertex index 9 out of range (expected 1 to 8)");
  write_file("range0.node", "4 3\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n");
  write_file("range0.ele", "1 4\n0 1 2 3 4\n");
  expect_error(read_error(tmp_dir() / "range0.ele"), "range0.ele", "line 2",
               "vertex index 4 out of range (expected 0 to 3)");
  expect_error(read_error("gap.node", "2 3 0 0\n1 0 0 0\n3 1 0 0\n"), "gap.node", "line 3",
               "expected point index 2, found 3");
}

TEST(ReadTetMesh, BinaryVersionsAndMissingSections) {
  expect_error(read_error("binary.msh", "$MeshFormat\n4.1 1 8\n\x01\n$EndMeshFormat\n"), "binary.msh", "line 2",
               "binary .msh is not supported, save as ASCII");
  expect_error(read_error("v3.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n"), "v3.msh", "line 2",
               "unsupported .msh format version '3.0'");
  expect_error(read_error("v1.msh", "$NOD\n1\n1 0 0 0\n$ENDNOD\n"), "v1.msh", "line 1",
               "expected $MeshFormat first, found '$NOD'");
  const std::string head = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
  expect_error(read_error("nonodes.msh", head), "nonodes.msh", "", "no $Nodes section");
  expect_error(read_error("noelements.msh", head + "$Nodes\n1\n1 0 0 0\n$EndNodes\n"), "noelements.msh", "",
               "no $Elements section");
  expect_error(read_error("order.msh", head + "$Elements\n0\n$EndElements\n"), "order.msh", "line 4",
               "$Elements before $Nodes");
  expect_error(read_error("empty.msh", ""), "empty.msh", "", "no $MeshFormat section");
}

TEST(ReadTetMesh, NoTetrahedra) {
  expect_error(read_error("triangles.msh",
                          "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n$EndNodes\n"
                          "$Elements\n1\n1 2 0 1 2 3\n$EndElements\n"),
               "triangles.msh", "", "no tetrahedra (element type 4) in the file");
  expect_error(read_error("points.tet", "v 0 0 0\n"), "points.tet", "", "no tetrahedra in the file");
}

TEST(ReadTetMesh, MissingFiles) {
  write_file("lonely.ele", "1 4 0\n1 1 2 3 4\n");
  fs::remove(tmp_dir() / "lonely.node");
  const Error e = read_error(tmp_dir() / "lonely.ele");
  expect_error(e, "lonely.node", "", "cannot open the .node file that ");
  EXPECT_NE(e.what.find("lonely.ele needs"), std::string::npos) << e.what;
  write_file("alone.node", "1 3\n1 0 0 0\n");
  fs::remove(tmp_dir() / "alone.ele");
  expect_error(read_error(tmp_dir() / "alone.node"), "alone.ele", "", "cannot open the .ele file that ");
  expect_error(read_error(tmp_dir() / "no_such.msh"), "no_such.msh", "", "cannot open the mesh file");
  expect_error(read_error("box.obj", "v 0 0 0\n"), "box.obj", "", "not a tetrahedral mesh file");
}

TEST(ReadTetMesh, FlatAndRepeatingTetrahedraNameTheLine) {
  expect_error(read_error("flat.tet", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nt 1 2 3 4\n"), "flat.tet", "line 5",
               "tetrahedron 0 (vertices 1, 2, 3, 4) is flat: volume 0");
  std::string msh = msh2_file();
  msh.replace(msh.find("5 5 5"), 5, "0.1 1 2");  // node 500 onto the side x = 0.1 ...
  msh.replace(msh.find("24 4 2 7 1 7 55 1000 8"), 22, "24 4 2 7 1 500 55 1000 101");  // ... with three corners there
  expect_error(read_error("flat.msh", msh), "flat.msh", "line 32",
               "tetrahedron 4 (vertices 500, 55, 1000, 101) is flat");
  expect_error(read_error("repeat.tet", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nt 1 2 3 2\n"), "repeat.tet", "line 5",
               "tetrahedron 0 uses vertex 2 twice");
}

// --- validate and the generators -------------------------------------------------------------

TEST(Validate, RefusesAFaceSharedByThreeTetrahedra) {
  Mesh m;
  m.positions.resize(3, 6);
  m.positions << 0, 1, 0, 0, 0, 0.2,  //
      0, 0, 1, 0, 0, 0.2,             //
      0, 0, 0, 1, -1, 2;
  m.tetrahedra.resize(4, 3);
  m.tetrahedra << 0, 0, 0,  //
      1, 1, 2,              //
      2, 2, 1,              //
      3, 5, 4;
  for (Eigen::Index t = 0; t < 3; ++t) ASSERT_GT(signed_volume(m, t), 0);
  m.triangles = pce::sim::boundary_faces(m.tetrahedra);
  m.segments.resize(2, 0);
  try {
    pce::sim::validate(m, "three.tet");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("three.tet: tetrahedra 0, 1 and 2 share a face (vertices 0, 1, 2)"),
              std::string::npos)
        << e.what();
  }
  m.tetrahedra.conservativeResize(4, 2);  // two of them: an interior face, accepted
  m.triangles = pce::sim::boundary_faces(m.tetrahedra);
  EXPECT_EQ(m.triangles.cols(), 6);
  EXPECT_NO_THROW(pce::sim::validate(m, "two.tet"));
}

/// Every boundary edge in exactly two faces, once in each direction (a closed, consistently
/// oriented surface); and Σ area-weighted normal · centroid = 3 · volume (the divergence
/// theorem for the field x: the normals point out).
void expect_closed_outward(const Mesh& m, double volume, double tolerance) {
  std::map<std::pair<int, int>, int> directed;
  double flux = 0;
  for (Eigen::Index f = 0; f < m.triangles.cols(); ++f) {
    for (int k = 0; k < 3; ++k) ++directed[{m.triangles(k, f), m.triangles((k + 1) % 3, f)}];
    const Eigen::Vector3d a = m.positions.col(m.triangles(0, f)), b = m.positions.col(m.triangles(1, f)),
                          c = m.positions.col(m.triangles(2, f));
    flux += 0.5 * (b - a).cross(c - a).dot((a + b + c) / 3.0);
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "edge " << edge.first << " → " << edge.second;
    const auto back = directed.find({edge.second, edge.first});
    EXPECT_TRUE(back != directed.end() && back->second == 1) << "edge " << edge.first << " – " << edge.second;
  }
  EXPECT_NEAR(flux, 3 * volume, tolerance);
}

TEST(TetBox, CountsVolumeOrientationAndBoundary) {
  const Eigen::Vector3d size(1.5, 0.5, 2.25);
  const Eigen::Vector3i n(3, 2, 4);
  const Mesh m = pce::sim::tet_box(size, n);
  EXPECT_EQ(m.vertex_count(), 4 * 3 * 5);
  ASSERT_EQ(m.tetrahedra.cols(), 6 * 3 * 2 * 4);
  for (Eigen::Index t = 0; t < m.tetrahedra.cols(); ++t) EXPECT_GT(signed_volume(m, t), 0) << "tetrahedron " << t;
  EXPECT_NEAR(total_volume(m), size.prod(), 1e-14);
  EXPECT_EQ(m.triangles.cols(), 2 * 2 * (3 * 2 + 2 * 4 + 3 * 4));
  EXPECT_EQ(m.triangles, pce::sim::boundary_faces(m.tetrahedra));
  EXPECT_EQ(m.segments.cols(), 0);
  expect_closed_outward(m, size.prod(), 1e-13);
  EXPECT_EQ(m.positions.col(2 + 4 * (1 + 3 * 3)),
            Eigen::Vector3d((2.0 / 3 - 0.5) * 1.5, (1.0 / 2 - 0.5) * 0.5, (3.0 / 4 - 0.5) * 2.25));  // (2, 1, 3)
  EXPECT_NO_THROW(pce::sim::validate(m, "tet_box"));
  for (int t = 6 * (2 + 3 * (1 + 2 * 3)); t < 6 * (2 + 3 * (1 + 2 * 3)) + 6; ++t)  // cube (2, 1, 3)'s six
    for (int k = 0; k < 4; ++k) {
      const int v = m.tetrahedra(k, t), i = v % 4, j = v / 4 % 3, l = v / 12;
      EXPECT_TRUE(i >= 2 && i <= 3 && j >= 1 && j <= 2 && l >= 3 && l <= 4) << "tetrahedron " << t << ": " << v;
    }
  const Mesh one = pce::sim::tet_box(Eigen::Vector3d(1, 2, 3), Eigen::Vector3i(1, 1, 1));
  EXPECT_EQ(one.tetrahedra.cols(), 6);
  EXPECT_EQ(one.triangles.cols(), 12);
  EXPECT_NEAR(total_volume(one), 6.0, 1e-14);
}

TEST(TetBall, EveryTetrahedronPositiveAndWellShaped) {
  // Kuhn's cubes mirrored per octant keep volume / longest edge³ ≥ 0.0244 up to n = 24
  // (with one diagonal direction for all cubes it falls as 1/n², to 1.5e-5 at n = 24).
  for (int n = 1; n <= 24; ++n) {
    const Mesh m = pce::sim::tet_ball(1.0, n);
    ASSERT_EQ(m.tetrahedra.cols(), 6 * 8 * n * n * n);
    double worst = 1;
    for (Eigen::Index t = 0; t < m.tetrahedra.cols(); ++t) worst = std::min(worst, quality(m, t));
    EXPECT_GT(worst, 0.02) << "n = " << n;
  }
}

TEST(TetBall, BoundaryOnTheSphereVolumeConverges) {
  const double r = 0.8, pi = std::acos(-1.0), ball = 4.0 / 3.0 * pi * r * r * r;
  const Mesh m = pce::sim::tet_ball(r, 8);
  EXPECT_EQ(m.vertex_count(), 17 * 17 * 17);
  ASSERT_EQ(m.triangles.cols(), 6 * 2 * 16 * 16);
  EXPECT_EQ(m.triangles, pce::sim::boundary_faces(m.tetrahedra));
  for (Eigen::Index f = 0; f < m.triangles.cols(); ++f)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.positions.col(m.triangles(k, f)).norm(), r, 1e-15);
  EXPECT_EQ(m.positions.col((17 * 17 * 17 - 1) / 2), Eigen::Vector3d::Zero());
  const double v8 = total_volume(m);
  expect_closed_outward(m, v8, 1e-13);
  EXPECT_NO_THROW(pce::sim::validate(m, "tet_ball"));
  // Bound: a boundary edge is at most a cube face's diagonal projected onto the sphere, which
  // does not lengthen it: L ≤ √2 r / n. A point of a face, a convex combination of three
  // points on the sphere, is at least √(r² − L²/3) ≥ r − L²/(3r) = r (1 − 2/(3n²)) from the
  // centre, so the ball of that radius lies inside; and the whole mesh inside the sphere.
  const double n = 8, inner = r * (1 - 2 / (3 * n * n));
  EXPECT_LT(v8, ball);
  EXPECT_GT(v8, 4.0 / 3.0 * pi * inner * inner * inner);
  // The missing caps are second order in the spacing: a quarter of n = 4's (0.254 measured).
  const double v4 = total_volume(pce::sim::tet_ball(r, 4));
  EXPECT_GT((ball - v8) / (ball - v4), 0.2);
  EXPECT_LT((ball - v8) / (ball - v4), 0.3);
}

TEST(TetGenerators, InvalidParametersAreInputErrors) {
  using Eigen::Vector3d;
  using Eigen::Vector3i;
  EXPECT_THROW(pce::sim::tet_box(Vector3d(1, 0, 1), Vector3i(1, 1, 1)), InputError);
  EXPECT_THROW(pce::sim::tet_box(Vector3d(1, std::nan(""), 1), Vector3i(1, 1, 1)), InputError);
  EXPECT_THROW(pce::sim::tet_box(Vector3d(1, 1, 2e6), Vector3i(1, 1, 1)), InputError);
  EXPECT_THROW(pce::sim::tet_box(Vector3d(1, 1, 1), Vector3i(1, 0, 1)), InputError);
  EXPECT_THROW(pce::sim::tet_box(Vector3d(1, 1, 1), Vector3i(257, 1, 1)), InputError);
  EXPECT_THROW(pce::sim::tet_box(Vector3d(1, 1, 1), Vector3i(256, 256, 256)), InputError);  // 257³ > 2^24
  EXPECT_NO_THROW(pce::sim::tet_box(Vector3d(1, 1, 1), Vector3i(256, 1, 1)));
  EXPECT_THROW(pce::sim::tet_ball(-1, 2), InputError);
  EXPECT_THROW(pce::sim::tet_ball(std::nan(""), 2), InputError);
  EXPECT_THROW(pce::sim::tet_ball(1, 0), InputError);
  EXPECT_THROW(pce::sim::tet_ball(1, 128), InputError);
}

}  // namespace
