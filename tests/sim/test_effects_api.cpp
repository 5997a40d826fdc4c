// SPDX-License-Identifier: MIT
// The typed C++ builders (pce/sim/effects.hpp, build_model in pce/sim/model.hpp) and the
// runnable-state checks of Simulation::step: a scene using every effect type (with a
// keyframed obstacle and pin group) and its C++ transcription simulate bit for bit alike
// (the loader calls the same builders); every
// invalid argument throws one ArgumentError naming the field as the scene key would, and
// the scene loader reports the same fault at the JSON path; step() on an unrunnable
// simulation throws before it changes anything.
#include <pce/sim/effects.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

using namespace pce::sim;
using nlohmann::json;

namespace {

const char* const kScene = R"({
  "dt": 0.02, "frames": 14,
  "solver": {"tolerance": 1e-3, "broad_phase": "bullet", "threads": 1},
  "meshes": [
    {"name": "lower", "generator": {"type": "grid", "width": 0.5, "height": 0.5, "nx": 6, "ny": 6},
     "transform": {"translation": [0, 0, 0.12]}},
    {"name": "upper", "generator": {"type": "grid", "width": 0.5, "height": 0.5, "nx": 6, "ny": 6},
     "transform": {"translation": [0.01, 0.02, 0.135]}, "density": 0.2},
    {"name": "hair", "generator": {"type": "strands", "count": 2, "segments": 4, "length": 0.2, "spacing": 0.05},
     "transform": {"translation": [0, 0, 0.45]}, "linear_density": 0.01},
    {"name": "jelly", "generator": {"type": "tet_box", "size": [0.08, 0.08, 0.08], "n": [2, 2, 2]},
     "transform": {"translation": [0.15, 0.15, 0.2]}}
  ],
  "obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.1,
                 "motion": {"interpolation": "smooth", "keyframes": [{"time": 0},
                   {"time": 0.16, "translation": [0.02, 0.01, 0], "rotation": {"axis": [1, 1, 0], "degrees": 45}}]}}],
  "effects": [
    {"type": "gravity"},
    {"type": "stretching", "stiffness": 50},
    {"type": "bending", "stiffness": 0.001},
    {"type": "strand_stretching", "stiffness": 10},
    {"type": "strand_bending", "stiffness": 0.0001},
    {"type": "pins", "stiffness": 1e4, "groups": [
      {"mesh": "lower", "vertices": [0], "release_frame": 8, "motion": {"center": [0, 0, 0.12], "keyframes": [
        {"time": 0.04, "translation": [0, 0, 0.01]},
        {"time": 0.12, "translation": [0, 0, 0.03], "rotation": {"axis": [0, 0, 1], "degrees": 20}}]}},
      {"mesh": "hair", "box": {"min": [-1, -1, 0.449], "max": [1, 1, 1]}, "motion": {"velocity": [0.1, 0, 0]}}]},
    {"type": "damping", "coefficient": 0.1},
    {"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 1000, "distance": 0.01},
     "hessian": "exact", "area_weighted": true, "friction": {"coefficient": 0.4}},
    {"type": "self_edge_edge", "penalty": {"type": "cubic", "stiffness": 1000, "distance": 0.01, "delta": 0.002},
     "length": "signed", "friction": {"coefficient": 0.3, "slip_velocity": 0.002, "lagged_iterations": 2},
     "min_separation": 0.05},
    {"type": "obstacle_contact", "penalty": {"type": "log_barrier", "stiffness": 10, "distance": 0.01},
     "friction": {"coefficient": 0.5}, "min_separation": 0.02},
    {"type": "volume_elasticity", "young_modulus": 2e4, "poisson_ratio": 0.3}
  ]
})";

constexpr double kPi = 3.14159265358979323846;

Mesh moved(Mesh m, const Eigen::Vector3d& by) {
  m.positions.colwise() += by;
  return m;
}

/// kScene, written against the C++ API (with the solver's `mode`; block descent at 10 sweeps).
void transcribe(Simulation& sim, SolverMode mode) {
  std::vector<ModelMesh> meshes = {
      {"lower", moved(grid(0.5, 0.5, 6, 6), {0, 0, 0.12}), 0.1, 0.005},
      {"upper", moved(grid(0.5, 0.5, 6, 6), {0.01, 0.02, 0.135}), 0.2, 0.005},
      {"hair", moved(strands(2, 4, 0.2, 0.05, 0.0), {0, 0, 0.45}), 0.1, 0.01},
      {"jelly", moved(tet_box({0.08, 0.08, 0.08}, {2, 2, 2}), {0.15, 0.15, 0.2}), 1000, 0.005}};
  sim.model = build_model(meshes);
  // A rotation as the scene's {"axis", "degrees"} gives it.
  const auto rotation = [](const Eigen::Vector3d& axis, double degrees) {
    return Eigen::AngleAxisd(degrees * kPi / 180.0, axis.normalized()).toRotationMatrix();
  };
  Obstacle ball;
  ball.name = "ball";
  ball.radius = 0.1;
  ball.motion.interpolation = Interpolation::smooth;
  ball.motion.keyframes = {Keyframe{0.0}, Keyframe{0.16, {0.02, 0.01, 0}, rotation({1, 1, 0}, 45)}};
  sim.obstacles = {ball};
  sim.solver.dt = 0.02;
  sim.solver.tolerance = 1e-3;
  sim.solver.threads = 1;
  sim.solver.mode = mode;
  if (mode == SolverMode::block_descent) sim.solver.iterations = 10;
  sim.frames = 14;
  const Model& m = sim.model;
  std::vector<PinGroup> pins(2);
  pins[0].vertices = {m.meshes[0].first_vertex};
  pins[0].release_frame = 8;
  pins[0].motion = Motion{};
  pins[0].motion->keyframes = {Keyframe{0.04, {0, 0, 0.01}}, Keyframe{0.12, {0, 0, 0.03}, rotation({0, 0, 1}, 20)}};
  pins[0].centre = Eigen::Vector3d(0, 0, 0.12);
  pins[1].vertices = vertices_in_box(m, {-1, -1, 0.449}, {1, 1, 1}, "hair");
  pins[1].motion = Motion{};
  pins[1].motion->velocity = {0.1, 0, 0};
  ContactSettings vf;
  vf.penalty = {ContactPenalty::Kind::quadratic, 1000, 0.01, 0};
  vf.hessian = pce::Projection::exact;
  vf.broad_phase = BroadPhaseKind::bullet;
  vf.area_weighted = true;
  vf.friction = FrictionSettings{0.4};
  ContactSettings ee;
  ee.penalty = {ContactPenalty::Kind::cubic, 1000, 0.01, 0.002};
  ee.signed_length = true;
  ee.broad_phase = BroadPhaseKind::bullet;
  ee.friction = FrictionSettings{0.3, 0.002, 2};
  ee.min_separation = 0.05;
  sim.effects.push_back(make_gravity(m));
  sim.effects.push_back(make_stretching(m, 50));
  sim.effects.push_back(make_bending(m, 0.001));
  sim.effects.push_back(make_strand_stretching(m, 10));
  sim.effects.push_back(make_strand_bending(m, 0.0001));
  sim.effects.push_back(make_pins(m, pins, 1e4));
  sim.effects.push_back(make_damping(m, 0.1));
  sim.effects.push_back(make_self_vertex_face(m, vf));
  sim.effects.push_back(make_self_edge_edge(m, ee));
  ObstacleContactSettings oc;
  oc.penalty = {ContactPenalty::Kind::log_barrier, 10, 0.01, 0};
  oc.friction = FrictionSettings{0.5};
  oc.min_separation = 0.02;
  sim.effects.push_back(make_obstacle_contact(m, sim.obstacles, oc));
  sim.effects.push_back(make_volume_elasticity(m, pce::StableNeoHookean::from_young_poisson(2e4, 0.3)));
  sim.start_at_rest();
}

/// The field of the ArgumentError `f` throws ("(no error)" when none).
std::string field_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ArgumentError& e) {
    EXPECT_FALSE(e.expected().empty());
    EXPECT_EQ(std::string(e.what()), e.field().empty() ? e.expected() : e.field() + ": " + e.expected());
    return e.field();
  }
  return "(no error)";
}

/// The JSON path of the InputError loading `j` throws ("(no error)" when none).
std::string scene_error_at(const json& j) {
  try {
    load_scene_text(j.dump(), "api.json", PCE_TEST_TMP);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "api.json");
    return e.where();
  }
  return "(no error)";
}

Model small_cloth() { return build_model({{"cloth", grid(1.0, 1.0, 3, 3)}}); }

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// kScene with the solver's `mode` and its transcription simulate bit for bit alike, and
/// the comparison is not vacuous.
void expect_scene_and_transcription_alike(SolverMode mode) {
  json j = json::parse(kScene);
  j["solver"]["mode"] = std::string(pce::name_of(mode));
  if (mode == SolverMode::block_descent) j["solver"]["iterations"] = 10;
  auto scene = load_scene_text(j.dump(), "api.json", PCE_TEST_TMP);
  Simulation& a = scene->simulation;
  Simulation b;
  transcribe(b, mode);
  ASSERT_EQ(a.effects.size(), b.effects.size());
  for (std::size_t k = 0; k < a.effects.size(); ++k) EXPECT_STREQ(a.effects[k]->name(), b.effects[k]->name());
  EXPECT_EQ(a.model.rest, b.model.rest);
  EXPECT_EQ(a.model.mass, b.model.mass);
  EXPECT_EQ(a.model.edges, b.model.edges);
  double obstacle = 0, self = 0, pinned_after_release = 0, friction = 0;
  for (int f = 1; f <= 14; ++f) {
    const FrameStats sa = a.step(), sb = b.step();
    ASSERT_EQ(a.x, b.x) << "frame " << f;  // exact equality: same builders, same arithmetic
    ASSERT_EQ(a.v, b.v) << "frame " << f;
    EXPECT_EQ(sa.newton_iterations, sb.newton_iterations);
    for (const char* key : {"obstacle_contacts", "vertex_face_contacts", "edge_edge_contacts", "pinned_vertices",
                            "obstacle_friction_contacts", "vertex_face_friction_contacts",
                            "edge_edge_friction_contacts", "inverted_tetrahedra", "volume_ratio"})
      EXPECT_EQ(sa.counters.at(key), sb.counters.at(key)) << key << ", frame " << f;
    friction += sa.counters.at("obstacle_friction_contacts") + sa.counters.at("vertex_face_friction_contacts") +
                sa.counters.at("edge_edge_friction_contacts");
    obstacle += sa.counters.at("obstacle_contacts");
    self += sa.counters.at("vertex_face_contacts") + sa.counters.at("edge_edge_contacts");
    if (f >= 8) pinned_after_release = sa.counters.at("pinned_vertices");
  }
  // The comparison is not vacuous: contacts of both kinds happened, and the release did.
  EXPECT_GT(obstacle, 0);
  EXPECT_GT(self, 0);
  EXPECT_GT(friction, 0);
  EXPECT_EQ(pinned_after_release, 2);  // the two hair roots; the lower sheet's corner is released
  EXPECT_TRUE(a.x.allFinite());
}

}  // namespace

TEST(EffectsApi, SceneAndItsCppTranscriptionSimulateBitForBitAlike) {
  expect_scene_and_transcription_alike(SolverMode::newton);
}

TEST(EffectsApi, BlockDescentSceneAndItsCppTranscriptionSimulateBitForBitAlike) {
  expect_scene_and_transcription_alike(SolverMode::block_descent);
}

TEST(EffectsApi, ElasticBuildersNameTheBadField) {
  const Model m = small_cloth();
  const Model hair = build_model({{"hair", strands(1, 3, 1.0, 0.1, 0.0)}});
  EXPECT_EQ(field_of([&] { make_gravity(m, {0, kNaN, 0}); }), "acceleration");
  EXPECT_EQ(field_of([&] { make_stretching(m, 0); }), "stiffness");
  EXPECT_EQ(field_of([&] { make_stretching(m, kNaN); }), "stiffness");
  EXPECT_EQ(field_of([&] { make_bending(m, -1); }), "stiffness");
  EXPECT_EQ(field_of([&] { make_strand_stretching(hair, std::numeric_limits<double>::infinity()); }), "stiffness");
  EXPECT_EQ(field_of([&] { make_strand_bending(hair, 0); }), "stiffness");
  EXPECT_EQ(field_of([&] { make_damping(m, -0.5); }), "coefficient");
  EXPECT_EQ(field_of([&] { make_damping(m, 0); }), "(no error)");
  // A collapsed rest triangle: the whole input is at fault (no field).
  Model flat = m;
  flat.rest.col(1) = flat.rest.col(0);
  EXPECT_EQ(field_of([&] { make_stretching(flat, 1); }), "");
}

TEST(EffectsApi, PinBuildersNameTheBadField) {
  const Model m = small_cloth();  // 16 vertices
  const auto pins = [&](PinGroup g) { make_pins(m, {PinGroup{{0}}, std::move(g)}); };
  EXPECT_EQ(field_of([&] { make_pins(m, {}); }), "groups");
  EXPECT_EQ(field_of([&] { make_pins(m, {PinGroup{{0}}}, 0); }), "stiffness");
  EXPECT_EQ(field_of([&] { pins(PinGroup{}); }), "groups[1].vertices");
  EXPECT_EQ(field_of([&] { pins(PinGroup{{3, 16}}); }), "groups[1].vertices[1]");
  EXPECT_EQ(field_of([&] { pins(PinGroup{{-1}}); }), "groups[1].vertices[0]");
  EXPECT_EQ(field_of([&] { pins(PinGroup{{3}, -2}); }), "groups[1].release_frame");
  PinGroup late{{3}};
  late.motion = Motion{};
  late.motion->start = 2;
  late.motion->stop = 1;
  EXPECT_EQ(field_of([&] { pins(late); }), "groups[1].motion.stop");
  late.motion->stop = 3;
  late.centre = Eigen::Vector3d(0, kNaN, 0);
  EXPECT_EQ(field_of([&] { pins(late); }), "groups[1].motion.center");
  PinGroup lifted{{3}};
  lifted.motion = Motion{};
  lifted.motion->keyframes = {Keyframe{0.0}, Keyframe{0.5, {0, 0, 0.2}}, Keyframe{1.0}};
  EXPECT_EQ(field_of([&] { pins(lifted); }), "(no error)");
  lifted.motion->keyframes[2].time = 0.5;
  EXPECT_EQ(field_of([&] { pins(lifted); }), "groups[1].motion.keyframes[2].time");
  lifted.motion->keyframes[2].time = kNaN;
  EXPECT_EQ(field_of([&] { pins(lifted); }), "groups[1].motion.keyframes[2].time");
  lifted.motion->keyframes[2].time = 1.0;
  lifted.motion->keyframes[1].translation.z() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(field_of([&] { pins(lifted); }), "groups[1].motion.keyframes[1].translation");
  lifted.motion->keyframes[1].translation.z() = 0.2;
  lifted.motion->velocity.x() = 0.1;
  EXPECT_EQ(field_of([&] { pins(lifted); }), "groups[1].motion.velocity");
  EXPECT_EQ(field_of([&] { vertices_in_box(m, {0, 0, 1}, {1, 1, 0}); }), "max");
  EXPECT_EQ(field_of([&] { vertices_in_box(m, {0, 0, 0}, {1, 1, 1}, "nope"); }), "mesh");
  EXPECT_EQ(vertices_in_box(m, {-0.51, -0.51, 0}, {-0.49, 0.51, 0}, "cloth"), (std::vector<int>{0, 4, 8, 12}));
}

TEST(EffectsApi, ContactBuildersNameTheBadField) {
  const Model m = small_cloth();
  ContactSettings ok;
  ok.penalty = {ContactPenalty::Kind::quadratic, 1e3, 0.01, 0};
  const auto vf = [&](const std::function<void(ContactSettings&)>& change) {
    ContactSettings s = ok;
    change(s);
    make_self_vertex_face(m, s);
  };
  EXPECT_EQ(field_of([&] { vf([](ContactSettings&) {}); }), "(no error)");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.penalty.stiffness = 0; }); }), "penalty.stiffness");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.penalty.distance = kNaN; }); }), "penalty.distance");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.penalty.delta = 0.001; }); }), "penalty.delta");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.hessian = pce::Projection::none; }); }), "hessian");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.signed_length = s.closest_features = true; }); }), "length");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.penalty.kind = ContactPenalty::Kind::log_barrier; }); }),
            "closest_features");
  const Model hair = build_model({{"hair", strands(1, 1, 1.0, 0.1, 0.0)}});  // one segment, no triangles
  EXPECT_EQ(field_of([&] { make_self_vertex_face(hair, ok); }), "");
  EXPECT_EQ(field_of([&] { make_self_edge_edge(hair, ok); }), "");
  // friction and area weighting
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.friction = FrictionSettings{0.3}; }); }), "(no error)");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.friction = FrictionSettings{-0.1}; }); }),
            "friction.coefficient");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.friction = FrictionSettings{kNaN}; }); }),
            "friction.coefficient");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) {
                             s.friction = FrictionSettings{0.3, 0.0};
                           }); }),
            "friction.slip_velocity");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) {
                             s.friction = FrictionSettings{0.3, 1e-3, 0};
                           }); }),
            "friction.lagged_iterations");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.area_weighted = true; }); }), "(no error)");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.min_separation = 0.5; }); }), "(no error)");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.min_separation = 0.6; }); }), "min_separation");
  EXPECT_EQ(field_of([&] { vf([](ContactSettings& s) { s.min_separation = kNaN; }); }), "min_separation");
  const Model mixed = build_model({{"cloth", grid(1.0, 1.0, 3, 3)}, {"hair", strands(1, 2, 1.0, 0.1, 0.0)}});
  ContactSettings weighted = ok;
  weighted.area_weighted = true;
  EXPECT_EQ(field_of([&] { make_self_vertex_face(mixed, weighted); }), "(no error)");   // faces have area
  EXPECT_EQ(field_of([&] { make_self_edge_edge(mixed, weighted); }), "area_weighted");  // segments have none
  ObstacleContactSettings on_mixed;
  on_mixed.penalty = {ContactPenalty::Kind::quadratic, 10, 0.01, 0};
  on_mixed.area_weighted = true;
  EXPECT_EQ(field_of([&] { make_obstacle_contact(mixed, {}, on_mixed); }), "area_weighted");
  ObstacleContactSettings below;
  below.penalty = {ContactPenalty::Kind::quadratic, 10, 0.01, 0};
  below.min_separation = -0.01;
  EXPECT_EQ(field_of([&] { make_obstacle_contact(mixed, {}, below); }), "min_separation");
  EXPECT_EQ(field_of([&] { make_obstacle_contact(m, {}, on_mixed); }), "(no error)");
  on_mixed.friction = FrictionSettings{0.2, 2e6};
  EXPECT_EQ(field_of([&] { make_obstacle_contact(m, {}, on_mixed); }), "friction.slip_velocity");

  Obstacle ball;
  ball.name = "ball";
  ball.radius = 0.1;
  const ContactPenalty penalty{ContactPenalty::Kind::cubic, 10, 0.01, 0.001};
  const auto with = [&](const std::function<void(Obstacle&)>& change) {
    Obstacle o = ball;
    change(o);
    make_obstacle_contact({ball, o}, penalty);
  };
  EXPECT_EQ(field_of([&] { with([](Obstacle&) {}); }), "(no error)");
  EXPECT_EQ(field_of([&] { with([](Obstacle& o) { o.radius = 0; }); }), "obstacles[1].radius");
  EXPECT_EQ(field_of([&] { with([](Obstacle& o) { o.kind = ShapeKind::box; }); }), "obstacles[1].half_extents");
  EXPECT_EQ(field_of([&] { with([](Obstacle& o) { o.kind = ShapeKind::capsule; }); }), "obstacles[1].half_length");
  EXPECT_EQ(field_of([&] { with([](Obstacle& o) { o.kind = ShapeKind::mesh; }); }), "obstacles[1].mesh");
  EXPECT_EQ(field_of([&] { with([](Obstacle& o) { o.position.x() = kNaN; }); }), "obstacles[1].position");
  EXPECT_EQ(field_of([&] { with([](Obstacle& o) { o.rotation(0, 0) = 2; }); }), "obstacles[1].rotation");
  EXPECT_EQ(field_of([&] { with([](Obstacle& o) { o.motion.stop = -1; }); }), "obstacles[1].motion.stop");
  // Keyframes: each fault names its field, as the scene key would.
  const auto keyed = [&](const std::function<void(Motion&)>& change) {
    with([&](Obstacle& o) {
      o.motion.keyframes = {Keyframe{0.0}, Keyframe{0.5, {0, 0, 0.2}}};
      change(o.motion);
    });
  };
  EXPECT_EQ(field_of([&] { keyed([](Motion&) {}); }), "(no error)");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.keyframes[1].time = 0; }); }),
            "obstacles[1].motion.keyframes[1].time");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.keyframes[0].time = -0.1; }); }),
            "obstacles[1].motion.keyframes[0].time");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.keyframes[1].time = kNaN; }); }),
            "obstacles[1].motion.keyframes[1].time");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.keyframes[1].time = std::numeric_limits<double>::infinity(); }); }),
            "obstacles[1].motion.keyframes[1].time");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.keyframes[1].translation.y() = kNaN; }); }),
            "obstacles[1].motion.keyframes[1].translation");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.keyframes[1].translation.y() = 2e6; }); }),
            "obstacles[1].motion.keyframes[1].translation");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.keyframes[0].rotation(1, 1) = -1; }); }),  // a mirror
            "obstacles[1].motion.keyframes[0].rotation");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.velocity.z() = 1; }); }), "obstacles[1].motion.velocity");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.angular_velocity.x() = 1; }); }),
            "obstacles[1].motion.angular_velocity");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.start = 1; }); }), "obstacles[1].motion.start");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.stop = 1; }); }), "obstacles[1].motion.stop");
  EXPECT_EQ(field_of([&] { keyed([](Motion& k) { k.interpolation = static_cast<Interpolation>(7); }); }),
            "obstacles[1].motion.interpolation");
  EXPECT_EQ(field_of([&] {
              make_obstacle_contact({ball}, {ContactPenalty::Kind::quadratic, 10, 0, 0});
            }),
            "penalty.distance");
}

TEST(EffectsApi, BuildModelNamesTheBadMesh) {
  const Mesh g = grid(1.0, 1.0, 2, 2);
  EXPECT_EQ(field_of([&] { build_model({}); }), "meshes");
  EXPECT_EQ(field_of([&] { build_model({{"a", g}, {"", g}}); }), "meshes[1].name");
  EXPECT_EQ(field_of([&] { build_model({{"a", g}, {"a", g}}); }), "meshes[1].name");
  EXPECT_EQ(field_of([&] { build_model({{"a", g, 0.0}}); }), "meshes[0].density");
  EXPECT_EQ(field_of([&] { build_model({{"a", g, 0.1, kNaN}}); }), "meshes[0].linear_density");
  Mesh broken = g;
  broken.triangles(2, 3) = 99;
  EXPECT_EQ(field_of([&] { build_model({{"a", g}, {"b", broken}}); }), "meshes[1]");
  Mesh lonely = g;  // a vertex in no element has no mass
  lonely.positions.conservativeResize(3, lonely.positions.cols() + 1);
  lonely.positions.rightCols<1>().setZero();
  EXPECT_EQ(field_of([&] { build_model({{"a", lonely}}); }), "meshes[0]");
  const Model m = build_model({{"a", g, 0.3}, {"b", strands(1, 2, 1.0, 0.1, 0.0), 0.1, 0.02}});
  EXPECT_NEAR(m.mass.sum(), 0.3 * 1.0 + 0.02 * 1.0, 1e-12);
  EXPECT_EQ(m.meshes[1].first_vertex, 9);
  EXPECT_EQ(m.edges.cols(), 16 + 2);  // a 2×2 grid's 16 unique edges, then the 2 segments
}

// The loader turns a builder's field into the JSON path, nested fields included.
TEST(EffectsApi, SceneErrorsFromTheBuildersNameTheJsonPath) {
  const json base = json::parse(kScene);
  json j = base;
  j["effects"][5]["groups"][1]["box"] = {{"min", {0, 0, 1}}, {"max", {1, 1, 0}}};
  EXPECT_EQ(scene_error_at(j), "effects[5].groups[1].box.max");
  j = base;
  j["effects"][9]["friction"]["coefficient"] = -1;
  EXPECT_EQ(scene_error_at(j), "effects[9].friction.coefficient");
  j = base;
  j["effects"][8]["friction"]["lagged_iterations"] = 0;
  EXPECT_EQ(scene_error_at(j), "effects[8].friction.lagged_iterations");
  j = base;
  j["effects"][7]["friction"]["slip_velocity"] = 0;
  EXPECT_EQ(scene_error_at(j), "effects[7].friction.slip_velocity");
  j = base;
  j["effects"][7]["friction"]["static"] = 0.5;
  EXPECT_EQ(scene_error_at(j), "effects[7].friction.static");
  j = base;
  j["effects"][7]["friction"].erase("coefficient");
  EXPECT_EQ(scene_error_at(j), "effects[7].friction.coefficient");
  j = base;
  j["effects"][8]["area_weighted"] = true;  // the hair's segments have no area
  EXPECT_EQ(scene_error_at(j), "effects[8].area_weighted");
  j = base;
  j["effects"][9]["area_weighted"] = "yes";
  EXPECT_EQ(scene_error_at(j), "effects[9].area_weighted");
  const json hair = json::parse(R"({
    "dt": 0.02, "frames": 1,
    "meshes": [{"name": "hair", "generator": {"type": "strands", "count": 2, "segments": 2, "length": 1, "spacing": 1}}],
    "effects": [{"type": "gravity"},
                {"type": "self_vertex_face", "penalty": {"type": "quadratic", "stiffness": 1, "distance": 0.1}}]
  })");
  EXPECT_EQ(scene_error_at(hair), "effects[1]");  // no triangles: the builder's whole-input fault
  j = hair;
  j["effects"][1]["type"] = "self_edge_edge";
  EXPECT_EQ(scene_error_at(j), "(no error)");
}

TEST(EffectsApi, DampingBeforeTheFirstStepIsZero) {
  const Model m = small_cloth();
  auto d = make_damping(m, 2.0);
  Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, m.vertex_count());
  const Eigen::Matrix3Xd x = m.rest.array() + 0.1;
  EXPECT_EQ(d->evaluate(x, &g, nullptr), 0.0);
  EXPECT_EQ(g.norm(), 0.0);
}

TEST(EffectsApi, StepRefusesAnUnrunnableSimulationAndChangesNothing) {
  Simulation sim;
  EXPECT_EQ(field_of([&] { sim.step(); }), "model");
  sim.model = small_cloth();
  sim.effects.push_back(make_gravity(sim.model));
  EXPECT_EQ(field_of([&] { sim.step(); }), "x");  // x, v not set
  sim.start_at_rest();
  sim.solver.dt = 0;
  EXPECT_EQ(field_of([&] { sim.step(); }), "solver.dt");
  sim.solver.dt = 0.01;
  sim.solver.tolerance = kNaN;
  EXPECT_EQ(field_of([&] { sim.step(); }), "solver.tolerance");
  sim.solver.tolerance = 1e-2;
  sim.model.mass[3] = 0;
  EXPECT_EQ(field_of([&] { sim.step(); }), "model.mass");
  sim.model.mass[3] = 0.1;
  sim.effects.emplace_back();
  EXPECT_EQ(field_of([&] { sim.step(); }), "effects[1]");
  EXPECT_EQ(sim.frame, 0);
  EXPECT_EQ(sim.x, sim.model.rest);  // nothing moved
  sim.effects.pop_back();
  EXPECT_EQ(field_of([&] { sim.step(); }), "(no error)");
  EXPECT_EQ(sim.frame, 1);
  EXPECT_LT(sim.x.row(2).maxCoeff(), 0.0);
}
