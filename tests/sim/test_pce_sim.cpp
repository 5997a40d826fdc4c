// SPDX-License-Identifier: MIT
// pce-sim end to end: every shipped scene's short variant runs in Newton and single-solve
// mode with finite statistics; stats.json lists exactly the declared effects; invalid input
// exits with code 2, one line naming file and field, and writes nothing.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const fs::path kScenes = fs::path(PCE_SOURCE_DIR) / "examples" / "scenes";

/// Runs pce-sim with `args`; returns the exit code and the captured stderr.
int run(const std::string& args, std::string* err = nullptr) {
  const fs::path log = fs::path(PCE_TEST_TMP) / "pce_sim_stderr.txt";
  const std::string cmd = std::string(PCE_SIM_EXE) + " " + args + " 2> " + log.string() + " > /dev/null";
  const int status = std::system(cmd.c_str());
  if (err) {
    std::ifstream in(log);
    std::stringstream s;
    s << in.rdbuf();
    *err = s.str();
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

}  // namespace

class ShippedScene : public ::testing::TestWithParam<std::tuple<std::string, bool>> {};

TEST_P(ShippedScene, ShortVariantRunsWithFiniteStats) {
  const auto [name, single] = GetParam();
  const fs::path out = fs::path(PCE_TEST_TMP) / ("run_" + name + (single ? "_single" : "_newton"));
  fs::remove_all(out);
  std::string err;
  const std::string args =
      (kScenes / (name + ".json")).string() + " --frames 3 --out " + out.string() + (single ? " --single-solve" : "");
  ASSERT_EQ(run(args, &err), 0) << err;
  const json stats = read_json(out / "stats.json");
  ASSERT_EQ(stats.size(), 3u);
  const json scene = read_json(kScenes / (name + ".json"));
  std::set<std::string> declared;
  for (const auto& e : scene["effects"]) declared.insert(e["type"].get<std::string>());
  for (const auto& r : stats) {
    for (const char* key : {"frame", "wall_ms", "newton_iterations", "residual", "energy", "broad_phase_ms",
                            "assembly_ms", "solve_ms", "intersecting_triangle_pairs", "contacts", "effects"})
      EXPECT_TRUE(r.contains(key)) << key;
    EXPECT_TRUE(r["energy"].is_number() && std::isfinite(r["energy"].get<double>()));
    if (single) {
      EXPECT_EQ(r["newton_iterations"].get<int>(), 1);
    }
    std::set<std::string> evaluated;
    for (auto it = r["effects"].begin(); it != r["effects"].end(); ++it) {
      evaluated.insert(it.key());
      EXPECT_GE(it.value().get<double>(), 0.0);
    }
    EXPECT_EQ(evaluated, declared);  // exactly the declared effects, each timed
  }
  EXPECT_TRUE(fs::exists(out / "last_frame.png"));
  EXPECT_TRUE(fs::exists(out / "frame_0003.obj"));
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

INSTANTIATE_TEST_SUITE_P(Scenes, ShippedScene,
                         ::testing::Combine(::testing::Values("hammock", "drape", "strands", "twist"),
                                            ::testing::Bool()),
                         [](const auto& info) {
                           return std::get<0>(info.param) + (std::get<1>(info.param) ? "_single" : "_newton");
                         });

TEST(PceSim, InvalidSceneExitsWithCodeTwoAndWritesNothing) {
  const fs::path scene = fs::path(PCE_TEST_TMP) / "bad_scene.json";
  std::ofstream(scene) << R"({"dt": 0.01, "frames": 2,
    "meshes": [{"name": "c", "generator": {"type": "grid", "width": 1, "height": 1, "nx": 2, "ny": 2}}],
    "effects": [{"type": "gravity", "acceleration": [0, 0, "down"]}]})";
  const fs::path out = fs::path(PCE_TEST_TMP) / "bad_out";
  fs::remove_all(out);
  std::string err;
  EXPECT_EQ(run(scene.string() + " --out " + out.string(), &err), 2);
  EXPECT_NE(err.find("bad_scene.json: effects[0].acceleration:"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(PceSim, MissingSceneFile) {
  std::string err;
  EXPECT_EQ(run((fs::path(PCE_TEST_TMP) / "no_such_scene.json").string(), &err), 2);
  EXPECT_NE(err.find("no_such_scene.json: cannot open"), std::string::npos) << err;
}
