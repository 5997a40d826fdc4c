// SPDX-License-Identifier: MIT
// Effects per mesh (scene key `meshes`, `restrict_to_meshes`, docs/simulation.md §2.5):
// the restricted model keeps the vertices and only the named meshes' elements (naming every
// mesh gives the model itself); two cloth materials in one scene each act on their own sheet,
// which stretches by the ratio of the stiffnesses; per-mesh friction on one slope lets one
// sheet slide as Coulomb says while the other sticks, through obstacle contact and through
// self contact given as mesh pairs; overlaps, gaps and entries naming meshes without the
// type's elements are errors naming both entries (a pins entry's meshes narrow what its groups
// pin); and a scene with such entries simulates bit for bit as its C++ transcription.
#include <pce/sim/effects.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/scene.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <array>
#include <cstring>
#include <initializer_list>
#include <functional>
#include <string>
#include <vector>

using namespace pce::sim;
using nlohmann::json;

namespace {

Model three_meshes() {
  return build_model({{"cloth", grid(0.2, 0.2, 2, 2), 0.1, 0.005},
                      {"hair", strands(2, 3, 0.1, 0.05), 0.1, 0.005},
                      {"jelly", tet_box(Eigen::Vector3d(0.1, 0.1, 0.1), Eigen::Vector3i(1, 1, 1)), 500.0, 0.005}});
}

/// `"meshes"` as pairs of names (an initializer list of pairs would be read as a JSON object).
json pairs(std::initializer_list<std::array<const char*, 2>> list) {
  json out = json::array();
  for (const auto& p : list) out.push_back(json::array({p[0], p[1]}));
  return out;
}

/// The error a scene gives, or "" when it loads.
std::string error_of(const json& scene) {
  try {
    load_scene_text(scene.dump(), "meshes.json", PCE_TEST_TMP);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(EffectMeshes, TheRestrictedModelKeepsTheVerticesAndOnlyTheNamedElements) {
  const Model m = three_meshes();
  const MeshRange &cloth = m.meshes[0], &hair = m.meshes[1], &jelly = m.meshes[2];
  ASSERT_GT(jelly.tetrahedron_count, 0);
  const Model v = restrict_to_meshes(m, {"jelly", "cloth"});
  EXPECT_EQ(v.rest, m.rest);
  EXPECT_EQ(v.triangles.cols(), cloth.triangle_count + jelly.triangle_count);
  EXPECT_EQ(v.triangles.leftCols(cloth.triangle_count), m.triangles.leftCols(cloth.triangle_count));
  EXPECT_EQ(v.segments.cols(), 0);
  EXPECT_EQ(v.tetrahedra, m.tetrahedra);
  EXPECT_EQ(v.edges, unique_edges(v.triangles));
  for (int i = 0; i < m.vertex_count(); ++i) {
    const bool in_hair = i >= hair.first_vertex && i < hair.first_vertex + hair.vertex_count;
    EXPECT_EQ(v.mass[i], in_hair ? 0.0 : m.mass[i]) << i;
    EXPECT_EQ(v.is_surface_vertex(i), !in_hair && m.is_surface_vertex(i)) << i;
  }
  ASSERT_EQ(v.meshes.size(), 3u);
  EXPECT_EQ(v.meshes[1].segment_count, 0);
  EXPECT_EQ(v.meshes[2].first_triangle, cloth.triangle_count);
  for (Eigen::Index t = 0; t < v.triangles.cols(); ++t)
    EXPECT_EQ(v.is_boundary_triangle(t), t >= cloth.triangle_count) << t;
  // Every mesh named: the model itself.
  const Model all = restrict_to_meshes(m, {"hair", "jelly", "cloth"});
  EXPECT_EQ(all.triangles, m.triangles);
  EXPECT_EQ(all.segments, m.segments);
  EXPECT_EQ(all.edges, m.edges);
  EXPECT_EQ(all.mass, m.mass);
  EXPECT_EQ(all.boundary_triangle, m.boundary_triangle);
  // Bad names.
  for (const std::vector<std::string>& names :
       {std::vector<std::string>{}, std::vector<std::string>{"nope"}, std::vector<std::string>{"hair", "hair"}}) {
    try {
      restrict_to_meshes(m, names);
      ADD_FAILURE() << "no error";
    } catch (const ArgumentError& e) {
      EXPECT_EQ(e.field(), "meshes");
    }
  }
}

namespace {

/// Two 0.2 m × 0.4 m strips (5 × 9 vertices) hanging from their top edges side by side,
/// each with its own stretching entry (μ_a, μ_b), under gravity with damping.
json two_strips(double mu_a, double mu_b) {
  const auto strip = [](const char* name, double x) {
    return json{{"name", name},
                {"generator", {{"type", "grid"}, {"width", 0.2}, {"height", 0.4}, {"nx", 4}, {"ny", 8}}},
                {"transform", {{"rotation", {{"axis", {1, 0, 0}}, {"degrees", 90}}}, {"translation", {x, 0, 0}}}}};
  };
  const auto top = [](const char* mesh) {
    return json{{"mesh", mesh}, {"box", {{"min", {-5, -5, 0.199}}, {"max", {5, 5, 0.201}}}}};
  };
  return {{"dt", 0.02},
          {"frames", 150},
          {"solver", {{"tolerance", 1e-5}, {"threads", 1}}},
          {"meshes", {strip("a", -0.3), strip("b", 0.3)}},
          {"effects",
           {{{"type", "gravity"}},
            {{"type", "stretching"}, {"meshes", {"a"}}, {"stiffness", mu_a}},
            {{"type", "stretching"}, {"meshes", {"b"}}, {"stiffness", mu_b}},
            {{"type", "damping"}, {"coefficient", 4.0}},
            {{"type", "pins"}, {"groups", {top("a"), top("b")}}}}}};
}

/// How far each strip's bottom edge hangs below its rest height after the run.
std::pair<double, double> sag(const json& scene) {
  auto s = load_scene_text(scene.dump(), "strips.json", PCE_TEST_TMP);
  Simulation& sim = s->simulation;
  for (int f = 0; f < scene["frames"].get<int>(); ++f) sim.step();
  const auto bottom = [&](int mesh) {
    const MeshRange& r = sim.model.meshes[static_cast<std::size_t>(mesh)];
    double drop = 0;
    for (int i = r.first_vertex; i < r.first_vertex + 5; ++i) drop += sim.model.rest(2, i) - sim.x(2, i);
    return drop / 5;
  };
  return {bottom(0), bottom(1)};
}

}  // namespace

TEST(EffectMeshes, TwoClothMaterialsStretchEachTheirSheetByTheStiffnessRatio) {
  // Hanging under its own weight, a membrane's small displacements are the load over the
  // stiffness: the strip four times stiffer sags a quarter as far (to geometric
  // non-linearity, ~1 % at these strains); with one material for both they sag alike.
  const auto [a, b] = sag(two_strips(20.0, 80.0));
  const auto [a1, a2] = sag(two_strips(20.0, 20.0));
  std::printf("sag: mu 20: %.4e m, mu 80: %.4e m (ratio %.4f); both mu 20: %.4e / %.4e m\n", a, b, a / b, a1, a2);
  EXPECT_GT(b, 0.0);
  EXPECT_NEAR(a / b, 4.0, 0.1);
  EXPECT_NEAR(a1, a2, 1e-9);  // mirror images
  EXPECT_NEAR(a, a1, 1e-6);   // strip a does not feel b's material
}

namespace {

constexpr double kG = 9.81;
const double kRad = 20.0 * M_PI / 180.0;

/// Two 0.2 m sheets (5 × 5 vertices) side by side on the 20° slope, resting at their depth:
/// on a tilted box (obstacle contact, one entry per sheet with its own μ) or on a pinned
/// tilted sheet ("floor": self vertex-face contact, one entry per (floor, sheet) pair with
/// its μ and one frictionless entry for the other pairs).
json two_sheets_on_a_slope(bool on_box, double mu_a, double mu_b) {
  const double mass = 0.1 * 0.04 / 25, rest = 0.01 - mass * kG * std::cos(kRad) / (2 * 80.0);
  const auto at = [&](double s, double y, double h) {
    return std::vector<double>{s * std::cos(kRad) + h * std::sin(kRad), y, -s * std::sin(kRad) + h * std::cos(kRad)};
  };
  const auto sheet = [&](const char* name, double y, double base) {
    return json{{"name", name},
                {"generator", {{"type", "grid"}, {"width", 0.2}, {"height", 0.2}, {"nx", 4}, {"ny", 4}}},
                {"transform",
                 {{"rotation", {{"axis", {0, 1, 0}}, {"degrees", 20.0}}}, {"translation", at(-0.3, y, base + rest)}}}};
  };
  const json penalty = {{"type", "quadratic"}, {"stiffness", 80.0}, {"distance", 0.01}};
  const auto friction = [](double mu) { return json{{"coefficient", mu}, {"slip_velocity", 1e-3}}; };
  json effects = {
      {{"type", "gravity"}}, {{"type", "stretching"}, {"stiffness", 60.0}}, {{"type", "bending"}, {"stiffness", 2e-5}}};
  json scene = {
      {"dt", 0.01}, {"frames", 50}, {"solver", {{"tolerance", 1e-4}, {"max_iterations", 50}, {"threads", 1}}}};
  if (on_box) {
    scene["meshes"] = {sheet("a", -0.15, 0.05), sheet("b", 0.15, 0.05)};
    scene["obstacles"] = {{{"name", "ramp"},
                           {"shape", "box"},
                           {"half_extents", {3, 1, 0.05}},
                           {"rotation", {{"axis", {0, 1, 0}}, {"degrees", 20.0}}}}};
    effects.push_back(
        {{"type", "obstacle_contact"}, {"meshes", {"a"}}, {"penalty", penalty}, {"friction", friction(mu_a)}});
    effects.push_back(
        {{"type", "obstacle_contact"}, {"meshes", {"b"}}, {"penalty", penalty}, {"friction", friction(mu_b)}});
  } else {
    json floor = {{"name", "floor"},
                  {"generator", {{"type", "grid"}, {"width", 1.2}, {"height", 0.8}, {"nx", 12}, {"ny", 8}}},
                  {"transform", {{"rotation", {{"axis", {0, 1, 0}}, {"degrees", 20.0}}}}}};
    scene["meshes"] = {floor, sheet("a", -0.2, 0.0), sheet("b", 0.2, 0.0)};
    effects.push_back(
        {{"type", "pins"}, {"groups", {{{"mesh", "floor"}, {"box", {{"min", {-5, -5, -5}}, {"max", {5, 5, 5}}}}}}}});
    const auto vf = [&](const json& pairs) {
      return json{{"type", "self_vertex_face"}, {"meshes", pairs}, {"penalty", penalty}, {"closest_features", true}};
    };
    json with_a = vf(pairs({{"floor", "a"}})), with_b = vf(pairs({{"floor", "b"}}));
    with_a["friction"] = friction(mu_a);
    with_b["friction"] = friction(mu_b);
    effects.push_back(with_a);
    effects.push_back(with_b);
    effects.push_back(vf(pairs({{"floor", "floor"}, {"a", "a"}, {"b", "b"}, {"a", "b"}})));
  }
  scene["effects"] = effects;
  return scene;
}

/// Down-slope travel of mesh `k`'s centroid over the run.
double downhill(const json& scene, int k) {
  auto s = load_scene_text(scene.dump(), "slope.json", PCE_TEST_TMP);
  Simulation& sim = s->simulation;
  const MeshRange& r = sim.model.meshes[static_cast<std::size_t>(k)];
  const Eigen::Vector3d c0 = sim.x.middleCols(r.first_vertex, r.vertex_count).rowwise().mean();
  for (int f = 0; f < scene["frames"].get<int>(); ++f) sim.step();
  const Eigen::Vector3d d = sim.x.middleCols(r.first_vertex, r.vertex_count).rowwise().mean() - c0;
  return d.x() * std::cos(kRad) - d.z() * std::sin(kRad);
}

}  // namespace

TEST(EffectMeshes, PerMeshFrictionLetsOneSheetSlideAndTheOtherStick) {
  // μ_a = 0.1 < tan 20° slides with g(sin θ − μ cos θ) (backward Euler from rest: × (1 + h/T),
  // T = 0.5 s, to 1 %); μ_b = 0.6 > tan 20° sticks, creeping no faster than the mollified
  // static friction's ε_v(1 − √(1 − tan θ/μ)).
  const double T = 0.5, lag = 1 + 0.01 / T, expected = kG * (std::sin(kRad) - 0.1 * std::cos(kRad));
  for (const bool on_box : {true, false}) {
    SCOPED_TRACE(on_box ? "obstacle contact per mesh" : "self contact per mesh pair");
    const json scene = two_sheets_on_a_slope(on_box, 0.1, 0.6);
    const int a = on_box ? 0 : 1;
    const double slid = downhill(scene, a), stuck = downhill(scene, a + 1);
    std::printf("%s: sheet a (mu 0.1) a = %.4f m/s^2 (expected %.4f), sheet b (mu 0.6) %.3e m\n",
                on_box ? "box" : "floor", 2 * slid / (T * T), lag * expected, stuck);
    EXPECT_NEAR(2 * slid / (T * T), lag * expected, (on_box ? 0.01 : 0.05) * expected);
    const double creep = 1e-3 * (1 - std::sqrt(1 - std::tan(kRad) / 0.6));  // ε_v(1 − √(1 − tan θ/μ))
    EXPECT_LT(stuck, 1.05 * creep * T);
    EXPECT_GT(stuck, 0.0);
  }
}

TEST(EffectMeshes, OverlapsGapsAndMeshesWithoutTheElementsNameTheEntries) {
  const json base = two_strips(20, 80);
  const auto with = [&](const std::function<void(json&)>& change) {
    json s = base;
    change(s["effects"]);
    return error_of(s);
  };
  EXPECT_EQ(error_of(base), "");
  // Overlap: b in two stretching entries.
  EXPECT_EQ(with([](json& e) {
              e[2]["meshes"] = {"b", "a"};
            }),
            "meshes.json: effects[2].meshes: mesh \"a\" is also covered by effects[1] (stretching): each takes one "
            "stretching entry (name each entry's \"meshes\")");
  // An entry without meshes overlaps every other.
  EXPECT_NE(with([](json& e) { e[2].erase("meshes"); }).find("effects[2]: mesh \"a\" is also covered by effects[1]"),
            std::string::npos);
  // Gap: b in no stretching entry.
  EXPECT_EQ(with([](json& e) { e.erase(2); }),
            "meshes.json: effects[1].meshes: mesh \"b\" (with cloth triangles) is in no stretching entry "
            "(effects[1]): name it in one");
  // Unknown, repeated, empty, pairs where names are expected.
  EXPECT_NE(with([](json& e) { e[2]["meshes"] = {"c"}; }).find("effects[2].meshes[0]: unknown mesh \"c\""),
            std::string::npos);
  EXPECT_NE(with([](json& e) {
              e[2]["meshes"] = {"b", "b"};
            }).find("effects[2].meshes[1]: mesh \"b\" named twice"),
            std::string::npos);
  EXPECT_NE(with([](json& e) { e[2]["meshes"] = json::array(); }).find("effects[2].meshes: expected at least one"),
            std::string::npos);
  EXPECT_NE(with([](json& e) {
              e[2]["meshes"] = pairs({{"a", "b"}});
            }).find("pairs are for self contact"),
            std::string::npos);
  // pins: `meshes` narrows what its groups may pin.
  EXPECT_EQ(with([](json& e) { e[4]["meshes"] = {"a", "b"}; }), "");
  EXPECT_EQ(with([](json& e) { e[4]["meshes"] = {"a"}; }),
            "meshes.json: effects[4].groups[1].mesh: mesh \"b\" is not one of the entry's meshes (\"a\")");
  EXPECT_NE(with([](json& e) {
              e[4]["meshes"] = {"a"};
              e[4]["groups"][1].erase("mesh");
              e[4]["groups"][1]["box"]["min"] = {0.2, -5, 0.199};  // only b's top edge
            }).find("effects[4].groups[1].box: the box contains no vertex of the entry's meshes (\"a\") at rest"),
            std::string::npos);
  // A mesh without the type's elements: strand stretching on a cloth.
  EXPECT_NE(with([](json& e) {
              e.push_back({{"type", "strand_stretching"}, {"meshes", {"a"}}, {"stiffness", 1.0}});
            }).find("effects[5].meshes: mesh \"a\" has no segments for strand_stretching"),
            std::string::npos);
  // Self contact: the pair (a, b) in two entries; the pair (b, b) in none.
  EXPECT_NE(with([](json& e) {
              const json p = {{"type", "quadratic"}, {"stiffness", 10.0}, {"distance", 0.01}};
              e.push_back({{"type", "self_edge_edge"}, {"meshes", {"a", "b"}}, {"penalty", p}});
              e.push_back({{"type", "self_edge_edge"}, {"meshes", pairs({{"b", "a"}})}, {"penalty", p}});
            }).find("effects[6].meshes: the mesh pair [\"a\", \"b\"] is also covered by effects[5] (self_edge_edge)"),
            std::string::npos);
  EXPECT_NE(with([](json& e) {
              const json p = {{"type", "quadratic"}, {"stiffness", 10.0}, {"distance", 0.01}};
              e.push_back({{"type", "self_edge_edge"}, {"meshes", pairs({{"a", "a"}, {"a", "b"}})}, {"penalty", p}});
            }).find("the mesh pair [\"b\", \"b\"] (with edges) is in no self_edge_edge entry (effects[5])"),
            std::string::npos);
}

TEST(EffectMeshes, CoverageIsCheckedBeforeTheFirstEffectIsBuilt) {
  // effects[0]'s own field is wrong as well: its loader would refuse it when building the
  // first effect, so the coverage error arriving instead shows that no loader ran before the
  // checks between the entries.
  json s = two_strips(20, 80);
  s["effects"][0]["acceleration"] = "down";
  EXPECT_NE(error_of(s).find("meshes.json: effects[0].acceleration: "), std::string::npos) << error_of(s);
  s["effects"][2]["meshes"] = {"b", "a"};
  EXPECT_EQ(error_of(s),
            "meshes.json: effects[2].meshes: mesh \"a\" is also covered by effects[1] (stretching): each takes one "
            "stretching entry (name each entry's \"meshes\")");
  // An obstacle_contact entry's obstacles are read with its meshes, before the checks: an
  // unknown name is reported as such, not as the meshes it leaves in no entry.
  s = two_strips(20, 80);
  s["obstacles"] = {{{"name", "ball"}, {"shape", "sphere"}, {"radius", 0.1}, {"position", {0, 0, -5}}}};
  const json penalty = {{"type", "quadratic"}, {"stiffness", 10.0}, {"distance", 0.01}};
  s["effects"].push_back({{"type", "obstacle_contact"}, {"penalty", penalty}, {"obstacles", {"nope"}}});
  EXPECT_EQ(error_of(s),
            "meshes.json: effects[5].obstacles[0]: unknown obstacle \"nope\" (the scene's obstacles: \"ball\")");
  s["effects"][5]["obstacles"] = {"ball"};
  EXPECT_EQ(error_of(s), "");
}

TEST(EffectMeshes, ASceneWithMeshEntriesAndItsCppTranscriptionSimulateBitForBitAlike) {
  // The self-contact floor scene (entries per mesh pair with their own friction) and two
  // stretching materials, 12 frames, built from the scene and by hand with
  // restrict_to_meshes and ContactSettings::mesh_pairs.
  json scene = two_sheets_on_a_slope(false, 0.1, 0.6);
  scene["effects"][1] = {{"type", "stretching"}, {"meshes", {"floor", "a"}}, {"stiffness", 60.0}};
  scene["effects"].push_back({{"type", "stretching"}, {"meshes", {"b"}}, {"stiffness", 30.0}});
  scene["frames"] = 12;
  auto s = load_scene_text(scene.dump(), "slope.json", PCE_TEST_TMP);

  Simulation sim;
  sim.model = s->simulation.model;  // the same meshes (build_model is tested elsewhere)
  sim.solver = s->simulation.solver;
  const Model& m = sim.model;
  const Model b = restrict_to_meshes(m, {"b"});
  const Model fa = restrict_to_meshes(m, {"floor", "a"}), fb = restrict_to_meshes(m, {"floor", "b"}),
              rest = restrict_to_meshes(m, {"floor", "a", "b"});
  sim.effects.push_back(make_gravity(m));
  sim.effects.push_back(make_stretching(fa, 60.0));
  sim.effects.push_back(make_bending(m, 2e-5));
  sim.effects.push_back(make_pins(m, {PinGroup{vertices_in_box(m, {-5, -5, -5}, {5, 5, 5}, "floor")}}));
  ContactSettings c;
  c.penalty = {ContactPenalty::Kind::quadratic, 80.0, 0.01, 0.0};
  c.closest_features = true;
  ContactSettings ca = c, cb = c, cr = c;
  ca.mesh_pairs = {{"floor", "a"}};
  ca.friction = FrictionSettings{0.1, 1e-3, 1};
  cb.mesh_pairs = {{"floor", "b"}};
  cb.friction = FrictionSettings{0.6, 1e-3, 1};
  cr.mesh_pairs = {{"floor", "floor"}, {"a", "a"}, {"b", "b"}, {"a", "b"}};
  sim.effects.push_back(make_self_vertex_face(fa, ca));
  sim.effects.push_back(make_self_vertex_face(fb, cb));
  sim.effects.push_back(make_self_vertex_face(rest, cr));
  sim.effects.push_back(make_stretching(b, 30.0));
  sim.start_at_rest();
  ASSERT_EQ(sim.effects.size(), s->simulation.effects.size());
  for (int f = 0; f < 12; ++f) {
    s->simulation.step();
    sim.step();
    ASSERT_EQ(
        std::memcmp(sim.x.data(), s->simulation.x.data(), sizeof(double) * static_cast<std::size_t>(sim.x.size())), 0)
        << "frame " << f + 1 << ", largest difference " << (sim.x - s->simulation.x).cwiseAbs().maxCoeff();
  }
  EXPECT_GT((sim.x - sim.model.rest).cwiseAbs().maxCoeff(), 1e-3);  // it moved
}
