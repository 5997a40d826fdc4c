// SPDX-License-Identifier: MIT
// Checkpoint files (src/sim/output/checkpoint.cpp), in process: a checkpoint read into a
// simulation of the same scene writes back the same bytes and continues bit for bit as the
// simulation it was written from; a checkpoint of another fingerprint is refused, and the
// fingerprint changes with the scene text and every part of the model; and when
// one effect refuses its saved state after the effects before it took theirs, read_checkpoint
// puts those back, so the simulation it throws from is the one it was given.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <pce/sim/checkpoint.hpp>
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/counters.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/scene.hpp>
#include <pce/sim/simulation.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using nlohmann::json;
using namespace pce::sim;

namespace {

/// A sheet resting on a box and a smaller one, turned by 10°, dropped onto it from 2.5 cm:
/// it lands around frame 7, and from then on both self-contact effects (the last two
/// effects) track active pairs. Obstacle contact comes before them.
const std::string& scene_text() {
  static const std::string text = json{
      {"dt", 0.01},
      {"frames", 20},
      {"solver", {{"tolerance", 0.01}, {"max_iterations", 30}}},
      {"obstacles",
       {{{"name", "table"}, {"shape", "box"}, {"half_extents", {0.3, 0.3, 0.05}}, {"position", {0, 0, -0.05}}}}},
      {"meshes",
       {{{"name", "under"},
         {"generator", {{"type", "grid"}, {"width", 0.2}, {"height", 0.2}, {"nx", 8}, {"ny", 8}}},
         {"transform", {{"translation", {0, 0, 0.006}}}}},
        {{"name", "over"},
         {"generator", {{"type", "grid"}, {"width", 0.12}, {"height", 0.12}, {"nx", 6}, {"ny", 6}}},
         {"transform", {{"rotation", {{"axis", {0, 0, 1}}, {"degrees", 10}}}, {"translation", {0.01, 0.01, 0.031}}}}}}},
      {"effects",
       {{{"type", "gravity"}},
        {{"type", "stretching"}, {"stiffness", 20}},
        {{"type", "bending"}, {"stiffness", 1e-5}},
        {{"type", "obstacle_contact"}, {"penalty", {{"type", "quadratic"}, {"stiffness", 20}, {"distance", 0.005}}}},
        {{"type", "self_vertex_face"}, {"penalty", {{"type", "quadratic"}, {"stiffness", 20}, {"distance", 0.005}}}},
        {{"type", "self_edge_edge"},
         {"penalty",
          {{"type", "quadratic"},
           {"stiffness", 20},
           {"distance", 0.005}}}}}}}.dump();
  return text;
}

/// The scene, stepped to frame `frame`.
std::unique_ptr<Scene> scene_at(int frame) {
  auto scene = load_scene_text(scene_text(), "checkpoint.json", PCE_TEST_TMP);
  while (scene->simulation.frame < frame) scene->simulation.step();
  return scene;
}

std::uint64_t fingerprint_of(const Simulation& sim) { return simulation_fingerprint(scene_text(), sim.model); }

/// What read_checkpoint may change in a simulation: every effect's saved state, x, v, frame
/// and time.
struct Snapshot {
  std::vector<std::string> states;
  Eigen::Matrix3Xd x, v;
  int frame = 0;
  double time = 0;
  explicit Snapshot(const Simulation& sim) : x(sim.x), v(sim.v), frame(sim.frame), time(sim.time) {
    for (const auto& e : sim.effects) {
      const auto* c = dynamic_cast<const ContactEffect*>(e.get());
      states.push_back(c ? c->save_state() : std::string());
    }
  }
};

/// Expects `sim` to be exactly what `before` saw (bit for bit).
void expect_unchanged(const Simulation& sim, const Snapshot& before) {
  const Snapshot now(sim);
  ASSERT_EQ(now.states.size(), before.states.size());
  for (std::size_t k = 0; k < now.states.size(); ++k)
    EXPECT_TRUE(now.states[k] == before.states[k])
        << "the state of effect " << k << " (" << sim.effects[k]->name() << ") changed";
  EXPECT_EQ(now.x, before.x);
  EXPECT_EQ(now.v, before.v);
  EXPECT_EQ(now.frame, before.frame);
  EXPECT_EQ(now.time, before.time);
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
}

template <class T> T get(const std::string& bytes, std::size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof value);
  return value;
}

/// Where each effect's name and state lie in a checkpoint's bytes, read by the layout that
/// checkpoint.hpp documents (magic, version, byte-order mark, fingerprint, frame, time, n,
/// x, v, effect count, per effect name and state, checksum).
struct Layout {
  std::vector<std::string> names;
  std::vector<std::size_t> state_at, state_size;
};
Layout layout_of(const std::string& bytes) {
  Layout l;
  std::size_t at = 8 + 4 + 4 + 8 + 4 + 8;
  const auto n = get<std::int64_t>(bytes, at);
  at += 8 + 2 * 3 * static_cast<std::size_t>(n) * sizeof(double);
  const auto effects = get<std::uint32_t>(bytes, at);
  at += 4;
  for (std::uint32_t k = 0; k < effects; ++k) {
    const auto name_size = get<std::uint32_t>(bytes, at);
    l.names.push_back(bytes.substr(at + 4, name_size));
    at += 4 + name_size;
    l.state_size.push_back(get<std::uint64_t>(bytes, at));
    l.state_at.push_back(at + 8);
    at += 8 + l.state_size.back();
  }
  EXPECT_EQ(at + 8, bytes.size());  // only the checksum follows
  return l;
}

/// Replaces the trailing FNV-1a checksum with that of the bytes before it.
void fix_checksum(std::string& bytes) {
  const std::size_t body = bytes.size() - sizeof(std::uint64_t);
  const std::uint64_t sum = fnv1a64(std::string_view(bytes.data(), body));
  std::memcpy(bytes.data() + body, &sum, sizeof sum);
}

/// The index of the effect named `name` in `sim`.
std::size_t effect_index(const Simulation& sim, const std::string& name) {
  for (std::size_t k = 0; k < sim.effects.size(); ++k)
    if (sim.effects[k]->name() == name) return k;
  ADD_FAILURE() << "no effect " << name;
  return 0;
}

}  // namespace

TEST(Checkpoint, ReadBackWritesTheSameBytesAndContinuesBitForBit) {
  // A at frame 10, in contact, written; read into B (the same scene at frame 4): B then
  // writes the same bytes (so every saved quantity came back exactly), and one more step
  // of each ends on the same bits. Fails if read and write disagree on any part of the
  // layout or a state does not come back whole.
  auto a = scene_at(10), b = scene_at(4);
  ASSERT_GT(a->simulation.effects.size(), 0u);
  const fs::path file = fs::path(PCE_TEST_TMP) / "checkpoint_round_trip.pcecp",
                 again = fs::path(PCE_TEST_TMP) / "checkpoint_round_trip_again.pcecp";
  write_checkpoint(file, a->simulation, fingerprint_of(a->simulation));
  read_checkpoint(file, b->simulation, fingerprint_of(b->simulation));
  write_checkpoint(again, b->simulation, fingerprint_of(b->simulation));
  EXPECT_TRUE(read_bytes(file) == read_bytes(again));
  EXPECT_EQ(b->simulation.frame, 10);
  a->simulation.step();
  b->simulation.step();
  EXPECT_EQ(a->simulation.x, b->simulation.x);
  EXPECT_EQ(a->simulation.v, b->simulation.v);
  EXPECT_EQ(a->simulation.time, b->simulation.time);
}

TEST(Checkpoint, BlockDescentWithSubstepsAndChebyshevContinuesBitForBit) {
  // The same scene in block descent, 3 substeps a frame, Chebyshev's acceleration: a run
  // written at frame 9 and read into one at frame 3 goes on as the uninterrupted run does.
  const auto configure = [](Simulation& sim) {
    sim.solver.mode = SolverMode::block_descent;
    sim.solver.iterations = 8;
    sim.solver.substeps = 3;
    sim.solver.acceleration = Acceleration::chebyshev;
  };
  auto a = load_scene_text(scene_text(), "checkpoint.json", PCE_TEST_TMP);
  auto b = load_scene_text(scene_text(), "checkpoint.json", PCE_TEST_TMP);
  configure(a->simulation);
  configure(b->simulation);
  while (a->simulation.frame < 9) a->simulation.step();
  while (b->simulation.frame < 3) b->simulation.step();
  const fs::path file = fs::path(PCE_TEST_TMP) / "checkpoint_block_descent.pcecp";
  write_checkpoint(file, a->simulation, fingerprint_of(a->simulation));
  read_checkpoint(file, b->simulation, fingerprint_of(b->simulation));
  double contacts = 0;
  for (int f = 10; f <= 13; ++f) {
    const FrameStats sa = a->simulation.step();
    b->simulation.step();
    ASSERT_EQ(a->simulation.x, b->simulation.x) << "frame " << f;
    ASSERT_EQ(a->simulation.v, b->simulation.v) << "frame " << f;
    contacts += sa.counters.at(Counter::vertex_face_contacts) + sa.counters.at(Counter::obstacle_contacts);
  }
  EXPECT_EQ(a->simulation.time, b->simulation.time);
  EXPECT_GT(contacts, 0);  // in contact, where the effects' carried state matters
}

TEST(Checkpoint, AnotherFingerprintIsRefusedAndChangesNothing) {
  auto a = scene_at(10), b = scene_at(4);
  const fs::path file = fs::path(PCE_TEST_TMP) / "checkpoint_fingerprint.pcecp";
  write_checkpoint(file, a->simulation, fingerprint_of(a->simulation) + 1);
  const Snapshot before(b->simulation);
  try {
    read_checkpoint(file, b->simulation, fingerprint_of(b->simulation));
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_NE(std::string(e.what()).find("written for another scene"), std::string::npos) << e.what();
  }
  expect_unchanged(b->simulation, before);
}

TEST(Checkpoint, AnEffectRefusingItsStateRollsBackTheEffectsBeforeIt) {
  // A at frame 10 (both sheets in contact) is written; B, the same scene at frame 8, has
  // other tracked pairs and another query in each self-contact effect. The file is then
  // corrupted in self_edge_edge's state alone, the last effect (its first pair's first edge
  // index set to the edge count, which load_state refuses), and its checksum recomputed so
  // that only load_state can refuse it. read_checkpoint into B restores obstacle_contact
  // and self_vertex_face before self_edge_edge refuses: it must throw an InputError naming
  // the file and the reason and put those two back, leaving every effect's state, x, v,
  // frame and time as they were (without the rollback, self_vertex_face keeps A's state and
  // this fails), and B then steps exactly as a twin that never read the file. The same file
  // uncorrupted is then read into B, which continues bit for bit as A does.
  auto a = scene_at(9), b = scene_at(8), twin = scene_at(8);
  Simulation& sa = a->simulation;
  Simulation& sb = b->simulation;
  const FrameStats tenth = sa.step();
  ASSERT_GT(tenth.counters.at(Counter::vertex_face_contacts), 0.0);  // A is in contact at frame 10
  ASSERT_GT(tenth.counters.at(Counter::edge_edge_contacts), 0.0);
  const std::size_t vf = effect_index(sa, "self_vertex_face"), ee = effect_index(sa, "self_edge_edge");
  ASSERT_LT(vf, ee);
  ASSERT_EQ(ee + 1, sa.effects.size());
  const Snapshot of_a(sa), before(sb);
  ASSERT_FALSE(of_a.states[vf] == before.states[vf]);  // restoring A's state would show
  ASSERT_FALSE(of_a.states[ee] == before.states[ee]);

  const fs::path file = fs::path(PCE_TEST_TMP) / "checkpoint_rollback.pcecp",
                 corrupt = fs::path(PCE_TEST_TMP) / "checkpoint_rollback_corrupt.pcecp";
  write_checkpoint(file, sa, fingerprint_of(sa));
  const std::string bytes = read_bytes(file);
  const Layout l = layout_of(bytes);
  ASSERT_EQ(l.names.size(), sa.effects.size());
  ASSERT_EQ(l.names[ee], "self_edge_edge");
  std::uint64_t pairs = 0;
  std::memcpy(&pairs, bytes.data() + l.state_at[ee], sizeof pairs);
  ASSERT_GT(pairs, 0u);  // A tracks edge-edge pairs
  std::string bad = bytes;
  const auto edges = static_cast<std::int32_t>(sa.model.edges.cols());
  std::memcpy(bad.data() + l.state_at[ee] + sizeof pairs, &edges, sizeof edges);  // pair 0's first edge
  fix_checksum(bad);
  write_bytes(corrupt, bad);

  try {
    read_checkpoint(corrupt, sb, fingerprint_of(sb));
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), corrupt.string());
    EXPECT_NE(std::string(e.what()).find(corrupt.string() + ": self_edge_edge: pair 0 of the saved state does not fit"),
              std::string::npos)
        << e.what();
  }
  expect_unchanged(sb, before);
  sb.step();
  twin->simulation.step();
  EXPECT_EQ(sb.x, twin->simulation.x);  // nothing of the refused file stayed behind

  read_checkpoint(file, sb, fingerprint_of(sb));
  expect_unchanged(sb, of_a);
  sa.step();
  sb.step();
  EXPECT_EQ(sa.x, sb.x);
  EXPECT_EQ(sa.v, sb.v);
}

TEST(Checkpoint, TheFingerprintCoversTheSceneTextAndEveryPartOfTheModel) {
  // A tet box: changing any one part of the model (or the text) changes the fingerprint,
  // the connectivity of the tetrahedra too (two tetrahedra trade a vertex order that keeps
  // the rest positions and masses).
  Model model =
      build_model({{"box", tet_box(Eigen::Vector3d(0.1, 0.1, 0.1), Eigen::Vector3i(1, 1, 1)), 1000.0, 0.005}});
  const std::uint64_t base = simulation_fingerprint("scene", model);
  EXPECT_EQ(simulation_fingerprint("scene", model), base);
  EXPECT_NE(simulation_fingerprint("scene ", model), base);
  const auto changed = [&](const std::function<void(Model&)>& change) {
    Model m = model;
    change(m);
    return simulation_fingerprint("scene", m) != base;
  };
  EXPECT_TRUE(changed([](Model& m) { m.rest(0, 0) += 1e-12; }));
  EXPECT_TRUE(changed([](Model& m) { m.mass[0] *= 1 + 1e-15; }));
  EXPECT_TRUE(changed([](Model& m) { std::swap(m.triangles(0, 0), m.triangles(1, 0)); }));
  EXPECT_TRUE(changed([](Model& m) { std::swap(m.tetrahedra(2, 0), m.tetrahedra(3, 0)); }));
  Model strand = build_model({{"s", strands(1, 3, 0.1, 0.01, 0.0), 0.1, 0.005}});
  const std::uint64_t s = simulation_fingerprint("scene", strand);
  std::swap(strand.segments(0, 0), strand.segments(1, 0));
  EXPECT_NE(simulation_fingerprint("scene", strand), s);
}
