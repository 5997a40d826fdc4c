// SPDX-License-Identifier: MIT
// Start-state validation: intersecting meshes (within one, between two, against a mesh
// obstacle) and vertices inside a shape obstacle are refused with the meshes named and
// counted; contact already active at the start is a warning; a clean start has neither;
// the check leaves the simulation's state and its first step unchanged.
#include <pce/sim/scene.hpp>
#include <pce/sim/start_state.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

using namespace pce::sim;
using nlohmann::json;

namespace {

/// Two 8 × 8 sheets, "lower" at z = 0 and "upper" turned by `degrees` about x and raised by `z`.
json two_sheets(double degrees, double z) {
  json j = json::parse(R"({
    "dt": 0.01, "frames": 2,
    "meshes": [
      {"name": "lower", "generator": {"type": "grid", "width": 0.4, "height": 0.4, "nx": 8, "ny": 8}},
      {"name": "upper", "generator": {"type": "grid", "width": 0.4, "height": 0.4, "nx": 8, "ny": 8}}
    ],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 20},
      {"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 1, "distance": 0.01}},
      {"type": "self_edge_edge", "penalty": {"type": "quadratic", "stiffness": 1, "distance": 0.01}}]
  })");
  j["meshes"][1]["transform"] = {{"rotation", {{"axis", {1, 0, 0}}, {"degrees", degrees}}},
                                 {"translation", {0.013, 0.007, z}}};
  return j;
}

std::unique_ptr<Scene> load(const json& j) { return load_scene_text(j.dump(), "start.json", PCE_TEST_TMP); }

bool mentions(const std::vector<std::string>& lines, const std::string& text) {
  for (const auto& l : lines)
    if (l.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(StartState, CleanStartHasNothingToSay) {
  auto s = load(two_sheets(0, 0.1));
  const StartStateReport r = check_start_state(s->simulation);
  EXPECT_TRUE(r.refusals.empty());
  EXPECT_TRUE(r.warnings.empty());
  // every shipped scene (examples/scenes/*.json)
  int shipped_scenes = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    auto shipped = load_scene(entry.path());
    const StartStateReport q = check_start_state(shipped->simulation);
    EXPECT_TRUE(q.refusals.empty() && q.warnings.empty()) << entry.path().filename();
    ++shipped_scenes;
  }
  EXPECT_GE(shipped_scenes, 9);
}

TEST(StartState, SheetsThroughEachOtherAreRefusedWithTheMeshesNamed) {
  auto s = load(two_sheets(90, 0));  // the upper sheet stands upright through the lower one
  const StartStateReport r = check_start_state(s->simulation);
  ASSERT_EQ(r.refusals.size(), 1u);
  EXPECT_NE(r.refusals[0].find("intersecting triangle pairs between meshes \"lower\" and \"upper\""), std::string::npos)
      << r.refusals[0];
  EXPECT_EQ(r.refusals[0].find("the start state has 0 "), std::string::npos) << r.refusals[0];
  EXPECT_TRUE(mentions(r.warnings, "pairs are within the contact distance at the start"));
}

TEST(StartState, AFoldedMeshIsRefusedWithinItself) {
  // One sheet folded flat onto itself through a second copy of its half: an OBJ whose two
  // layers cross.
  const std::filesystem::path obj = std::filesystem::path(PCE_TEST_TMP) / "crossing_layers.obj";
  std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0.2 0.2 -0.5\nv 0.3 0.2 0.5\nv 0.2 0.3 0.5\nf 1 2 3\nf 4 5 6\n";
  json j = json::parse(R"({"dt": 0.01, "frames": 1, "meshes": [{"name": "layers", "file": "crossing_layers.obj"}],
                          "effects": [{"type": "gravity"}]})");
  auto s = load(j);
  const StartStateReport r = check_start_state(s->simulation);
  ASSERT_EQ(r.refusals.size(), 1u);
  EXPECT_NE(r.refusals[0].find("the start state has 1 intersecting triangle pairs within mesh \"layers\""),
            std::string::npos)
      << r.refusals[0];
}

TEST(StartState, VerticesInsideAShapeOrThroughAMeshObstacleAreRefused) {
  json j = two_sheets(0, 0.5);
  j["obstacles"] = json::parse(R"([{"name": "ball", "shape": "sphere", "radius": 0.05, "position": [0, 0, 0]}])");
  j["effects"].push_back(json::parse(
      R"({"type": "obstacle_contact", "penalty": {"type": "quadratic", "stiffness": 10, "distance": 0.01}})"));
  StartStateReport r = check_start_state(load(j)->simulation);
  ASSERT_EQ(r.refusals.size(), 1u);
  EXPECT_NE(r.refusals[0].find("vertices of mesh \"lower\" inside obstacle \"ball\""), std::string::npos)
      << r.refusals[0];
  // Without obstacle contact the obstacle is only drawn: nothing to refuse.
  j["effects"].erase(j["effects"].size() - 1);
  EXPECT_TRUE(check_start_state(load(j)->simulation).refusals.empty());
  // A mesh obstacle crossing the upper sheet.
  const std::filesystem::path obj = std::filesystem::path(PCE_TEST_TMP) / "blade.obj";
  std::ofstream(obj) << "v -0.5 0 0.3\nv 0.5 0 0.3\nv 0 0 0.7\nf 1 2 3\n";
  j["obstacles"] = json::parse(R"([{"name": "blade", "shape": "mesh", "file": "blade.obj"}])");
  j["effects"].push_back(json::parse(
      R"({"type": "obstacle_contact", "penalty": {"type": "quadratic", "stiffness": 10, "distance": 0.01}})"));
  r = check_start_state(load(j)->simulation);
  ASSERT_EQ(r.refusals.size(), 1u);
  EXPECT_NE(r.refusals[0].find("triangles of mesh \"upper\" intersecting obstacle \"blade\""), std::string::npos)
      << r.refusals[0];
}

TEST(StartState, TheCheckChangesNeitherTheStateNorTheFirstStep) {
  const json j = two_sheets(0, 0.006);  // within the contact distance: contact acts in step 1
  auto checked = load(j), plain = load(j);
  const StartStateReport r = check_start_state(checked->simulation);
  EXPECT_TRUE(r.refusals.empty());
  EXPECT_TRUE(mentions(r.warnings, "effect \"self_vertex_face\""));
  EXPECT_EQ(checked->simulation.frame, 0);
  for (int f = 0; f < 2; ++f) {
    checked->simulation.step();
    plain->simulation.step();
  }
  EXPECT_TRUE((checked->simulation.x.array() == plain->simulation.x.array()).all());
}
