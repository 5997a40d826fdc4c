// SPDX-License-Identifier: MIT
// pce-sim end to end: every shipped scene's short variant runs in Newton and single-solve
// mode with finite statistics; stats.json lists exactly the declared effects; invalid input
// exits with code 2, one line naming file and field, and writes nothing. Run control:
// stats.jsonl holds every completed frame, SIGINT and SIGTERM end a run after the current
// frame with everything written, SIGKILL loses no completed frame, a resumed run ends bit for
// bit where the uninterrupted one ends, and a checkpoint of another scene is refused. The
// movie and the USD cache: --usd holds every output frame as its OBJ has it (also with
// --no-frames, after a stop signal, and from a resumed run's checkpoint on); --video
// without ffmpeg exits 2 before anything is written, and with it the movie has one frame
// per output frame.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <pce/sim/movie.hpp>
#include <pce/sim/obj.hpp>
#include <pce/sim/obstacle.hpp>
#include <pce/sim/scene.hpp>

#include "ffprobe.hpp"
#include "usda_reader.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <chrono>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <thread>
#include <vector>
#include <sstream>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const fs::path kScenes = fs::path(PCE_SOURCE_DIR) / "examples" / "scenes";

/// Runs pce-sim with `args`; returns the exit code and the captured stderr. The capture
/// file is this process's own: ctest runs the tests of this file as separate processes in
/// parallel, and one file for all of them let a test read another's output.
/// `environment` (e.g. "PATH=/x") is put before the command.
int run(const std::string& args, std::string* err = nullptr, const std::string& environment = "") {
  static int calls = 0;
  const fs::path log =
      fs::path(PCE_TEST_TMP) / ("pce_sim_stderr_" + std::to_string(getpid()) + "_" + std::to_string(calls++) + ".txt");
  const std::string cmd =
      environment + " " + std::string(PCE_SIM_EXE) + " " + args + " 2> " + log.string() + " > /dev/null";
  const int status = std::system(cmd.c_str());
  if (err) {
    std::ifstream in(log);
    std::stringstream s;
    s << in.rdbuf();
    *err = s.str();
  }
  fs::remove(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

json read_json(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

/// Starts pce-sim with `args` (stderr into `err_file`) and returns its pid.
pid_t spawn(const std::vector<std::string>& args, const fs::path& err_file) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 2);
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    std::vector<char*> argv{const_cast<char*>(PCE_SIM_EXE)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(PCE_SIM_EXE, argv.data());
    _exit(127);
  }
  return pid;
}

/// Complete lines in `file` (0 while it does not exist).
long lines_in(const fs::path& file) {
  std::ifstream in(file);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return static_cast<long>(std::count(text.begin(), text.end(), '\n'));
}

/// Waits (at most ~120 s) until `file` has `count` lines; false on time-out or if the
/// process ended first.
bool wait_for_lines(pid_t pid, const fs::path& file, long count) {
  for (int i = 0; i < 12000; ++i) {
    if (lines_in(file) >= count) return true;
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

std::vector<json> read_jsonl(const fs::path& p) {
  std::vector<json> records;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) records.push_back(json::parse(line));
  return records;
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// A record without its timings (wall-clock numbers differ between runs) and without the
/// count of symbolic analyses (a resumed run's solver starts without one).
json physics_of(json r) {
  for (const char* key :
       {"wall_ms", "broad_phase_ms", "pair_ms", "assembly_ms", "solve_ms", "line_search_ms", "effects"})
    r.erase(key);
  json counters = json::object();
  for (auto it = r["counters"].begin(); it != r["counters"].end(); ++it)
    if (it.key().find("_ms") == std::string::npos && it.key() != "analyses") counters[it.key()] = it.value();
  r["counters"] = counters;
  return r;
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

/// Every shipped scene (examples/scenes/*.json), by name, sorted; drop_130k (130 321
/// vertices) runs reduced in BlockDescent.TheLargeShippedSceneRunsReduced instead.
std::vector<std::string> shipped_scenes() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(kScenes))
    if (entry.path().extension() == ".json" && entry.path().stem() != "drop_130k")
      names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

INSTANTIATE_TEST_SUITE_P(Scenes, ShippedScene,
                         ::testing::Combine(::testing::ValuesIn(shipped_scenes()), ::testing::Bool()),
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

TEST(PceSim, StatsJsonlHoldsEveryFrameAsStatsJsonDoes) {
  const fs::path out = fs::path(PCE_TEST_TMP) / "jsonl_twist";
  fs::remove_all(out);
  std::string err;
  ASSERT_EQ(run((kScenes / "twist.json").string() + " --frames 3 --out " + out.string(), &err), 0) << err;
  const json stats = read_json(out / "stats.json");
  const std::vector<json> lines = read_jsonl(out / "stats.jsonl");
  ASSERT_EQ(lines.size(), 3u);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    EXPECT_EQ(lines[k], stats[k]);
    EXPECT_EQ(lines[k]["new_intersections"].get<long>(), 0);
  }
}

/// A run of the twist scene long enough to be stopped: 200 frames, every frame written.
std::vector<std::string> long_twist(const fs::path& out) {
  return {(kScenes / "twist.json").string(), "--frames", "200", "--out", out.string(), "--threads", "1"};
}

/// Runs the long twist into `out`, sends `signal_number` once `records` frames are done and
/// returns the wait status (−1 if the run ended before that or did not reach it in time).
int signal_after(const fs::path& out, long records, int signal_number) {
  fs::remove_all(out);
  const pid_t pid = spawn(long_twist(out), out.string() + ".err");
  if (!wait_for_lines(pid, out / "stats.jsonl", records)) return -1;
  kill(pid, signal_number);
  int status = 0;
  return waitpid(pid, &status, 0) == pid ? status : -1;
}

class StopSignal : public ::testing::TestWithParam<int> {};

TEST_P(StopSignal, EndsAfterTheCurrentFrameWithEverythingWritten) {
  const int signal_number = GetParam();
  const fs::path out = fs::path(PCE_TEST_TMP) / ("stopped_" + std::to_string(signal_number));
  const int status = signal_after(out, 2, signal_number);
  ASSERT_NE(status, -1);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + signal_number);
  const json summary = read_json(out / "summary.json");
  const int done = summary["frames_done"].get<int>();
  EXPECT_GE(done, 2);
  EXPECT_LT(done, 200);
  EXPECT_EQ(summary["stopped_by"], signal_number == SIGINT ? "SIGINT" : "SIGTERM");
  const json stats = read_json(out / "stats.json");
  const std::vector<json> lines = read_jsonl(out / "stats.jsonl");
  ASSERT_EQ(stats.size(), static_cast<std::size_t>(done));
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(done));
  for (int f = 1; f <= done; ++f) EXPECT_EQ(lines[static_cast<std::size_t>(f - 1)]["frame"].get<int>(), f);
  char obj[32];
  std::snprintf(obj, sizeof obj, "frame_%04d.obj", done);
  EXPECT_TRUE(fs::exists(out / obj)) << obj;  // the last frame, whatever output_every says
  EXPECT_TRUE(fs::exists(out / "last_frame.png"));
  char name[40];
  std::snprintf(name, sizeof name, "checkpoint_%04d.pcecp", done);
  EXPECT_TRUE(fs::exists(out / name));
}

INSTANTIATE_TEST_SUITE_P(Signals, StopSignal, ::testing::Values(SIGINT, SIGTERM),
                         [](const auto& info) { return info.param == SIGINT ? "SIGINT" : "SIGTERM"; });

TEST(PceSim, KilledRunKeepsEveryCompletedFrame) {
  const fs::path out = fs::path(PCE_TEST_TMP) / "killed";
  const int status = signal_after(out, 3, SIGKILL);
  ASSERT_NE(status, -1);
  ASSERT_TRUE(WIFSIGNALED(status));
  const long complete = lines_in(out / "stats.jsonl");  // a record is complete once its newline is written
  ASSERT_GE(complete, 3);
  const std::vector<json> lines = read_jsonl(out / "stats.jsonl");
  const long every = read_json(kScenes / "twist.json")["output_every"].get<long>();
  for (long f = 1; f <= complete; ++f) {
    EXPECT_EQ(lines[static_cast<std::size_t>(f - 1)]["frame"].get<long>(), f);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04ld.obj", f);
    if (f % every == 0) {
      EXPECT_TRUE(fs::exists(out / name)) << name;
    }
  }
}

/// Runs `scene` to frame `frames` whole, and again interrupted at `stop` and resumed (from
/// its last checkpoint, every 5 frames, at `resumed_at`); the resumed run ends bit for bit
/// where the whole one does (the last checkpoint, every stats record without timings).
/// Returns the whole run's stats records (empty after a failure).
std::vector<json> resume_matches(const fs::path& scene, const std::string& tag, int frames, int stop, int resumed_at) {
  const fs::path whole = fs::path(PCE_TEST_TMP) / (tag + "_whole"), parts = fs::path(PCE_TEST_TMP) / (tag + "_parts");
  fs::remove_all(whole);
  fs::remove_all(parts);
  std::string err;
  const std::string common = scene.string() + " --no-frames --checkpoint-every 5 --out ";
  EXPECT_EQ(run(common + whole.string() + " --frames " + std::to_string(frames), &err), 0) << err;
  EXPECT_EQ(run(common + parts.string() + " --frames " + std::to_string(stop), &err), 0) << err;
  EXPECT_EQ(run(scene.string() + " --no-frames --checkpoint-every 5 --frames " + std::to_string(frames) + " --resume " +
                    parts.string(),
                &err),
            0)
      << err;
  EXPECT_NE(err.find("resumed at frame " + std::to_string(resumed_at)), std::string::npos) << err;
  char last[32];
  std::snprintf(last, sizeof last, "checkpoint_%04d.pcecp", frames);
  EXPECT_EQ(read_text(whole / last), read_text(parts / last));
  const std::vector<json> a = read_jsonl(whole / "stats.jsonl"), b = read_jsonl(parts / "stats.jsonl");
  EXPECT_EQ(a.size(), static_cast<std::size_t>(frames));
  EXPECT_EQ(b.size(), static_cast<std::size_t>(frames));
  if (a.size() != b.size() || a.size() != static_cast<std::size_t>(frames)) return {};
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(physics_of(a[k]), physics_of(b[k])) << "frame " << k + 1;
  return a;
}

TEST(PceSim, ResumedRunKeepsTheStiffeningOfHeldPairs) {
  // tests/sim/scenes/press.json: vertices held at the box's floor from frame 15 on, plate
  // and sheet pairs from frame 22, so the checkpoint of frame 30 carries the stiffening
  // factors of obstacle and self contact; the resumed run ends frame 35 bit for bit where
  // the uninterrupted one does (either factor left out of a checkpoint fails it).
  const std::vector<json> a =
      resume_matches(fs::path(PCE_SOURCE_DIR) / "tests" / "sim" / "scenes" / "press.json", "resume_press", 35, 32, 30);
  ASSERT_EQ(a.size(), 35u);
  EXPECT_GT(a[29]["counters"]["stiffened_pairs"].get<double>(), 0.0);  // the checkpoint carries factors
}

TEST(PceSim, ResumedRunEndsBitForBitWhereTheUninterruptedRunEnds) {
  // The crumpling drop: contact from frame 9, so the checkpoint of frame 10 carries tracked
  // pairs and declarations; the interrupted run went on to frame 13, whose records the
  // resume drops.
  const std::vector<json> a = resume_matches(kScenes / "crumple.json", "resume", 15, 13, 10);
  ASSERT_EQ(a.size(), 15u);
  EXPECT_EQ(read_text(fs::path(PCE_TEST_TMP) / "resume_whole" / "frame_0015.obj"),
            read_text(fs::path(PCE_TEST_TMP) / "resume_parts" / "frame_0015.obj"));
  long vertex_face = 0, edge_edge = 0;
  for (const auto& r : a) {
    vertex_face += r["contacts"]["vertex_face"].get<long>();
    edge_edge += r["contacts"]["edge_edge"].get<long>();
  }
  EXPECT_GT(vertex_face, 0);  // the comparison covers both kinds of self contact
  EXPECT_GT(edge_edge, 0);
}

TEST(PceSim, ResumedBlockDescentRunEndsBitForBitWhereTheUninterruptedRunEnds) {
  // crumple.json under block descent (2 substeps of 5 sweeps a frame): contact from frame 9;
  // the resume from the checkpoint of frame 10 ends frame 15 where the uninterrupted run does
  // (each step colours its vertices afresh, so nothing but the checkpoint carries over).
  json scene = read_json(kScenes / "crumple.json");
  scene["solver"]["mode"] = "block_descent";
  scene["solver"]["substeps"] = 2;
  scene["solver"]["iterations"] = 5;
  scene["solver"].erase("max_iterations");
  scene["solver"].erase("tolerance");
  const fs::path file = fs::path(PCE_TEST_TMP) / "crumple_block_descent.json";
  std::ofstream(file) << scene.dump();
  const std::vector<json> a = resume_matches(file, "resume_bd", 15, 13, 10);
  ASSERT_EQ(a.size(), 15u);
  long contacts = 0;
  for (const auto& r : a) contacts += r["contacts"]["vertex_face"].get<long>() + r["contacts"]["edge_edge"].get<long>();
  EXPECT_GT(contacts, 0);
  EXPECT_EQ(a.back()["stop"], "sweeps");
  EXPECT_EQ(a.back()["sweeps"], 10);
  EXPECT_EQ(a.back()["substeps"], 2);
  EXPECT_EQ(a.back()["newton_iterations"], 0);
}

/// Writes `scene` to PCE_TEST_TMP/`name`.json and returns the path.
fs::path write_scene(const json& scene, const std::string& name) {
  const fs::path file = fs::path(PCE_TEST_TMP) / (name + ".json");
  std::ofstream(file) << scene.dump();
  return file;
}

/// The counter `key` of the stats record `r`.
double counter(const json& r, const char* key) { return r["counters"][key].get<double>(); }

/// Two sheets on a box tilted by 20° about y: the lower one (`under` quads a side) starts
/// 1 mm above its contact distance and lands at once, the upper one (`over` quads a side)
/// starts 3 cm above it and lands on it around frame 7. Every contact has Coulomb friction
/// μ = 0.3, below tan 20° ≈ 0.36, so the lower sheet slides down the box under kinetic
/// friction; self vertex-face contact solves each step twice (`lagged_iterations` 2).
json slope_scene(int under, int over) {
  const double tilt = 20.0 * M_PI / 180.0;
  const auto along_normal = [&](double d) { return json::array({d * std::sin(tilt), 0.0, d * std::cos(tilt)}); };
  const json rotation = {{"axis", {0, 1, 0}}, {"degrees", 20}};
  const json friction = {{"coefficient", 0.3}};
  const json penalty = {{"type", "quadratic"}, {"stiffness", 20}, {"distance", 0.005}};
  json lagged = friction;
  lagged["lagged_iterations"] = 2;
  json over_at = along_normal(0.03);
  over_at[1] = 0.01;
  return {{"dt", 0.01},
          {"frames", 15},
          {"solver", {{"tolerance", 0.01}, {"max_iterations", 30}}},
          {"obstacles",
           {{{"name", "slope"},
             {"shape", "box"},
             {"half_extents", {0.3, 0.3, 0.05}},
             {"position", along_normal(-0.05)},
             {"rotation", rotation}}}},
          {"meshes",
           {{{"name", "under"},
             {"generator", {{"type", "grid"}, {"width", 0.2}, {"height", 0.2}, {"nx", under}, {"ny", under}}},
             {"transform", {{"rotation", rotation}, {"translation", along_normal(0.006)}}}},
            {{"name", "over"},
             {"generator", {{"type", "grid"}, {"width", 0.12}, {"height", 0.12}, {"nx", over}, {"ny", over}}},
             {"transform", {{"rotation", rotation}, {"translation", over_at}}}}}},
          {"effects",
           {{{"type", "gravity"}},
            {{"type", "stretching"}, {"stiffness", 20}},
            {{"type", "bending"}, {"stiffness", 1e-5}},
            {{"type", "obstacle_contact"}, {"penalty", penalty}, {"friction", friction}},
            {{"type", "self_vertex_face"}, {"penalty", penalty}, {"friction", lagged}},
            {{"type", "self_edge_edge"}, {"penalty", penalty}, {"friction", friction}}}}};
}

TEST(PceSim, ResumedRunWithFrictionEndsBitForBit) {
  // slope_scene: at the checkpoint of frame 10 (and in every frame after it) the upper sheet
  // lies on the lower one and the lower one slides on the box, every kind of contact frozen
  // with friction and counted; the resumed run ends frame 15 where the uninterrupted one
  // does. It fails if a step's friction depends on anything the checkpoint does not carry
  // (the frozen normal forces and bases are rebuilt from the saved xⁿ, the slip from xⁿ and
  // the saved vⁿ).
  const std::vector<json> a =
      resume_matches(write_scene(slope_scene(8, 6), "resume_friction"), "resume_friction", 15, 13, 10);
  ASSERT_EQ(a.size(), 15u);
  for (std::size_t k = 9; k < a.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k + 1));
    EXPECT_GT(counter(a[k], "vertex_face_friction_contacts"), 0.0);
    EXPECT_GT(counter(a[k], "edge_edge_friction_contacts"), 0.0);
    EXPECT_GT(counter(a[k], "obstacle_friction_contacts"), 0.0);
  }
  // the lower sheet slides at the checkpoint: not every frozen obstacle contact sticks
  EXPECT_LT(counter(a[9], "obstacle_friction_sticking"), counter(a[9], "obstacle_friction_contacts"));
}

TEST(PceSim, ResumedRunOfAVolumeEndsBitForBit) {
  // A block of 162 tetrahedra (volume_elasticity), turned by 30° so that a corner points
  // down 1.3 cm above a box, falls onto it from frame 4 on and is squashed and tipped by the
  // contact: at the checkpoint of frame 10 it touches the box with its volume below its
  // rest volume, and the set of touching vertices changes after it. The resumed run ends
  // frame 15 where the uninterrupted one does; it fails if anything the volume's step reads
  // is not in the checkpoint.
  const json scene = {
      {"dt", 0.01},
      {"frames", 15},
      {"solver", {{"tolerance", 0.01}, {"max_iterations", 30}}},
      {"obstacles",
       {{{"name", "floor"}, {"shape", "box"}, {"half_extents", {0.2, 0.2, 0.05}}, {"position", {0, 0, -0.05}}}}},
      {"meshes",
       {{{"name", "block"},
         {"generator", {{"type", "tet_box"}, {"size", {0.06, 0.06, 0.06}}, {"n", {3, 3, 3}}}},
         {"transform", {{"rotation", {{"axis", {1, 1, 0}}, {"degrees", 30}}}, {"translation", {0, 0, 0.06}}}},
         {"density", 500}}}},
      {"effects",
       {{{"type", "gravity"}},
        {{"type", "volume_elasticity"}, {"young_modulus", 5000}, {"poisson_ratio", 0.4}},
        {{"type", "damping"}, {"coefficient", 0.1}},
        {{"type", "obstacle_contact"}, {"penalty", {{"type", "quadratic"}, {"stiffness", 2000}, {"distance", 0.004}}}},
        {{"type", "self_vertex_face"}, {"penalty", {{"type", "quadratic"}, {"stiffness", 200}, {"distance", 0.004}}}},
        {{"type", "self_edge_edge"}, {"penalty", {{"type", "quadratic"}, {"stiffness", 200}, {"distance", 0.004}}}}}}};
  const std::vector<json> a = resume_matches(write_scene(scene, "resume_volume"), "resume_volume", 15, 13, 10);
  ASSERT_EQ(a.size(), 15u);
  EXPECT_GT(counter(a[9], "tetrahedra"), 0.0);
  EXPECT_GT(a[9]["contacts"]["obstacle"].get<long>(), 0);  // the volume touches the box at the checkpoint
  EXPECT_LT(counter(a[9], "volume_ratio"), 1.0);           // and is squashed
  std::set<long> touching;
  for (std::size_t k = 9; k < a.size(); ++k) touching.insert(a[k]["contacts"]["obstacle"].get<long>());
  EXPECT_GT(touching.size(), 1u);  // the contact changes after the checkpoint
}

namespace {

/// A 0.2 m sheet (9 × 9 vertices) lying on a 0.3 m box that moves by `table_motion`, with a
/// pin group along its edge x ≥ 0.09 whose targets move by `pin_motion` until it is released
/// at frame 12; friction on the box, vertex-face self contact; 15 frames of 10 ms.
json sheet_on_a_moving_box(const json& table_motion, const json& pin_motion) {
  const json penalty = {{"type", "quadratic"}, {"stiffness", 20}, {"distance", 0.005}};
  return {{"dt", 0.01},
          {"frames", 15},
          {"solver", {{"tolerance", 0.01}, {"max_iterations", 30}}},
          {"obstacles",
           {{{"name", "table"},
             {"shape", "box"},
             {"half_extents", {0.15, 0.15, 0.05}},
             {"position", {0, 0, -0.05}},
             {"motion", table_motion}}}},
          {"meshes",
           {{{"name", "cloth"},
             {"generator", {{"type", "grid"}, {"width", 0.2}, {"height", 0.2}, {"nx", 8}, {"ny", 8}}},
             {"transform", {{"translation", {0, 0, 0.006}}}}}}},
          {"effects",
           {{{"type", "gravity"}},
            {{"type", "stretching"}, {"stiffness", 20}},
            {{"type", "bending"}, {"stiffness", 1e-5}},
            {{"type", "pins"},
             {"stiffness", 100},
             {"groups",
              {{{"mesh", "cloth"},
                {"box", {{"min", {0.09, -1, -1}}, {"max", {1, 1, 1}}}},
                {"motion", pin_motion},
                {"release_frame", 12}}}}},
            {{"type", "obstacle_contact"}, {"penalty", penalty}, {"friction", {{"coefficient", 0.3}}}},
            {{"type", "self_vertex_face"}, {"penalty", penalty}}}}};
}

}  // namespace

TEST(PceSim, ResumedRunWithMovingObstacleAndPinsEndsBitForBit) {
  // A sheet lying on a box that moves and turns from t = 0.05 s to 0.13 s (frames 6–13)
  // while a pin group along one edge pulls it up and turns it (its targets move from t = 0
  // on) until it is released at frame 12. The checkpoint of frame 10 comes while both move:
  // the obstacle keeps moving after it and stops within the run, the group is released
  // after it; the resumed run ends frame 15 where the uninterrupted one does. It fails if
  // the obstacle's pose, the pins' targets or the release read anything but the restored
  // frame and time.
  const json scene = sheet_on_a_moving_box(
      {{"velocity", {0.3, 0, 0.1}}, {"angular_velocity", {1.5, 0, 2}}, {"start", 0.05}, {"stop", 0.13}},
      {{"velocity", {0, 0, 0.3}}, {"angular_velocity", {2, 0, 0}}});
  const fs::path file = write_scene(scene, "resume_moving");
  const std::vector<json> a = resume_matches(file, "resume_moving", 15, 13, 10);
  ASSERT_EQ(a.size(), 15u);
  for (std::size_t k = 9; k < 13; ++k) EXPECT_GT(a[k]["contacts"]["obstacle"].get<long>(), 0) << "frame " << k + 1;
  EXPECT_GT(counter(a[9], "pinned_vertices"), 0.0);   // pinned at the checkpoint
  EXPECT_GT(counter(a[10], "pinned_vertices"), 0.0);  // and in frame 11
  EXPECT_EQ(counter(a[11], "pinned_vertices"), 0.0);  // released in frame 12
  // The obstacle rests before its start, moves between the checkpoint (t = 0.1 s) and the
  // end (t = 0.15 s) and stands still after its stop.
  const auto scene_in_cpp = pce::sim::load_scene(file);
  const pce::sim::Obstacle& table = scene_in_cpp->simulation.obstacles.at(0);
  const auto moved = [&](double t0, double t1) { return !table.pose(t0).isApprox(table.pose(t1), 1e-12); };
  EXPECT_FALSE(moved(0.0, 0.04));
  EXPECT_TRUE(moved(0.10, 0.15));
  EXPECT_FALSE(moved(0.135, 0.15));
}

TEST(PceSim, ResumedRunWithKeyframedObstacleAndPinsEndsBitForBit) {
  // The same sheet and box as above, moved by keyframes instead: the box holds its first
  // keyframe until t = 0.05 s, then (smooth) shifts and turns through a second keyframe at
  // 0.09 s to a third at 0.13 s, and the pinned edge's targets rise and turn (linear) through
  // keyframes at 0.06 s and 0.2 s until the group is released at frame 12. The checkpoint of
  // frame 10 falls inside both paths' second segments; the resumed run ends frame 15 where
  // the uninterrupted one does. It fails if a keyframed pose or target read anything but
  // the restored time.
  const json box_keyframes = {
      {"interpolation", "smooth"},
      {"keyframes",
       {{{"time", 0.05}},
        {{"time", 0.09}, {"translation", {0.01, 0, 0.004}}, {"rotation", {{"axis", {0, 0, 1}}, {"degrees", 5}}}},
        {{"time", 0.13},
         {"translation", {0.024, 0, 0.008}},
         {"rotation", {{"axis", {0.6, 0, 0.8}}, {"degrees", 9}}}}}}};
  const json pin_keyframes = {
      {"keyframes",
       {{{"time", 0}},
        {{"time", 0.06}, {"translation", {0, 0, 0.018}}, {"rotation", {{"axis", {1, 0, 0}}, {"degrees", 7}}}},
        {{"time", 0.2}, {"translation", {0, 0, 0.04}}, {"rotation", {{"axis", {1, 0, 0}}, {"degrees", 20}}}}}}};
  const json scene = sheet_on_a_moving_box(box_keyframes, pin_keyframes);
  const fs::path file = write_scene(scene, "resume_keyframed");
  const std::vector<json> a = resume_matches(file, "resume_keyframed", 15, 13, 10);
  ASSERT_EQ(a.size(), 15u);
  for (std::size_t k = 9; k < 13; ++k) EXPECT_GT(a[k]["contacts"]["obstacle"].get<long>(), 0) << "frame " << k + 1;
  EXPECT_GT(counter(a[9], "pinned_vertices"), 0.0);   // pinned at the checkpoint
  EXPECT_EQ(counter(a[11], "pinned_vertices"), 0.0);  // released in frame 12
  // The box holds before its first keyframe and after its last, and moves in between,
  // across the checkpoint (t = 0.1 s).
  const auto loaded = pce::sim::load_scene(file);
  const pce::sim::Obstacle& table = loaded->simulation.obstacles.at(0);
  const auto moved = [&](double t0, double t1) { return !table.pose(t0).isApprox(table.pose(t1), 1e-12); };
  EXPECT_FALSE(moved(0.0, 0.05));
  EXPECT_TRUE(moved(0.09, 0.10));
  EXPECT_TRUE(moved(0.10, 0.11));
  EXPECT_FALSE(moved(0.13, 0.15));
}

TEST(PceSim, ResumedRunWithTwoThreadsEndsBitForBit) {
  // slope_scene at 17² + 11² vertices with "threads": 2 in the scene, so the interrupted, the
  // resumed and the uninterrupted run all use two threads: at the checkpoint of frame 10
  // every kind of contact is active with friction, and the candidate lists are longer than
  // one chunk of the contact passes (2048 pairs), so both threads share them. The resumed
  // run ends frame 15 where the uninterrupted one does; it fails if a checkpointed state
  // depended on which thread produced which part of it.
  json scene = slope_scene(16, 10);
  scene["solver"]["threads"] = 2;
  const std::vector<json> a = resume_matches(write_scene(scene, "resume_threads"), "resume_threads", 15, 13, 10);
  ASSERT_EQ(a.size(), 15u);
  EXPECT_GT(counter(a[9], "vertex_face_friction_contacts"), 0.0);
  EXPECT_GT(counter(a[9], "edge_edge_friction_contacts"), 0.0);
  EXPECT_GT(counter(a[9], "obstacle_friction_contacts"), 0.0);
  EXPECT_GT(counter(a[9], "vertex_face_candidates"), 2048.0);
  EXPECT_GT(counter(a[9], "edge_edge_candidates"), 2048.0);
}

TEST(PceSim, CheckpointOfAnotherSceneOrCorruptIsRefused) {
  const fs::path out = fs::path(PCE_TEST_TMP) / "refuse_ckpt";
  fs::remove_all(out);
  std::string err;
  ASSERT_EQ(run((kScenes / "twist.json").string() + " --frames 2 --checkpoint-every 2 --out " + out.string(), &err), 0)
      << err;
  EXPECT_EQ(run((kScenes / "twist.json").string() + " --frames 4 --hessian exact --resume " + out.string(), &err), 2);
  EXPECT_NE(err.find("checkpoint_0002.pcecp: written for another scene"), std::string::npos) << err;
  EXPECT_EQ(run((kScenes / "drape.json").string() + " --frames 4 --resume " + out.string(), &err), 2);
  EXPECT_NE(err.find("written for another scene"), std::string::npos) << err;
  std::string bytes = read_text(out / "checkpoint_0002.pcecp");
  std::ofstream(out / "checkpoint_0002.pcecp", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_EQ(run((kScenes / "twist.json").string() + " --frames 4 --resume " + out.string(), &err), 2);
  EXPECT_NE(err.find("truncated or corrupted"), std::string::npos) << err;
  bytes[8] = 9;  // the format version
  std::ofstream(out / "checkpoint_0002.pcecp", std::ios::binary) << bytes;
  EXPECT_EQ(run((kScenes / "twist.json").string() + " --frames 4 --resume " + out.string(), &err), 2);
  EXPECT_NE(err.find("checkpoint format version 9"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

TEST(PceSim, IntersectingStartIsRefusedUnlessAllowed) {
  json scene = read_json(kScenes / "crumple.json");
  scene["meshes"][1]["transform"]["translation"] = {0, 0, 0.1};  // the dropped sheet stands through the base
  const fs::path file = fs::path(PCE_TEST_TMP) / "through.json", out = fs::path(PCE_TEST_TMP) / "through_out";
  std::ofstream(file) << scene.dump();
  fs::remove_all(out);
  std::string err;
  EXPECT_EQ(run(file.string() + " --frames 1 --out " + out.string(), &err), 2);
  EXPECT_NE(err.find("through.json: the start state has "), std::string::npos) << err;
  EXPECT_NE(err.find(" intersecting triangle pairs between meshes \"base\" and \"drop\""), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_FALSE(fs::exists(out));
  scene["allow_initial_intersections"] = true;
  std::ofstream(file) << scene.dump();
  EXPECT_EQ(run(file.string() + " --frames 1 --no-frames --out " + out.string(), &err), 0) << err;
  EXPECT_NE(err.find("pce-sim: warning: "), std::string::npos) << err;
  EXPECT_NE(err.find("(allowed by allow_initial_intersections)"), std::string::npos) << err;
}

namespace {

/// A cloth and two strands falling, a box sliding below them: dt 0.01 s, frames 5, every
/// second frame written (frames 0, 2, 4 and 5).
fs::path small_scene() {
  return write_scene(json::parse(R"({"dt": 0.01, "frames": 5, "output_every": 2,
    "meshes": [
      {"name": "cloth", "generator": {"type": "grid", "width": 0.5, "height": 0.5, "nx": 6, "ny": 6}},
      {"name": "hair", "generator": {"type": "strands", "count": 2, "segments": 4, "length": 0.3, "spacing": 0.2},
       "transform": {"translation": [1, 0, 0.5]}}],
    "obstacles": [{"name": "slider", "shape": "box", "half_extents": [0.2, 0.2, 0.05], "position": [0, 0, -0.3],
                   "motion": {"velocity": [0.5, 0, 0]}}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 20},
                {"type": "strand_stretching", "stiffness": 20}]})"),
                     "small_movie");
}

/// The frame numbers of `dir`'s frame_NNNN.obj files, in order.
std::vector<int> obj_frames(const fs::path& dir) {
  std::set<int> frames;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("frame_", 0) == 0 && e.path().extension() == ".obj") frames.insert(std::stoi(name.substr(6)));
  }
  return {frames.begin(), frames.end()};
}

/// Checks the USD cache `usda` of a run of `scene` against the OBJ frames in `objs` (every
/// time code's points are the OBJ's vertices rounded to float; the topology once) and
/// returns its time codes.
std::vector<int> cache_matches_frames(const fs::path& usda_file, const fs::path& scene, const fs::path& objs) {
  namespace usda = pce::sim::usda;
  const usda::Layer layer = usda::read(usda_file.string());
  const auto model = pce::sim::load_scene(scene)->simulation.model;
  const double dt = read_json(scene)["dt"].get<double>();
  EXPECT_EQ(layer.metadata.at("timeCodesPerSecond").x, 1 / dt);
  EXPECT_EQ(layer.metadata.at("upAxis").text, "Z");
  EXPECT_EQ(layer.metadata.at("metersPerUnit").x, 1.0);
  std::vector<int> codes;
  for (const pce::sim::MeshRange& r : model.meshes) {
    SCOPED_TRACE(r.name);
    const usda::Prim* p = layer.at("/World/" + r.name);
    if (!p) {
      ADD_FAILURE() << "no prim /World/" << r.name;
      continue;
    }
    EXPECT_EQ(p->type, r.triangle_count > 0 ? "Mesh" : "BasisCurves");
    if (r.triangle_count > 0) {
      EXPECT_EQ(usda::ints(p->attributes.at("faceVertexCounts").value).size(),
                static_cast<std::size_t>(r.triangle_count));
      EXPECT_EQ(usda::ints(p->attributes.at("faceVertexIndices").value).size(), 3u * r.triangle_count);
    } else {
      const std::vector<int> counts = usda::ints(p->attributes.at("curveVertexCounts").value);
      EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), 0), r.vertex_count);
      EXPECT_EQ(static_cast<int>(counts.size()), r.vertex_count - r.segment_count);  // one curve per strand
    }
    std::vector<int> here;
    for (const auto& [time, points] : p->attributes.at("points").samples) {
      here.push_back(static_cast<int>(time));
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d.obj", static_cast<int>(time));
      if (!fs::exists(objs / name)) continue;  // checked by the caller against the OBJ files there are
      const pce::sim::Mesh obj = pce::sim::read_obj(objs / name);
      const Eigen::Matrix3Xf want = obj.positions.middleCols(r.first_vertex, r.vertex_count).cast<float>();
      EXPECT_EQ(usda::floats(points), std::vector<float>(want.data(), want.data() + want.size())) << name;
    }
    if (codes.empty()) codes = here;
    EXPECT_EQ(here, codes);  // every prim has the same time codes
  }
  if (!codes.empty()) {
    EXPECT_EQ(layer.metadata.at("startTimeCode").x, codes.front());
    EXPECT_EQ(layer.metadata.at("endTimeCode").x, codes.back());
  }
  return codes;
}

using pce::sim::testing::have_ffmpeg_and_ffprobe;
using pce::sim::testing::probe;

}  // namespace

TEST(PceSim, UsdCacheHoldsEveryOutputFrameAsItsObj) {
  const fs::path scene = small_scene(), out = fs::path(PCE_TEST_TMP) / "usd_run";
  fs::remove_all(out);
  std::string err;
  ASSERT_EQ(run(scene.string() + " --out " + out.string() + " --usd " + (out / "cache.usda").string(), &err), 0) << err;
  EXPECT_EQ(obj_frames(out), (std::vector<int>{0, 2, 4, 5}));
  EXPECT_EQ(cache_matches_frames(out / "cache.usda", scene, out), (std::vector<int>{0, 2, 4, 5}));
  EXPECT_FALSE(fs::exists(out / "pce-sim-frames.tmp"));
  // The box slides: its transform has a sample at every time code.
  const auto layer = pce::sim::usda::read((out / "cache.usda").string());
  EXPECT_EQ(layer.at("/World/obstacles/slider")->attributes.at("xformOp:transform").samples.size(), 4u);
  // --no-frames: the same cache, without the OBJ files.
  const fs::path bare = fs::path(PCE_TEST_TMP) / "usd_run_no_frames";
  fs::remove_all(bare);
  ASSERT_EQ(
      run(scene.string() + " --no-frames --out " + bare.string() + " --usd " + (bare / "cache.usda").string(), &err), 0)
      << err;
  EXPECT_EQ(obj_frames(bare), (std::vector<int>{5}));
  EXPECT_EQ(read_text(bare / "cache.usda"), read_text(out / "cache.usda"));
}

TEST(PceSim, VideoWithoutFfmpegExitsTwoAndWritesNothing) {
  const fs::path empty = fs::path(PCE_TEST_TMP) / "empty_path", out = fs::path(PCE_TEST_TMP) / "video_no_ffmpeg";
  fs::create_directories(empty);
  fs::remove_all(out);
  std::string err;
  EXPECT_EQ(run(small_scene().string() + " --out " + out.string() + " --video " + (out / "m.mp4").string(), &err,
                "PATH=" + empty.string()),
            2);
  EXPECT_EQ(err,
            "pce-sim: command line: --video: ffmpeg not found on PATH; install it (Debian, Ubuntu: apt-get install "
            "ffmpeg), or leave --video out (see pce-sim --help)\n");
  EXPECT_FALSE(fs::exists(out));
  // A movie or cache that could not be written is refused the same way, before the run.
  EXPECT_EQ(run(small_scene().string() + " --out " + out.string() + " --usd " + (out / "c.txt").string(), &err), 2);
  EXPECT_EQ(err, "pce-sim: command line: --usd: " + (out / "c.txt").string() +
                     ": expected a file name ending in .usda or .usd (see pce-sim --help)\n");
  EXPECT_EQ(run(small_scene().string() + " --out " + out.string() + " --usd " + PCE_TEST_TMP + "/x.usda", &err, ""), 0)
      << err;  // a control: the same command with a good file runs
  fs::remove_all(out);
  EXPECT_EQ(run(small_scene().string() + " --out " + out.string() + " --video " + PCE_TEST_TMP, &err), 2);
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_FALSE(fs::exists(out));
}

TEST(PceSim, VideoHasOneFramePerOutputFrame) {
  if (!have_ffmpeg_and_ffprobe()) GTEST_SKIP() << "ffmpeg or ffprobe is not installed (Debian: apt-get install ffmpeg)";
  const fs::path out = fs::path(PCE_TEST_TMP) / "video_run", movie = out / "movie.mp4";
  fs::remove_all(out);
  std::string err;
  // --no-frames: the movie still has every output frame (0, 2, 4, 5), at 1/(0.01 · 2) = 50 fps.
  ASSERT_EQ(run(small_scene().string() + " --no-frames --out " + out.string() + " --video " + movie.string(), &err), 0)
      << err;
  const auto p = probe(movie);
  EXPECT_EQ(p.count("nb_read_frames") ? p.at("nb_read_frames") : "", "4");
  EXPECT_EQ(p.count("r_frame_rate") ? p.at("r_frame_rate") : "", "50/1");
  EXPECT_EQ(p.count("codec_name") ? p.at("codec_name") : "", "h264");
  EXPECT_EQ(p.count("pix_fmt") ? p.at("pix_fmt") : "", "yuv420p");
  EXPECT_EQ(p.count("width") ? p.at("width") : "", "960");
  EXPECT_EQ(p.count("height") ? p.at("height") : "", "720");
  EXPECT_FALSE(fs::exists(out / "pce-sim-frames.tmp"));
  EXPECT_FALSE(fs::exists(movie.string() + ".ffmpeg-log"));
}

TEST(PceSim, StoppedRunWritesTheMovieAndCacheOfItsFramesAndAResumedRunFromItsCheckpoint) {
  // The long twist (output_every 4) stopped by SIGINT: the cache and the movie hold frame 0,
  // every fourth frame done and the frame it stopped at; a resumed run's start at the
  // checkpoint's frame.
  const bool movie = have_ffmpeg_and_ffprobe();
  const fs::path out = fs::path(PCE_TEST_TMP) / "stopped_usd";
  fs::remove_all(out);
  std::vector<std::string> args = long_twist(out);
  args.insert(args.end(), {"--usd", (out / "cache.usda").string()});
  if (movie) args.insert(args.end(), {"--video", (out / "movie.mp4").string()});
  const pid_t pid = spawn(args, out.string() + ".err");
  ASSERT_TRUE(wait_for_lines(pid, out / "stats.jsonl", 5));
  kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << read_text(out.string() + ".err");
  EXPECT_EQ(WEXITSTATUS(status), 130) << read_text(out.string() + ".err");
  const int done = read_json(out / "summary.json")["frames_done"].get<int>();
  std::vector<int> expected;
  for (int f = 0; f <= done; f += 4) expected.push_back(f);
  if (expected.back() != done) expected.push_back(done);
  const fs::path twist = kScenes / "twist.json";
  EXPECT_EQ(cache_matches_frames(out / "cache.usda", twist, out), expected);
  EXPECT_EQ(obj_frames(out), expected);  // every time code's OBJ was there to compare with
  if (movie) {
    const auto p = probe(out / "movie.mp4");
    EXPECT_EQ(p.count("nb_read_frames") ? p.at("nb_read_frames") : "", std::to_string(expected.size()));
  }
  // Resumed to three frames more: the new cache starts at the checkpoint's frame.
  std::string err;
  ASSERT_EQ(run(twist.string() + " --threads 1 --frames " + std::to_string(done + 3) + " --resume " + out.string() +
                    " --usd " + (out / "resumed.usda").string(),
                &err),
            0)
      << err;
  std::vector<int> resumed{done};
  for (int f = done + 1; f <= done + 3; ++f)
    if (f % 4 == 0 || f == done + 3) resumed.push_back(f);
  EXPECT_EQ(cache_matches_frames(out / "resumed.usda", twist, out), resumed);
}
