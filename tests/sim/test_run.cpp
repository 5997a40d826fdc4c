// SPDX-License-Identifier: MIT
// pce::sim::Run (run.hpp): the records of a run and the files it writes while open; the
// start-state check as pce-sim makes it; the physics key of the checkpoints' fingerprint.
#include <pce/sim/checkpoint.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/run.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

using namespace pce::sim;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

/// Two 6 × 6 sheets, the upper one turned by `degrees` about x and raised by `z`; every
/// second frame's mesh is written.
json two_sheets(double degrees, double z) {
  json j = json::parse(R"({
    "dt": 0.01, "frames": 5, "output_every": 2,
    "meshes": [
      {"name": "lower", "generator": {"type": "grid", "width": 0.4, "height": 0.4, "nx": 6, "ny": 6}},
      {"name": "upper", "generator": {"type": "grid", "width": 0.4, "height": 0.4, "nx": 6, "ny": 6}}
    ],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 20},
      {"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 1, "distance": 0.01}}]
  })");
  j["meshes"][1]["transform"] = {{"rotation", {{"axis", {1, 0, 0}}, {"degrees", degrees}}},
                                 {"translation", {0.013, 0.007, z}}};
  return j;
}

std::unique_ptr<Scene> load(const json& j) { return load_scene_text(j.dump(), "run.json", PCE_TEST_TMP); }

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::path(PCE_TEST_TMP) / name;
  fs::remove_all(d);
  return d;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

TEST(Run, RecordsEveryFrameWithoutWritingUntilOpened) {
  auto scene = load(two_sheets(0, 0.1));
  pce::sim::Run run(*scene, "run.json");
  EXPECT_FALSE(run.is_open());
  const FrameReport r = run.step();
  const json record = json::parse(r.record);
  EXPECT_EQ(record["frame"], 1);
  EXPECT_EQ(record["newton_iterations"], r.stats.newton_iterations);
  EXPECT_EQ(record["stop"], to_string(r.stats.stop));
  EXPECT_EQ(record["friction_load"], r.stats.friction_load);
  EXPECT_EQ(record["friction_residual"], r.stats.friction_residual);
  ASSERT_EQ(record["iterations"].size(), r.stats.iterations.size());
  EXPECT_EQ(record["iterations"][0]["friction_load"], r.stats.iterations[0].friction_load);
  EXPECT_EQ(record["iterations"][0]["friction_residual"], r.stats.iterations[0].friction_residual);
  EXPECT_EQ(record["intersecting_triangle_pairs"], 0);
  EXPECT_EQ(record["new_intersections"], 0);
  EXPECT_EQ(scene->simulation.frame, 1);
  run.close();  // nothing open: nothing to do
}

TEST(Run, WritesWhatPceSimWrites) {
  auto scene = load(two_sheets(0, 0.1));
  const fs::path dir = fresh_dir("run_files");
  pce::sim::Run run(*scene, "run.json");
  RunOutput out;
  out.dir = dir;
  out.checkpoint_every = 2;
  run.open(out);
  EXPECT_TRUE(run.is_open());
  EXPECT_EQ(run.dir(), dir);
  EXPECT_THROW(run.open(out), std::logic_error);
  for (int f = 0; f < 3; ++f) run.step();
  // stats.jsonl grows as frames end.
  std::ifstream jsonl(dir / "stats.jsonl");
  int lines = 0;
  for (std::string line; std::getline(jsonl, line);) EXPECT_EQ(json::parse(line)["frame"], ++lines);
  EXPECT_EQ(lines, 3);
  run.close("", nullptr);
  EXPECT_FALSE(run.is_open());
  for (const char* f : {"frame_0000.obj", "frame_0002.obj", "frame_0003.obj", "checkpoint_0002.pcecp", "last_frame.png",
                        "stats.json", "summary.json"})
    EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
  EXPECT_FALSE(fs::exists(dir / "frame_0001.obj"));  // output_every = 2; the last frame always
  const json summary = json::parse(read(dir / "summary.json"));
  EXPECT_EQ(summary["frames_done"], 3);
  EXPECT_TRUE(summary["failure"].is_null() && summary["stopped_by"].is_null());
  EXPECT_EQ(json::parse(read(dir / "stats.json")).size(), 3u);
}

TEST(Run, AStopWritesACheckpointAndNamesTheSignal) {
  auto scene = load(two_sheets(0, 0.1));
  const fs::path dir = fresh_dir("run_stop");
  pce::sim::Run run(*scene, "run.json");
  RunOutput out;
  out.dir = dir;
  out.write_frames = false;
  run.open(out);
  run.step();
  run.close("run.json: something failed", "SIGINT");
  EXPECT_TRUE(fs::is_regular_file(dir / "checkpoint_0001.pcecp"));
  EXPECT_TRUE(fs::is_regular_file(dir / "frame_0001.obj"));  // the last frame, even without frames
  EXPECT_FALSE(fs::exists(dir / "frame_0000.obj"));
  const json summary = json::parse(read(dir / "summary.json"));
  EXPECT_EQ(summary["stopped_by"], "SIGINT");
  EXPECT_EQ(summary["failure"], "run.json: something failed");
}

TEST(Run, StartStateRefusalsAreOneInputErrorNamingTheFile) {
  auto crossing = load(two_sheets(90, 0.0));
  try {
    accept_start_state(*crossing, "crossing.json");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("crossing.json: ", 0), 0u) << what;
    EXPECT_NE(what.find("\"lower\" and \"upper\""), std::string::npos) << what;
    EXPECT_NE(what.find("allow_initial_intersections"), std::string::npos) << what;
  }
  json allowed = two_sheets(90, 0.0);
  allowed["allow_initial_intersections"] = true;
  auto scene = load(allowed);
  const std::vector<std::string> warnings = accept_start_state(*scene, "allowed.json");
  ASSERT_FALSE(warnings.empty());
  EXPECT_EQ(warnings[0].rfind("allowed.json: ", 0), 0u);
  EXPECT_NE(warnings[0].find("(allowed by allow_initial_intersections)"), std::string::npos);
  EXPECT_TRUE(accept_start_state(*load(two_sheets(0, 0.1)), "clean.json").empty());
}

TEST(Run, PhysicsKeyHoldsTheOverridesThatChangeThePhysicsOnly) {
  const fs::path file = fs::path(PCE_TEST_TMP) / "physics_key.json";
  std::ofstream(file) << two_sheets(0, 0.1).dump();
  const std::string plain = physics_key(file, {});
  EXPECT_EQ(plain, two_sheets(0, 0.1).dump());
  SceneOverrides o;
  o.frames = 9;
  o.threads = 2;
  o.single_solve = false;  // the default: no override, the same key
  EXPECT_EQ(physics_key(file, o), plain);
  o.single_solve = true;
  EXPECT_EQ(physics_key(file, o), plain + "\n--single-solve");
  SceneOverrides h;
  h.hessian = pce::Projection::exact;
  EXPECT_EQ(physics_key(file, h), plain + "\n--hessian exact");
}
