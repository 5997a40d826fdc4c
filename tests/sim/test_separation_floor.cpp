// SPDX-License-Identifier: MIT
// The minimum separation (src/sim/effects/floor.hpp, one mechanism for both contact kinds:
// self contact's step_bound.cpp and separation_floor.*, obstacle contact's obstacle_bounds.*
// and obstacle_floor.*; docs/simulation.md §4.6): no Newton step brings a
// pair that starts it at or above its floor below it, however many steps press it; without
// the floor the same steps press pairs toward zero; a held pair's penalty is stiffened, the
// stiffened energy's gradient matches central differences, checkpoints keep the factors;
// scenes whose penalties are too soft for their load (a crumpling sheet, a sheet pressed onto
// a box by a growing load) end no frame with an intersecting pair or a vertex below the floor.
#include <pce/energy/closest_feature.hpp>
#include <pce/penalties/quadratic.hpp>
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/intersections.hpp>
#include <pce/sim/scene.hpp>

#include "two_sheets.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

using namespace pce::sim;
using nlohmann::json;

namespace {

constexpr double kDistance = 0.02;  // the contact effects' activation distance d

using fixtures::contact_of;
using fixtures::two_sheets;

json contact(const char* type, bool closest, double min_separation) {
  json c = {{"type", type}, {"length", "unsigned"}, {"closest_features", closest}, {"min_separation", min_separation}};
  c["penalty"] = {{"type", "quadratic"}, {"stiffness", 50.0}, {"distance", kDistance}};
  return c;
}

/// Starts a step at x (zero velocity) so the effect queries its pairs.
void begin(Scene& s, const Eigen::Matrix3Xd& at) { fixtures::begin_at(s, at); }

/// Sheet b pressed down by 12 mm, every vertex moved randomly by up to 2 mm per axis: the
/// sheets close in, and a step taken whole would pass b through a.
Eigen::Matrix3Xd pressing_motion(const Eigen::Matrix3Xd& x, int seed) {
  std::srand(static_cast<unsigned>(seed) + 7u);
  Eigen::Matrix3Xd dx = Eigen::Matrix3Xd::Random(3, x.cols()) * 0.002;
  dx.row(2).tail(x.cols() / 2).array() -= 0.012;
  return dx;
}

/// Every pair of the model (vertex-face or edge-edge) that shares no vertex, as its four
/// vertices.
std::vector<std::array<int, 4>> all_pairs(const Model& m, bool vf) {
  std::vector<std::array<int, 4>> pairs;
  if (vf) {
    for (int v = 0; v < m.vertex_count(); ++v)
      for (Eigen::Index t = 0; t < m.triangles.cols(); ++t)
        if (m.triangles(0, t) != v && m.triangles(1, t) != v && m.triangles(2, t) != v)
          pairs.push_back({v, m.triangles(0, t), m.triangles(1, t), m.triangles(2, t)});
  } else {
    for (Eigen::Index a = 0; a < m.edges.cols(); ++a)
      for (Eigen::Index b = a + 1; b < m.edges.cols(); ++b) {
        const int p = m.edges(0, a), q = m.edges(1, a), r = m.edges(0, b), s = m.edges(1, b);
        if (p != r && p != s && q != r && q != s) pairs.push_back({p, q, r, s});
      }
  }
  return pairs;
}

/// The distance between a pair's primitives at x (closest features); +∞ when degenerate.
double distance(const Eigen::Matrix3Xd& x, const std::array<int, 4>& v, bool vf) {
  pce::Vec12<double> xp;
  for (int j = 0; j < 4; ++j) xp.segment<3>(3 * j) = x.col(v[static_cast<std::size_t>(j)]);
  pce::ClosestFeatureEnergy<double> ce;
  const pce::QuadraticPenalty probe{1.0, 0.0};
  const pce::Status s = vf ? pce::closest_feature_energy<pce::VertexFace>(xp, pce::UnsignedLength{}, probe, ce)
                           : pce::closest_feature_energy<pce::EdgeEdge>(xp, pce::UnsignedLength{}, probe, ce);
  return s == pce::Status::ok ? ce.length : std::numeric_limits<double>::infinity();
}

/// What pressing two sheets together step after step did: the smallest distance any pair
/// that started a step at or above the floor reached along it (sampled), relative to the
/// floor, and the holds.
struct Pressed {
  double closest = std::numeric_limits<double>::infinity();  ///< smallest distance / floor (or / 1 without floor)
  int holds = 0;
};

/// Presses the sheets of `s` together for `steps` Newton-like updates: each takes the
/// fraction max_step allows of a new pressing motion (the candidates covered, checked and
/// queried again as the solver does), and samples 24 states along it.
Pressed press(Scene& s, bool vf, double floor, int steps, int seed) {
  ContactEffect& e = contact_of(s.simulation.effects[0]);
  Eigen::Matrix3Xd x = s.simulation.x;
  begin(s, x);
  const auto pairs = all_pairs(s.simulation.model, vf);
  Pressed out;
  const double unit = floor > 0 ? floor : 1.0;
  for (int it = 0; it < steps; ++it) {
    const Eigen::Matrix3Xd dx = pressing_motion(x, seed * 1000 + it);
    e.cover_step(x, dx);
    const double t = e.begin_line_search(x, dx);
    EXPECT_GE(t, 0.0);
    std::vector<double> d0(pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) d0[k] = distance(x, pairs[k], vf);
    for (int i = 1; i <= 24; ++i) {
      const Eigen::Matrix3Xd at = x + (t * i / 24.0) * dx;
      for (std::size_t k = 0; k < pairs.size(); ++k)
        if (d0[k] < 2 * kDistance && d0[k] >= floor)
          out.closest = std::min(out.closest, distance(at, pairs[k], vf) / unit);
    }
    x += t * dx;
    out.holds += e.end_line_search(x) ? 1 : 0;
    if (!e.still_valid(x)) e.refresh(x);
  }
  return out;
}

TEST(SeparationFloor, NoStepBringsAPairBelowItsFloorHoweverOftenItIsPressed) {
  // Two sheets 1.5 mm apart (d = 2 cm, floor 0.01 d = 0.2 mm), pressed together 30 times by
  // motions that would carry one through the other: every pair that starts a step at or
  // above its floor stays there at every sampled point of the step (to a relative 1e-9), and
  // the pairs do reach the floor's band (the step bound stops a pressed pair at twice the
  // floor), where the steps hold them.
  for (const char* type : {"self_vertex_face", "self_edge_edge"})
    for (const bool closest : {false, true})
      for (int seed = 0; seed < 3; ++seed) {
        SCOPED_TRACE(std::string(type) + (closest ? " closest features" : " plane") + " seed " + std::to_string(seed));
        auto s = two_sheets(contact(type, closest, 0.01), 0.0015);
        const Pressed p = press(*s, std::string(type) == "self_vertex_face", 0.01 * kDistance, 30, seed);
        EXPECT_GE(p.closest, 1 - 1e-9);
        EXPECT_LT(p.closest, 2.05);
        EXPECT_GT(p.holds, 0);
      }
}

/// Two identical 4 × 4 sheets (5 cm edges), the second `gap` straight above the first.
std::unique_ptr<Scene> stacked_sheets(const json& contact, double gap) {
  json j = json::parse(R"({
    "dt": 0.01, "frames": 1,
    "meshes": [
      {"name": "a", "generator": {"type": "grid", "width": 0.2, "height": 0.2, "nx": 4, "ny": 4}},
      {"name": "b", "generator": {"type": "grid", "width": 0.2, "height": 0.2, "nx": 4, "ny": 4}}
    ],
    "effects": []
  })");
  j["meshes"][1]["transform"]["translation"] = {0.0, 0.0, gap};
  j["effects"].push_back(contact);
  return load_scene_text(j.dump(), "stacked.json", PCE_TEST_TMP);
}

TEST(SeparationFloor, APairAtOrBelowItsFloorSlidesFreelyButComesNoCloser) {
  // Stacked sheets 0.3 mm apart (floor 0.2 mm: within twice of it) and 0.1 mm apart (below
  // it, as a start state could place them). The upper sliding 8 mm along x is not limited
  // at all: every pair's separating direction is normal to the slide, or the pair parts (the
  // Lipschitz bound alone allows 0.9 d / 8 mm, a few percent). Pressed down, no pair comes
  // closer than its floor, or than it was when below it.
  for (const double gap : {0.0003, 0.0001})
    for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
      SCOPED_TRACE(std::string(type) + " gap " + std::to_string(gap));
      const bool vf = std::string(type) == "self_vertex_face";
      auto s = stacked_sheets(contact(type, true, 0.01), gap);
      ContactEffect& e = contact_of(s->simulation.effects[0]);
      const Eigen::Matrix3Xd x = s->simulation.x;
      begin(*s, x);
      const Eigen::Index half = x.cols() / 2;
      Eigen::Matrix3Xd slide = Eigen::Matrix3Xd::Zero(3, x.cols());
      slide.block(0, half, 1, half).setConstant(0.008);
      e.cover_step(x, slide);
      EXPECT_EQ(e.begin_line_search(x, slide), 1.0);
      Eigen::Matrix3Xd press = Eigen::Matrix3Xd::Zero(3, x.cols());
      press.block(2, half, 1, half).setConstant(-0.01);
      e.cover_step(x, press);
      const double t = e.begin_line_search(x, press);
      EXPECT_LT(t, 0.1);
      double closest = std::numeric_limits<double>::infinity();
      for (const auto& p : all_pairs(s->simulation.model, vf)) {
        const double d0 = distance(x, p, vf);
        if (!(d0 < 2 * kDistance)) continue;
        for (int i = 1; i <= 24; ++i) {
          const double d = distance(x + (t * i / 24.0) * press, p, vf);
          EXPECT_GE(d, std::min(d0, 0.01 * kDistance) * (1 - 1e-9));
          closest = std::min(closest, d);
        }
      }
      if (gap > 0.01 * kDistance)
        EXPECT_LT(closest, gap);  // the press brought pairs into the floor's band
      else
        EXPECT_EQ(t, 0.0);  // below the floor: no step toward it at all
    }
}

TEST(SeparationFloor, WithoutAFloorTheSameStepsPressPairsTowardZero) {
  // The same presses with min_separation 0 (the step bound keeps a tenth of each distance
  // per step): the pairs come closer than a tenth of the floor above, and nothing is held.
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    SCOPED_TRACE(type);
    auto s = two_sheets(contact(type, true, 0.0), 0.0015);
    const Pressed p = press(*s, std::string(type) == "self_vertex_face", 0.0, 30, 0);
    EXPECT_LT(p.closest, 0.1 * 0.01 * kDistance);
    EXPECT_GT(p.closest, 0.0);  // still no crossing
    EXPECT_EQ(p.holds, 0);
  }
}

/// The effect's energy and gradient at x.
double energy(ContactEffect& e, const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd* g = nullptr) {
  if (g) g->setZero(3, x.cols());
  e.begin_iteration(x);
  return e.evaluate(x, g, nullptr);
}

TEST(SeparationFloor, AHeldPairsPenaltyIsStiffenedAndItsGradientIsTheEnergys) {
  // Pressed to the floor, the held pairs' penalties are stiffened (the counters say how
  // many), so the energy at the same state grows; the stiffened energy's gradient matches
  // central differences (step 1e-7 m at pairs ~0.2 mm apart) to 1e-5 relative.
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    SCOPED_TRACE(type);
    auto s = two_sheets(contact(type, true, 0.01), 0.0015);
    ContactEffect& e = contact_of(s->simulation.effects[0]);
    Eigen::Matrix3Xd x = s->simulation.x;
    begin(*s, x);
    double before = 0, after = 0;
    int held = 0;
    for (int it = 0; it < 30 && held < 3; ++it) {
      const Eigen::Matrix3Xd dx = pressing_motion(x, it);
      e.cover_step(x, dx);
      x += e.begin_line_search(x, dx) * dx;
      before = energy(e, x);
      if (e.end_line_search(x)) {
        ++held;
        after = energy(e, x);
        EXPECT_GT(after, before);
      }
      if (!e.still_valid(x)) e.refresh(x);
    }
    ASSERT_GT(held, 0);
    EffectCounters c;
    e.report(c);
    EXPECT_GT(c.at("floor_holds"), 0.0);
    EXPECT_GT(c.at("stiffened_pairs"), 0.0);
    Eigen::Matrix3Xd g;
    energy(e, x, &g);
    const double h = 1e-7;
    double worst = 0;
    for (Eigen::Index i = 0; i < x.cols(); ++i)
      for (int k = 0; k < 3; ++k) {
        Eigen::Matrix3Xd xp = x, xm = x;
        xp(k, i) += h;
        xm(k, i) -= h;
        const double fd = (energy(e, xp) - energy(e, xm)) / (2 * h);
        worst = std::max(worst, std::abs(fd - g(k, i)));
      }
    EXPECT_LE(worst, 1e-5 * g.cwiseAbs().maxCoeff()) << "largest gradient " << g.cwiseAbs().maxCoeff();
  }
}

TEST(SeparationFloor, CheckpointsKeepTheStiffening) {
  // A stiffened effect's saved state loads into a fresh one (begun at the same state) whose
  // energy there is bit for bit the same; a factor below 1 or cut short is refused.
  auto s = two_sheets(contact("self_vertex_face", true, 0.01), 0.0015);
  ContactEffect& e = contact_of(s->simulation.effects[0]);
  Eigen::Matrix3Xd x = s->simulation.x;
  begin(*s, x);
  bool held = false;
  for (int it = 0; it < 30 && !held; ++it) {
    const Eigen::Matrix3Xd dx = pressing_motion(x, it);
    e.cover_step(x, dx);
    x += e.begin_line_search(x, dx) * dx;
    held = e.end_line_search(x);
    if (!e.still_valid(x)) e.refresh(x);
  }
  ASSERT_TRUE(held);
  const std::string state = e.save_state();
  auto t = two_sheets(contact("self_vertex_face", true, 0.01), 0.0015);
  ContactEffect& f = contact_of(t->simulation.effects[0]);
  f.load_state(state);
  EXPECT_EQ(energy(f, x), energy(e, x));
  auto u = two_sheets(contact("self_vertex_face", true, 0.01), 0.0015);
  ContactEffect& plain = contact_of(u->simulation.effects[0]);
  EXPECT_THROW(plain.load_state(state.substr(0, state.size() - 1)), std::invalid_argument);
  std::string low = state;
  const double half = 0.5;
  std::memcpy(low.data() + low.size() - sizeof half, &half, sizeof half);
  try {
    plain.load_state(low);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& err) {
    EXPECT_NE(std::string(err.what()).find("stiffening factor"), std::string::npos) << err.what();
  }
}

/// A 5 × 5 sheet (5 cm edges) `gap` above a box, falling onto it under gravity, with an
/// obstacle penalty far too soft for its weight (largest force 2 k d = 2e-4 N a vertex,
/// against ~1e-3 N).
std::unique_ptr<Scene> sheet_on_box(double gap, double min_separation) {
  json j = json::parse(R"({
    "dt": 0.01, "frames": 30,
    "obstacles": [{"name": "crate", "shape": "box", "half_extents": [0.3, 0.3, 0.05], "position": [0, 0, -0.05]}],
    "meshes": [{"name": "sheet", "generator": {"type": "grid", "width": 0.2, "height": 0.2, "nx": 5, "ny": 5},
                "density": 0.1}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "model": "arap", "stiffness": 20.0},
                {"type": "obstacle_contact", "penalty": {"type": "quadratic", "stiffness": 0.005, "distance": 0.02}}]
  })");
  j["meshes"][0]["transform"]["translation"] = {0.0, 0.0, gap};
  j["effects"][2]["min_separation"] = min_separation;
  return load_scene_text(j.dump(), "box.json", PCE_TEST_TMP);
}

TEST(SeparationFloor, EveryStepEndsWithTheSheetAboveTheBoxsFloor) {
  // The sheet lands on the box (frame ~3): every frame ends with every vertex at least
  // 0.01 d off the box, the vertices are held (pressed within three floors) and their
  // penalties stiffened, so the sheet rests just above that band. Without the floor the same
  // sheet sinks through the box's top.
  for (const double f : {0.01, 0.0}) {
    SCOPED_TRACE("min_separation " + std::to_string(f));
    auto s = sheet_on_box(0.01, f);
    Simulation& sim = s->simulation;
    double closest = std::numeric_limits<double>::infinity(), holds = 0;
    for (int frame = 1; frame <= sim.frames; ++frame) {
      const FrameStats st = sim.step();
      closest = std::min(closest, st.counters.at("obstacle_min_distance"));
      holds += st.counters.at("floor_holds");
      if (f > 0) {
        EXPECT_GE(st.counters.at("obstacle_min_distance"), f * kDistance) << "frame " << frame;
        EXPECT_FALSE(st.line_search_failures > 0 && st.newton_iterations == 1) << "frame " << frame << ": did not move";
      }
    }
    if (f > 0) {
      EXPECT_GT(holds, 0.0);
      EXPECT_LT(closest,
                4 * f * kDistance);  // it was pressed to the floor's band (held within 3 floors, then stiffened)
    } else {
      EXPECT_LT(closest, 0.0);
      EXPECT_EQ(holds, 0.0);
    }
  }
}

TEST(SeparationFloor, SceneKeyOutOfRangeNamesItsPath) {
  for (const double bad : {-0.1, 0.6}) {
    try {
      two_sheets(contact("self_vertex_face", true, bad), 0.01);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("effects[0].min_separation"), std::string::npos) << e.what();
    }
    try {
      sheet_on_box(0.01, bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("effects[2].min_separation"), std::string::npos) << e.what();
    }
  }
}

const std::filesystem::path kTestScenes = std::filesystem::path(PCE_SOURCE_DIR) / "tests" / "sim" / "scenes";

TEST(SeparationFloor, ASoftCrumplingSheetNeverIntersects) {
  // tests/sim/scenes/crumple_soft.json: examples/scenes/crumple.json with a penalty too
  // soft for its load (d = 0.6 edge, bending 1e-7, dropped upright from 15 cm). Without a
  // floor, 14 triangle pairs intersect at frame 32 and the state stops moving at frame 34.
  // Frames 1-36 (all 60: `pce-sim tests/sim/scenes/crumple_soft.json`, docs/simulation.md
  // §4.6): no intersecting triangle pair, no pair below its floor, no frame that does not
  // move; and pairs were held.
  auto scene = load_scene(kTestScenes / "crumple_soft.json");
  Simulation& sim = scene->simulation;
  const double floor = 0.01 * 0.012;
  double holds = 0;
  for (int f = 1; f <= 36; ++f) {
    const FrameStats st = sim.step();
    ASSERT_EQ(intersecting_triangle_pairs(sim.x, sim.model.triangles), 0) << "frame " << f;
    EXPECT_GE(std::min(st.counters.at("vertex_face_min_distance"), st.counters.at("edge_edge_min_distance")),
              floor * (1 - 1e-9))
        << "frame " << f;
    EXPECT_FALSE(st.line_search_failures > 0 && st.newton_iterations == 1) << "frame " << f << ": did not move";
    holds += st.counters.at("floor_holds");
  }
  EXPECT_GT(holds, 0.0);
}

TEST(SeparationFloor, ASheetPressedOntoABoxByAGrowingLoadStaysOffIt) {
  // tests/sim/scenes/press.json: a plate pinned to a target that moves 2 cm a second into
  // the box presses a sheet onto it. Every frame: no intersecting triangle pair, every
  // vertex at least its floor off the box and every self-contact pair at least its floor
  // apart; the contacts are held and stiffened as the load grows.
  auto scene = load_scene(kTestScenes / "press.json");
  Simulation& sim = scene->simulation;
  const double floor = 0.01 * 0.005;
  double holds = 0, stiffened = 0;
  for (int f = 1; f <= sim.frames; ++f) {
    const FrameStats st = sim.step();
    ASSERT_EQ(intersecting_triangle_pairs(sim.x, sim.model.triangles), 0) << "frame " << f;
    EXPECT_GE(st.counters.at("obstacle_min_distance"), floor * (1 - 1e-9)) << "frame " << f;
    EXPECT_GE(std::min(st.counters.at("vertex_face_min_distance"), st.counters.at("edge_edge_min_distance")),
              floor * (1 - 1e-9))
        << "frame " << f;
    holds += st.counters.at("floor_holds");
    stiffened = st.counters.at("stiffened_pairs");
  }
  EXPECT_GT(holds, 0.0);
  EXPECT_GT(stiffened, 0.0);
}

}  // namespace
