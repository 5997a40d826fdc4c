// SPDX-License-Identifier: MIT
// Scene files: every kind of invalid input is one InputError naming the file, the JSON
// path and what was expected (keyframed motions' too); only declared effects are built;
// the shipped scenes load.
#include <pce/sim/input_error.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

using namespace pce::sim;
using nlohmann::json;

namespace {

json minimal() {
  return json::parse(R"({
    "dt": 0.025, "frames": 2,
    "meshes": [{"name": "cloth", "generator": {"type": "grid", "width": 1, "height": 1, "nx": 4, "ny": 4}}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 10}]
  })");
}

/// Loads `j` and returns the InputError's path (fails the test when it loads).
std::string error_path(const json& j, std::string* message = nullptr) {
  try {
    load_scene_text(j.dump(), "scene.json", PCE_TEST_TMP);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "scene.json");
    if (message) *message = e.what();
    return e.where();
  }
  ADD_FAILURE() << "scene loaded: " << j.dump();
  return "";
}

void write(const std::filesystem::path& p, const std::string& text) { std::ofstream(p) << text; }

}  // namespace

TEST(Scene, MinimalLoadsAndBuildsOnlyDeclaredEffects) {
  const auto s = load_scene_text(minimal().dump(), "scene.json", PCE_TEST_TMP);
  ASSERT_EQ(s->simulation.effects.size(), 2u);
  EXPECT_STREQ(s->simulation.effects[0]->name(), "gravity");
  EXPECT_STREQ(s->simulation.effects[1]->name(), "stretching");
  EXPECT_EQ(s->simulation.model.vertex_count(), 25);
  EXPECT_NEAR(s->simulation.model.mass.sum(), 0.1, 1e-12);  // 1 m² at the default 0.1 kg/m²
}

TEST(Scene, UnknownEffect) {
  json j = minimal();
  j["effects"][1]["type"] = "stretchin";
  std::string msg;
  EXPECT_EQ(error_path(j, &msg), "effects[1].type");
  EXPECT_NE(msg.find("unknown effect \"stretchin\""), std::string::npos) << msg;
}

TEST(Scene, MissingField) {
  json j = minimal();
  j.erase("dt");
  EXPECT_EQ(error_path(j), "dt");
  j = minimal();
  j["effects"][1].erase("stiffness");
  EXPECT_EQ(error_path(j), "effects[1].stiffness");
}

TEST(Scene, WrongType) {
  json j = minimal();
  j["frames"] = "ten";
  std::string msg;
  EXPECT_EQ(error_path(j, &msg), "frames");
  EXPECT_NE(msg.find("expected an integer, got a string"), std::string::npos) << msg;
  j = minimal();
  j["meshes"][0]["generator"]["nx"] = 4.5;
  EXPECT_EQ(error_path(j), "meshes[0].generator.nx");
}

TEST(Scene, NonFiniteOrNegativeParameter) {
  json j = minimal();
  j["dt"] = -0.01;
  EXPECT_EQ(error_path(j), "dt");
  j = minimal();
  j["effects"][1]["stiffness"] = -1.0;
  EXPECT_EQ(error_path(j), "effects[1].stiffness");
  // JSON has no NaN literal and no infinity; a number beyond double's range is refused by
  // the parser, and a NaN coordinate in a mesh file by the mesh check.
  std::string text = minimal().dump();
  text.replace(text.find("0.025"), 5, "1e999");
  try {
    load_scene_text(text, "scene.json", PCE_TEST_TMP);
    ADD_FAILURE() << "loaded an infinite dt";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.json: not valid JSON"), std::string::npos) << e.what();
  }
  write(std::filesystem::path(PCE_TEST_TMP) / "nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n");
  j = minimal();
  j["meshes"][0] = json::parse(R"({"name": "m", "file": "nan.obj"})");
  std::string msg;
  EXPECT_EQ(error_path(j, &msg), "meshes[0].file");
  EXPECT_NE(msg.find("finite"), std::string::npos) << msg;
}

TEST(Scene, UnknownFieldIsATypo) {
  json j = minimal();
  j["effects"][1]["stifness"] = 3;
  EXPECT_EQ(error_path(j), "effects[1].stifness");
}

TEST(Scene, MissingMeshFile) {
  json j = minimal();
  j["meshes"][0] = json::parse(R"({"name": "m", "file": "no_such_mesh.obj"})");
  std::string msg;
  EXPECT_EQ(error_path(j, &msg), "meshes[0].file");
  EXPECT_NE(msg.find("not found"), std::string::npos) << msg;
}

TEST(Scene, MalformedObj) {
  write(std::filesystem::path(PCE_TEST_TMP) / "malformed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 zero\nf 1 2 3\n");
  json j = minimal();
  j["meshes"][0] = json::parse(R"({"name": "m", "file": "malformed.obj"})");
  std::string msg;
  EXPECT_EQ(error_path(j, &msg), "meshes[0].file");
  EXPECT_NE(msg.find("line 3"), std::string::npos) << msg;
}

TEST(Scene, OutOfRangeIndex) {
  write(std::filesystem::path(PCE_TEST_TMP) / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  json j = minimal();
  j["meshes"][0] = json::parse(R"({"name": "m", "file": "range.obj"})");
  EXPECT_EQ(error_path(j), "meshes[0].file");
  j = minimal();
  j["effects"].push_back(json::parse(R"({"type": "pins", "groups": [{"vertices": [0, 25]}]})"));
  EXPECT_EQ(error_path(j), "effects[2].groups[0].vertices[1]");
}

TEST(Scene, ContactOptionsAreChecked) {
  json j = minimal();
  j["effects"].push_back(json::parse(
      R"({"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 10, "distance": 0.01},
          "length": "signed", "closest_features": true})"));
  EXPECT_EQ(error_path(j), "effects[2].length");
  j["effects"][2]["length"] = "unsigned";
  j["effects"][2]["penalty"]["type"] = "log_barrier";
  j["effects"][2]["closest_features"] = false;
  EXPECT_EQ(error_path(j), "effects[2].closest_features");  // the barrier needs true distances
  j["effects"][2]["penalty"]["distance"] = 0.0;
  j["effects"][2]["closest_features"] = true;
  EXPECT_EQ(error_path(j), "effects[2].penalty.distance");
}

TEST(Scene, ContactDistanceOf1e308IsRefusedNotACrash) {
  // twist.json with effects[5].penalty.distance = 1e308 crashed pce-sim in the broad phase
  // (boxes grown to ±inf); the scene is now refused at that path, and a distance beyond
  // half the model's diagonal is refused too (every pair would be a candidate).
  const std::filesystem::path file = std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes" / "twist.json";
  json j = json::parse(std::ifstream(file));
  ASSERT_EQ(j["effects"][5]["type"], "self_vertex_face");
  j["effects"][5]["penalty"]["distance"] = 1e308;
  std::string msg;
  EXPECT_EQ(error_path(j, &msg), "effects[5].penalty.distance");
  EXPECT_EQ(msg.rfind("scene.json: effects[5].penalty.distance: expected a number > 0 and <= 1e+06", 0), 0u) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  j["effects"][5]["penalty"]["distance"] = 1.0;  // the ribbon is 0.4 × 1.6 m: half its diagonal is 0.82 m
  EXPECT_EQ(error_path(j, &msg), "effects[5].penalty.distance");
  EXPECT_NE(msg.find("half the diagonal 1.64924225024706"), std::string::npos) << msg;
  j["effects"][5]["penalty"]["distance"] = 0.8;
  EXPECT_NO_THROW(load_scene_text(j.dump(), "scene.json", PCE_TEST_TMP));
  j["effects"][6]["penalty"]["distance"] = 1e6;
  EXPECT_EQ(error_path(j), "effects[6].penalty.distance");
}

TEST(Scene, AbsurdNumbersAreRefusedWithTheirPath) {
  json base = minimal();
  base["obstacles"] = json::parse(R"([{"name": "ball", "shape": "sphere", "radius": 0.2,
      "motion": {"velocity": [0, 0, 1]}},
    {"name": "floor", "shape": "box", "half_extents": [1, 1, 0.1], "position": [0, 0, -1]},
    {"name": "bar", "shape": "capsule", "radius": 0.1, "half_length": 0.5}])");
  base["effects"].push_back(json::parse(R"({"type": "damping", "coefficient": 0.1})"));
  base["effects"].push_back(json::parse(R"({"type": "pins", "stiffness": 1e4,
      "groups": [{"vertices": [0], "motion": {"velocity": [0, 0, 1], "center": [0, 0, 0]}}]})"));
  base["effects"].push_back(json::parse(R"({"type": "obstacle_contact",
      "penalty": {"type": "cubic", "stiffness": 10, "distance": 0.01, "delta": 1e-6}})"));
  base["effects"].push_back(json::parse(R"({"type": "bending", "stiffness": 1e-3})"));
  base["effects"].push_back(json::parse(R"({"type": "self_vertex_face",
      "penalty": {"type": "quadratic", "stiffness": 10, "distance": 0.01}})"));
  ASSERT_NO_THROW(load_scene_text(base.dump(), "scene.json", PCE_TEST_TMP));
  const double huge = 1e308, denormal = 1e-320;
  const struct {
    const char* pointer;  // JSON pointer of the field to set
    json value;
    const char* path;  // the JSON path the error must name
  } cases[] = {
      {"/dt", huge, "dt"},
      {"/dt", denormal, "dt"},
      {"/dt", 2.0, "dt"},
      {"/meshes/0/density", huge, "meshes[0].density"},
      {"/meshes/0/density", denormal, "meshes[0].density"},
      {"/meshes/0/generator/width", huge, "meshes[0].generator.width"},
      {"/meshes/0/generator/height", 2e6, "meshes[0].generator.height"},
      {"/meshes/0/transform", json::parse(R"({"translation": [1e300, 0, 0]})"), "meshes[0].transform.translation"},
      {"/meshes/0/transform", json::parse(R"({"scale": 1e300})"), "meshes[0].transform.scale"},
      {"/meshes/0/transform", json::parse(R"({"scale": 1e-320})"), "meshes[0].transform.scale"},
      {"/meshes/0/transform", json::parse(R"({"scale": 1e6, "translation": [9e5, 0, 0]})"), "meshes[0].generator"},
      {"/meshes/0/generator",
       json::parse(R"({"type": "strands", "count": 1048576, "segments": 65536, "length": 1, "spacing": 1})"),
       "meshes[0].generator.type"},
      {"/meshes/0/generator", json::parse(R"({"type": "strands", "count": 2, "segments": 2, "length": 1e300,
         "spacing": 1})"),
       "meshes[0].generator.length"},
      {"/obstacles/0/radius", huge, "obstacles[0].radius"},
      {"/obstacles/0/position", json::array({0, huge, 0}), "obstacles[0].position"},
      {"/obstacles/0/motion/velocity", json::array({huge, 0, 0}), "obstacles[0].motion.velocity"},
      {"/obstacles/0/motion/angular_velocity", json::array({0, 0, 1e7}), "obstacles[0].motion.angular_velocity"},
      {"/obstacles/1/half_extents", json::array({1, huge, 1}), "obstacles[1].half_extents"},
      {"/obstacles/2/half_length", 1e200, "obstacles[2].half_length"},
      {"/effects/0/acceleration", json::array({0, 0, -huge}), "effects[0].acceleration"},
      {"/effects/1/stiffness", huge, "effects[1].stiffness"},
      {"/effects/2/coefficient", huge, "effects[2].coefficient"},
      {"/effects/3/stiffness", 1e13, "effects[3].stiffness"},
      {"/effects/3/groups/0/motion/velocity", json::array({0, huge, 0}), "effects[3].groups[0].motion.velocity"},
      {"/effects/3/groups/0/motion/center", json::array({0, huge, 0}), "effects[3].groups[0].motion.center"},
      {"/effects/4/penalty/stiffness", huge, "effects[4].penalty.stiffness"},
      {"/effects/4/penalty/distance", huge, "effects[4].penalty.distance"},
      {"/effects/4/penalty/delta", huge, "effects[4].penalty.delta"},
      {"/effects/5/stiffness", huge, "effects[5].stiffness"},
      {"/effects/6/penalty/distance", huge, "effects[6].penalty.distance"},
      {"/effects/6/penalty/distance", 1.0, "effects[6].penalty.distance"},  // the grid is 1 × 1 m
      {"/effects/6/penalty/stiffness", 1e300, "effects[6].penalty.stiffness"},
  };
  for (const auto& c : cases) {
    json j = base;
    j[json::json_pointer(c.pointer)] = c.value;
    std::string msg;
    EXPECT_EQ(error_path(j, &msg), c.path) << c.pointer << " = " << c.value.dump() << ": " << msg;
    EXPECT_EQ(msg.rfind(std::string("scene.json: ") + c.path + ": ", 0), 0u) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

TEST(Scene, KeyframedMotionsLoadAndEveryBadKeyframeNamesItsPath) {
  // One keyframed obstacle and one keyframed pin group; each bad input gives one error naming
  // its JSON path, with the same message for an obstacle's and a pin group's motion.
  json base = minimal();
  base["obstacles"] = json::parse(R"([{"name": "paddle", "shape": "box", "half_extents": [0.3, 0.05, 0.02],
      "position": [0, 0, 0.6], "motion": {"interpolation": "smooth", "keyframes": [
        {"time": 0},
        {"time": 0.5, "translation": [0, 0, -0.3]},
        {"time": 1.5, "translation": [0, 0, -0.3], "rotation": {"axis": [0, 0, 1], "degrees": 90}},
        {"time": 2.0, "rotation": {"axis": [0, 0, 1], "degrees": 90}}]}}])");
  base["effects"].push_back(json::parse(R"({"type": "pins", "groups": [{"vertices": [0],
      "motion": {"center": [0, 0, 0], "keyframes": [{"time": 0}, {"time": 0.5, "translation": [0, 0, 0.2]}]}}]})"));
  const auto loaded = load_scene_text(base.dump(), "scene.json", PCE_TEST_TMP);
  const Motion& paddle = loaded->simulation.obstacles.at(0).motion;
  ASSERT_EQ(paddle.keyframes.size(), 4u);
  EXPECT_EQ(paddle.interpolation, Interpolation::smooth);
  EXPECT_EQ(paddle.keyframes[0].translation, Eigen::Vector3d::Zero());
  EXPECT_EQ(paddle.keyframes[0].rotation, Eigen::Matrix3d::Identity());
  EXPECT_EQ(paddle.keyframes[1].time, 0.5);
  EXPECT_EQ(paddle.keyframes[1].translation, Eigen::Vector3d(0, 0, -0.3));
  EXPECT_LT((paddle.keyframes[3].rotation * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-15);
  EXPECT_EQ(loaded->simulation.obstacles.at(0).pose(1.0).translation(), Eigen::Vector3d(0, 0, 0.3));

  const struct {
    const char* pointer;  // JSON pointer of the field to set, below the motion
    json value;
    const char* path;     // the error's JSON path, below the motion
    const char* message;  // a part of the error's message
  } cases[] = {
      {"/keyframes/2/time", 0.4, "keyframes[2].time", "expected a time greater than keyframes[1]'s (0.5), got 0.4"},
      {"/keyframes/1/time", 0.0, "keyframes[1].time", "expected a time greater than keyframes[0]'s (0), got 0"},
      {"/keyframes/0/time", -1.0, "keyframes[0].time", "expected a finite time >= 0, got -1"},
      {"/keyframes/0/time", "soon", "keyframes[0].time", "expected a number"},
      {"/keyframes/0/translation", json::array({1e300, 0, 0}), "keyframes[0].translation", "|value| <= 1e+06"},
      {"/keyframes/0/translation", json::array({0, 0}), "keyframes[0].translation", ""},
      {"/keyframes/0/rotation", json::parse(R"({"axis": [0, 0, 0], "degrees": 30})"), "keyframes[0].rotation.axis",
       "expected a non-zero axis"},
      {"/keyframes/0/rotation", json::parse(R"({"degrees": 30})"), "keyframes[0].rotation.axis", "missing"},
      {"/keyframes/0/spin", 1, "keyframes[0].spin", "unknown field (expected one of: time, translation, rotation)"},
      {"/keyframes/0", json::parse(R"({"translation": [0, 0, 1]})"), "keyframes[0].time", "missing"},
      {"/keyframes/0", 3, "keyframes[0]", ""},
      {"/keyframes", json::array(), "keyframes", "expected at least one keyframe"},
      {"/keyframes", json::parse(R"({"time": 0})"), "keyframes", ""},
      {"/velocity", json::array({0, 0, 1}), "velocity", "either \"keyframes\" or a constant velocity"},
      {"/angular_velocity", json::array({0, 0, 1}), "angular_velocity", "not both"},
      {"/start", 0.0, "start", "not both"},
      {"/stop", 1.0, "stop", "not both"},
      {"/interpolation", "cubic", "interpolation", "expected one of \"linear\", \"smooth\", got \"cubic\""},
  };
  for (const char* owner : {"/obstacles/0/motion", "/effects/2/groups/0/motion"}) {
    const std::string at =
        std::string(owner) == "/obstacles/0/motion" ? "obstacles[0].motion." : "effects[2].groups[0].motion.";
    for (const auto& c : cases) {
      json j = base;
      j[json::json_pointer(owner + std::string(c.pointer))] = c.value;
      std::string msg;
      EXPECT_EQ(error_path(j, &msg), at + c.path) << owner << c.pointer << " = " << c.value.dump() << ": " << msg;
      EXPECT_NE(msg.find(c.message), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
    // An interpolation without keyframes.
    json j = base;
    j[json::json_pointer(owner)] = json::parse(R"({"velocity": [0, 0, 1], "interpolation": "linear"})");
    std::string msg;
    EXPECT_EQ(error_path(j, &msg), at + "interpolation") << msg;
  }
}

TEST(Scene, InlineMeshesLoadAsTheirFileAndEveryBadElementNamesItsPath) {
  // A cloth square, a strand and a tetrahedron written inline load as the same OBJ and .tet
  // files do, bit for bit; every bad element is one error naming its JSON path.
  write(std::filesystem::path(PCE_TEST_TMP) / "inline_square.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0.5\nf 1 2 3\nf 1 3 4\nl 3 4\n");
  write(std::filesystem::path(PCE_TEST_TMP) / "inline_tet.tet", "v 0 0 2\nv 1 0 2\nv 0 1 2\nv 0 0 3\nt 1 2 3 4\n");
  json from_files = minimal(), inline_scene = minimal();
  from_files["meshes"] = json::parse(R"([{"name": "square", "file": "inline_square.obj"},
      {"name": "tet", "file": "inline_tet.tet", "transform": {"translation": [0, 0, 0.25]}}])");
  inline_scene["meshes"] = json::parse(R"([
      {"name": "square", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.5]],
       "triangles": [[0, 1, 2], [0, 2, 3]], "segments": [[2, 3]]},
      {"name": "tet", "vertices": [[0, 0, 2], [1, 0, 2], [0, 1, 2], [0, 0, 3]], "tetrahedra": [[0, 1, 2, 3]],
       "transform": {"translation": [0, 0, 0.25]}}])");
  const auto a = load_scene_text(from_files.dump(), "scene.json", PCE_TEST_TMP);
  const auto b = load_scene_text(inline_scene.dump(), "scene.json", PCE_TEST_TMP);
  EXPECT_EQ(a->simulation.model.rest, b->simulation.model.rest);
  EXPECT_EQ(a->simulation.model.triangles, b->simulation.model.triangles);
  EXPECT_EQ(a->simulation.model.segments, b->simulation.model.segments);
  EXPECT_EQ(a->simulation.model.tetrahedra, b->simulation.model.tetrahedra);
  EXPECT_EQ(a->simulation.model.mass, b->simulation.model.mass);
  EXPECT_EQ(b->simulation.model.tetrahedra.cols(), 1);
  EXPECT_EQ(b->simulation.model.triangles.cols(), 2 + 4);  // the square's and the tetrahedron's faces

  const struct {
    const char* pointer;  // JSON pointer of the field to set, below meshes[1]
    json value;
    const char* path;     // the error's JSON path
    const char* message;  // a part of the error's message
  } cases[] = {
      {"/vertices/2/1", 2e7, "meshes[1].vertices[2][1]",
       "expected a number in [-1e+06, 1e+06] (the coordinates pce::sim accepts, in m), got 20000000"},
      {"/vertices/2/1", "x", "meshes[1].vertices[2][1]", "got \"x\""},
      {"/vertices/2/1", nullptr, "meshes[1].vertices[2][1]", "got null"},
      {"/vertices/2", json::array({0, 1}), "meshes[1].vertices[2]", "expected a vertex: an array of 3 numbers"},
      {"/vertices", json::array(), "meshes[1].vertices", "expected at least one vertex"},
      {"/vertices", 3, "meshes[1].vertices", "expected an array, got a number"},
      {"/tetrahedra/0/2", 12, "meshes[1].tetrahedra[0][2]", "expected a vertex index in [0, 4), got 12"},
      {"/tetrahedra/0/2", -1, "meshes[1].tetrahedra[0][2]", "expected a vertex index in [0, 4), got -1"},
      {"/tetrahedra/0/2", 18446744073709551615u, "meshes[1].tetrahedra[0][2]", "got 18446744073709551615"},
      {"/tetrahedra/0/2", 2.5, "meshes[1].tetrahedra[0][2]", "expected a vertex index (an integer) in [0, 4), got 2.5"},
      {"/tetrahedra/0/2", 1, "meshes[1].tetrahedra[0]", "the tetrahedron uses vertex 1 twice"},
      {"/tetrahedra/0", json::array({0, 1, 2}), "meshes[1].tetrahedra[0]", "expected a tetrahedron: an array of 4"},
      {"/tetrahedra/0", json::array({0, 2, 1, 3}), "meshes[1].tetrahedra",
       "tetrahedron 0 (vertices 0, 2, 1, 3) has signed volume -0.16666666666666666: it is inverted"},
      {"/vertices/3", json::array({0.5, 0.5, 2}), "meshes[1].tetrahedra", "it is flat"},
      {"/triangles", json::parse("[[0, 1, 2]]"), "meshes[1].triangles", "a mesh with \"tetrahedra\" is a volume"},
      {"/segments", json::parse("[[0, 1]]"), "meshes[1].segments", "leave \"segments\" out"},
      {"/tetrahedra", json::array(), "meshes[1].vertices",
       "expected \"triangles\", \"segments\" or \"tetrahedra\" with the vertices"},
      {"/file", "inline_tet.tet", "meshes[1].vertices",
       "expected exactly one of \"file\", \"generator\" or \"vertices\""},
      {"/transform/translation", json::array({0, 0, 1e6}), "meshes[1].vertices", "beyond |coordinate| <= 1e+06"},
  };
  for (const auto& c : cases) {
    json j = inline_scene;
    j[json::json_pointer("/meshes/1" + std::string(c.pointer))] = c.value;
    std::string msg;
    EXPECT_EQ(error_path(j, &msg), c.path) << c.pointer << " = " << c.value.dump() << ": " << msg;
    EXPECT_NE(msg.find(c.message), std::string::npos) << msg;
  }
  // Elements without vertices, and no source at all.
  json j = inline_scene;
  j["meshes"][0].erase("vertices");
  std::string msg;
  EXPECT_EQ(error_path(j, &msg), "meshes[0].file") << msg;
  j["meshes"][0]["generator"] = json::parse(R"({"type": "grid", "width": 1, "height": 1, "nx": 1, "ny": 1})");
  EXPECT_EQ(error_path(j, &msg), "meshes[0].triangles") << msg;
  EXPECT_NE(msg.find("the elements of a mesh given by its \"vertices\""), std::string::npos) << msg;
  // The triangle of an inline cloth that repeats a vertex, and one out of range.
  j = inline_scene;
  j["meshes"][0]["triangles"][1] = json::array({0, 3, 3});
  EXPECT_EQ(error_path(j, &msg), "meshes[0].triangles[1]") << msg;
  j["meshes"][0]["triangles"][1] = json::array({0, 3, 12});
  EXPECT_EQ(error_path(j, &msg), "meshes[0].triangles[1][2]") << msg;
  EXPECT_NE(msg.find("scene.json: meshes[0].triangles[1][2]: expected a vertex index in [0, 4), got 12"),
            std::string::npos)
      << msg;
  j["meshes"][0]["segments"] = json::parse("[[0, 1, 2]]");
  j["meshes"][0]["triangles"][1] = json::array({0, 2, 3});
  EXPECT_EQ(error_path(j, &msg), "meshes[0].segments[0]") << msg;
}

TEST(Scene, ShippedScenesLoad) {
  const std::filesystem::path dir = std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(load_scene(entry.path()));
    ++count;
  }
  EXPECT_GE(count, 1);
}
