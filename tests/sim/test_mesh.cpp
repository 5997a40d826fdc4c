// SPDX-License-Identifier: MIT
// pce::sim meshes (src/sim/mesh): OBJ reading of every face and polyline form the contract
// names, round trips, and one InputError naming file and line for each kind of bad input;
// the generators' counts, geometry and orientation; validation and unique edges.
#include <pce/sim/generators.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/obj.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>

namespace {
namespace fs = std::filesystem;
using pce::sim::InputError;

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path p = fs::path(PCE_TEST_TMP) / name;
  std::ofstream(p) << text;
  return p;
}

/// The message of the InputError that reading `text` throws ("" if none).
std::pair<std::string, std::string> obj_error(const std::string& name, const std::string& text) {
  try {
    pce::sim::read_obj(write_file(name, text));
  } catch (const InputError& e) {
    return {e.where(), e.what()};
  }
  return {"", ""};
}

TEST(ReadObj, TrianglesQuadsAndEveryIndexForm) {
  const fs::path p =
      write_file("forms.obj",
                 "# a comment\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\nvt 0 0\nvn 0 0 1\n"
                 "f 1/1/1 2/1/1 3/1/1\ns off\nf 1//1 3//1 4//1\nf -4 -3 -2 -1   # a quad, relative indices\r\n");
  const pce::sim::Mesh m = pce::sim::read_obj(p);
  ASSERT_EQ(m.vertex_count(), 4);
  ASSERT_EQ(m.triangles.cols(), 4);  // 1 + 1 + a fan of 2
  EXPECT_EQ(m.triangles.col(0), Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(m.triangles.col(1), Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(m.triangles.col(2), Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(m.triangles.col(3), Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(m.segments.cols(), 0);
  EXPECT_EQ(m.positions.col(2), Eigen::Vector3d(1, 1, 0));
}

TEST(ReadObj, PolylinesBecomeSegments) {
  const pce::sim::Mesh m =
      pce::sim::read_obj(write_file("strand.obj", "v 0 0 0\nv 0 0 -1\nv 0 0 -2\nv 1 0 0\nv 1 0 -1\nl 1 2 3\nl 4 5\n"));
  ASSERT_EQ(m.segments.cols(), 3);
  EXPECT_EQ(m.segments.col(1), Eigen::Vector2i(1, 2));
  EXPECT_EQ(m.segments.col(2), Eigen::Vector2i(3, 4));
  EXPECT_EQ(m.triangles.cols(), 0);
}

TEST(ReadObj, RoundTripIsExact) {
  pce::sim::Mesh m = pce::sim::grid(1.3, 0.7, 5, 3);
  m.positions.col(4) << 0.1, 1.0 / 3.0, -2e-300;
  const pce::sim::Mesh s = pce::sim::strands(2, 3, 1.0, 0.1, 0.01);
  pce::sim::write_obj(fs::path(PCE_TEST_TMP) / "grid.obj", m);
  pce::sim::write_obj(fs::path(PCE_TEST_TMP) / "strands.obj", s);
  const pce::sim::Mesh m2 = pce::sim::read_obj(fs::path(PCE_TEST_TMP) / "grid.obj");
  const pce::sim::Mesh s2 = pce::sim::read_obj(fs::path(PCE_TEST_TMP) / "strands.obj");
  EXPECT_EQ(m2.positions, m.positions);
  EXPECT_EQ(m2.triangles, m.triangles);
  EXPECT_EQ(s2.positions, s.positions);
  EXPECT_EQ(s2.segments, s.segments);
}

// One test per kind of bad input: each names the file and the line.
TEST(ReadObj, MissingFile) {
  try {
    pce::sim::read_obj(fs::path(PCE_TEST_TMP) / "no_such_mesh.obj");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (fs::path(PCE_TEST_TMP) / "no_such_mesh.obj").string());
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
}

TEST(ReadObj, MalformedNumber) {
  const auto [where, what] = obj_error("bad_number.obj", "v 0 0 0\nv 1 0 0\nv 1 x 0\n");
  EXPECT_EQ(where, "line 3");
  EXPECT_NE(what.find("bad_number.obj: line 3: expected a number, found 'x'"), std::string::npos) << what;
}

TEST(ReadObj, NonFiniteCoordinate) {
  EXPECT_EQ(obj_error("nan.obj", "v 0 0 0\nv nan 0 0\n").first, "line 2");
  EXPECT_EQ(obj_error("inf.obj", "v 0 0 0\nv 1e999 0 0\n").first, "line 2");
}

TEST(ReadObj, WrongCounts) {
  EXPECT_EQ(obj_error("short_v.obj", "v 0 0\n").first, "line 1");
  EXPECT_EQ(obj_error("short_f.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n").first, "line 3");
  EXPECT_EQ(obj_error("short_l.obj", "v 0 0 0\nl 1\n").first, "line 2");
}

TEST(ReadObj, OutOfRangeIndex) {
  const auto [where, what] = obj_error("range.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n");
  EXPECT_EQ(where, "line 4");
  EXPECT_NE(what.find("vertex index 4 out of range (3 vertices so far)"), std::string::npos) << what;
  EXPECT_EQ(obj_error("zero.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 0 1 2\n").first, "line 4");
  EXPECT_EQ(obj_error("negative.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf -1 -2 -4\n").first, "line 4");
  EXPECT_EQ(obj_error("forward.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 1 1 0\n").first, "line 3");  // not yet defined
  EXPECT_EQ(obj_error("garbage.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3x\n").first, "line 4");
}

TEST(ReadObj, RepeatedVertexAndEmptyMesh) {
  const auto [where, what] = obj_error("repeat.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 1\n");
  EXPECT_NE(what.find("triangle 0 uses vertex 0 twice"), std::string::npos) << what;
  EXPECT_NE(obj_error("empty.obj", "# nothing\n").second.find("no vertices"), std::string::npos);
}

TEST(WriteObj, UnwritablePathIsAnInputError) {
  EXPECT_THROW(pce::sim::write_obj(fs::path(PCE_TEST_TMP) / "no_such_dir" / "x.obj", pce::sim::grid(1, 1, 1, 1)),
               InputError);
}

TEST(Generators, GridCountsAreaAndOrientation) {
  const pce::sim::Mesh m = pce::sim::grid(2.0, 1.0, 4, 3);
  EXPECT_EQ(m.vertex_count(), 5 * 4);
  ASSERT_EQ(m.triangles.cols(), 2 * 4 * 3);
  double area = 0;
  for (Eigen::Index t = 0; t < m.triangles.cols(); ++t) {
    const Eigen::Vector3d a = m.positions.col(m.triangles(0, t)), b = m.positions.col(m.triangles(1, t)),
                          c = m.positions.col(m.triangles(2, t));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    EXPECT_GT(n.z(), 0) << "triangle " << t << " faces −z";
    area += 0.5 * n.norm();
  }
  EXPECT_NEAR(area, 2.0, 1e-14);
  EXPECT_EQ(pce::sim::unique_edges(m.triangles).cols(), 4 * 4 + 5 * 3 + 4 * 3);  // horizontal, vertical, diagonal
  EXPECT_NO_THROW(pce::sim::validate(m, "grid"));
  EXPECT_EQ(m.positions.col(3 * 5 + 4), Eigen::Vector3d(1.0, 0.5, 0.0));  // vertex (i, j) = (4, 3)
}

TEST(Generators, StrandsCountsLengthsAndSpacing) {
  const pce::sim::Mesh m = pce::sim::strands(5, 8, 2.0, 0.25);
  EXPECT_EQ(m.vertex_count(), 5 * 9);
  ASSERT_EQ(m.segments.cols(), 5 * 8);
  for (Eigen::Index s = 0; s < m.segments.cols(); ++s)
    EXPECT_NEAR((m.positions.col(m.segments(1, s)) - m.positions.col(m.segments(0, s))).norm(), 0.25, 1e-15);
  std::set<std::pair<double, double>> roots;
  for (int k = 0; k < 5; ++k) roots.insert({m.positions(0, k * 9), m.positions(1, k * 9)});
  EXPECT_EQ(roots.size(), 5u);
  const pce::sim::Mesh c = pce::sim::strands(3, 40, 1.0, 0.5, 0.05);  // curly: radius 0.05 about each axis
  for (Eigen::Index v = 0; v < c.vertex_count(); ++v) {
    const int k = static_cast<int>(v / 41);
    const Eigen::Vector2d axis =
        c.positions.col(k * 41).head<2>() -
        0.05 * Eigen::Vector2d(std::cos(2.399963229728653 * k), std::sin(2.399963229728653 * k));
    EXPECT_NEAR((c.positions.col(v).head<2>() - axis).norm(), 0.05, 1e-12);
  }
}

TEST(Generators, InvalidParametersAreInputErrors) {
  EXPECT_THROW(pce::sim::grid(0, 1, 2, 2), InputError);
  EXPECT_THROW(pce::sim::grid(1, std::nan(""), 2, 2), InputError);
  EXPECT_THROW(pce::sim::grid(1, 1, 0, 2), InputError);
  EXPECT_THROW(pce::sim::strands(0, 2, 1, 1), InputError);
  EXPECT_THROW(pce::sim::strands(2, 2, -1, 1), InputError);
  EXPECT_THROW(pce::sim::strands(2, 2, 1, 1, -0.1), InputError);
}

TEST(Generators, SizesAndCountsBeyondTheLimitsAreInputErrors) {
  // 2^20 strands of 2^16 segments: count (segments + 1) overflowed int before anything
  // checked it; now refused before allocation (kMaxVertices).
  EXPECT_THROW(pce::sim::strands(1 << 20, 1 << 16, 1, 1), InputError);
  EXPECT_THROW(pce::sim::grid(1, 1, 4096, 4096), InputError);  // 4097² > 2^24 vertices
  EXPECT_NO_THROW(pce::sim::grid(1, 1, 4095, 1));
  EXPECT_THROW(pce::sim::grid(1e308, 1, 2, 2), InputError);
  EXPECT_THROW(pce::sim::grid(1, 2e6, 2, 2), InputError);
  EXPECT_THROW(pce::sim::strands(2, 2, 1e7, 1), InputError);
  EXPECT_THROW(pce::sim::strands(2, 2, 1, 1e300), InputError);
  EXPECT_THROW(pce::sim::strands(2, 2, 1, 1, 1e300), InputError);
  EXPECT_NO_THROW(pce::sim::grid(pce::sim::kMaxCoordinate, 1, 1, 1));
}

TEST(Mesh, CoordinatesBeyondTheLimitAreRefused) {
  pce::sim::Mesh m = pce::sim::grid(1, 1, 1, 1);
  m.positions(2, 1) = pce::sim::kMaxCoordinate;
  EXPECT_NO_THROW(pce::sim::validate(m, "m"));
  m.positions(2, 1) = -1.5e6;
  try {
    pce::sim::validate(m, "scene.json: meshes[0]");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 1 at (0.5, -0.5, -1500000) is beyond |coordinate| <= 1e+06"),
              std::string::npos)
        << e.what();
  }
  // An OBJ file: refused by read_obj's validate, naming the file.
  const auto [where, what] = obj_error("far.obj", "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(where, "");
  EXPECT_NE(what.find("far.obj: vertex 1 at (1"), std::string::npos) << what;
  EXPECT_NE(what.find(") is beyond |coordinate| <= 1e+06"), std::string::npos) << what;
}

TEST(Mesh, TransformAndValidate) {
  pce::sim::Mesh m = pce::sim::grid(1, 1, 1, 1);
  pce::sim::Transform t;
  t.scale = 2;
  t.rotation = Eigen::AngleAxisd(std::acos(-1.0) / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  t.translation << 0, 0, 5;
  pce::sim::apply(t, m);
  EXPECT_TRUE(m.positions.col(3).isApprox(Eigen::Vector3d(1, 0, 6), 1e-15)) << m.positions.col(3).transpose();
  m.positions(1, 2) = std::nan("");
  try {
    pce::sim::validate(m, "scene.json: meshes[0]");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 2 has a non-finite coordinate"), std::string::npos) << e.what();
  }
}

}  // namespace
