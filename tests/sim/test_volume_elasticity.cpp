// SPDX-License-Identifier: MIT
// Volumes in pce::sim (src/sim/effects/volume_elasticity.cpp, mesh/model.cpp): masses from
// the density in kg/m³, boundary faces that contact sees and cloth effects do not, interior
// vertices left out of contact; the volume_elasticity effect's gradient against central
// differences, its Hessian PSD and the analytic one equal to the numerical one, finite
// energies for inverted and flat states, its counters, and one InputError per kind of bad
// scene input naming its JSON path.
#include "scene/effect_loaders.hpp"

#include <pce/sim/effects.hpp>
#include <pce/sim/generators.hpp>
#include <pce/sim/intersections.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/mesh.hpp>
#include <pce/sim/model.hpp>
#include <pce/sim/obj.hpp>
#include <pce/sim/scene.hpp>
#include <pce/sim/simulation.hpp>
#include <pce/volumes/stable_neo_hookean.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

using namespace pce::sim;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using nlohmann::json;

namespace {

Model box_model(const Eigen::Vector3i& n = Eigen::Vector3i(2, 2, 2), double density = 1000) {
  ModelMesh m;
  m.name = "box";
  m.mesh = tet_box(Eigen::Vector3d(0.2, 0.3, 0.4), n);
  m.density = density;
  return build_model({m});
}

std::unique_ptr<Effect> elasticity(const Model& model, const std::string& hessian = "analytic") {
  const json j = {{"type", "volume_elasticity"}, {"young_modulus", 1e4}, {"poisson_ratio", 0.4}, {"hessian", hessian}};
  const Params p(j, "test.json", "effects[0]");
  BuildContext ctx;
  ctx.model = &model;
  return load_volume_elasticity(p, ctx);
}

Matrix3Xd perturbed(const Matrix3Xd& x, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Matrix3Xd y = x;
  for (Eigen::Index i = 0; i < y.size(); ++i) y.data()[i] += amplitude * u(rng);
  return y;
}

MatrixXd hessian(Effect& e, const Matrix3Xd& x) {
  Pattern pattern;
  e.declare(pattern);
  BlockHessian H;
  H.set_pattern(static_cast<int>(x.cols()), pattern);
  H.set_zero();
  e.evaluate(x, nullptr, &H);
  const Eigen::SparseMatrix<double> full = H.matrix().selfadjointView<Eigen::Upper>();
  return MatrixXd(full);
}

Matrix3Xd gradient(Effect& e, const Matrix3Xd& x) {
  Matrix3Xd g = Matrix3Xd::Zero(3, x.cols());
  e.evaluate(x, &g, nullptr);
  return g;
}

/// The InputError path of loading a one-box scene with `effect` as its only effect.
std::string scene_error(const json& effect, const json& mesh_extra = json::object()) {
  json mesh = {{"name", "box"}, {"generator", {{"type", "tet_box"}, {"size", {0.2, 0.2, 0.2}}, {"n", {2, 2, 2}}}}};
  for (const auto& [k, v] : mesh_extra.items()) mesh[k] = v;
  const json j = {{"dt", 0.01}, {"frames", 1}, {"meshes", {mesh}}, {"effects", {effect}}};
  try {
    load_scene_text(j.dump(), "scene.json", PCE_TEST_TMP);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "scene.json");
    return e.where();
  }
  return "(no error)";
}

}  // namespace

TEST(VolumeModel, MassesFromDensityBoundaryAndInteriorVertices) {
  const Model m = box_model();
  EXPECT_NEAR(m.mass.sum(), 1000 * 0.2 * 0.3 * 0.4, 1e-12);
  EXPECT_EQ(m.tetrahedra.cols(), 6 * 8);
  ASSERT_EQ(m.meshes.size(), 1u);
  EXPECT_EQ(m.meshes[0].tetrahedron_count, 48);
  EXPECT_EQ(m.triangles.cols(), 2 * 2 * (4 + 4 + 4));  // two triangles per boundary square
  for (Eigen::Index t = 0; t < m.triangles.cols(); ++t) EXPECT_TRUE(m.is_boundary_triangle(t));
  int interior = 0;
  for (int v = 0; v < m.vertex_count(); ++v) interior += !m.is_surface_vertex(v);
  EXPECT_EQ(interior, 1);                 // the centre of a 2 × 2 × 2 box
  EXPECT_FALSE(m.is_surface_vertex(13));  // vertex (1, 1, 1)
}

TEST(VolumeModel, ClothEffectsSkipBoundaryFaces) {
  // The box's surface is closed: bending would find hinges on all its edges and stretching
  // its triangles, were they not a volume's boundary.
  const Model m = box_model();
  const auto bending = make_bending(m, 1.0);
  EffectCounters c;
  bending->report(c);
  EXPECT_EQ(c.at(Counter::hinges), 0.0);
  const auto stretching = make_stretching(m, 1.0);
  EXPECT_EQ(stretching->evaluate(perturbed(m.rest, 0.05, 3), nullptr, nullptr), 0.0);
}

TEST(VolumeElasticity, GradientMatchesCentralDifferences) {
  const Model m = box_model();
  auto e = elasticity(m);
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Matrix3Xd x = perturbed(m.rest, 0.03, seed);
    const Matrix3Xd g = gradient(*e, x);
    Matrix3Xd fd(3, x.cols());
    const double h = 1e-7;
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      Matrix3Xd p = x, q = x;
      p.data()[k] += h;
      q.data()[k] -= h;
      fd.data()[k] = (e->evaluate(p, nullptr, nullptr) - e->evaluate(q, nullptr, nullptr)) / (2 * h);
    }
    EXPECT_LT((g - fd).cwiseAbs().maxCoeff(), 1e-5 * g.cwiseAbs().maxCoeff()) << "seed " << seed;
  }
}

TEST(VolumeElasticity, HessianIsPsdAndAnalyticEqualsNumerical) {
  const Model m = box_model();
  auto analytic = elasticity(m, "analytic");
  auto numerical = elasticity(m, "numerical");
  for (double amplitude : {0.01, 0.05, 0.2}) {  // 0.2: many tetrahedra inverted
    const Matrix3Xd x = perturbed(m.rest, amplitude, 7);
    const MatrixXd A = hessian(*analytic, x), N = hessian(*numerical, x);
    const double scale = A.cwiseAbs().maxCoeff();
    EXPECT_LT((A - N).cwiseAbs().maxCoeff(), 1e-10 * scale) << amplitude;
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatrixXd>(A).eigenvalues().minCoeff(), -1e-10 * scale) << amplitude;
  }
}

TEST(VolumeElasticity, InvertedAndFlatStatesStayFinite) {
  const Model m = box_model();
  auto e = elasticity(m);
  Matrix3Xd mirrored = m.rest, flat = m.rest, point = Matrix3Xd::Zero(3, m.rest.cols());
  mirrored.row(0) *= -1;
  flat.row(2).setZero();
  for (const Matrix3Xd* x : {&mirrored, &flat, &point}) {
    Matrix3Xd g = Matrix3Xd::Zero(3, x->cols());
    const double E = e->evaluate(*x, &g, nullptr);
    EXPECT_TRUE(std::isfinite(E));
    EXPECT_TRUE(g.allFinite());
    EXPECT_TRUE(hessian(*e, *x).allFinite());
  }
  e->evaluate(mirrored, nullptr, nullptr);
  EffectCounters c;
  e->report(c);
  EXPECT_EQ(c.at(Counter::tetrahedra), 48.0);
  EXPECT_EQ(c.at(Counter::inverted_tetrahedra), 48.0);
  EXPECT_NEAR(c.at(Counter::volume_ratio), -1.0, 1e-12);
  e->evaluate(m.rest, nullptr, nullptr);
  e->report(c);
  EXPECT_EQ(c.at(Counter::inverted_tetrahedra), 0.0);
  EXPECT_NEAR(c.at(Counter::volume_ratio), 1.0, 1e-12);
}

TEST(VolumeElasticity, RestIsAMinimumAndRigidMotionsCostNothing) {
  const Model m = box_model();
  auto e = elasticity(m);
  const double E0 = e->evaluate(m.rest, nullptr, nullptr);
  EXPECT_LT(gradient(*e, m.rest).cwiseAbs().maxCoeff(), 1e-9);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Matrix3Xd moved = (R * m.rest).colwise() + Eigen::Vector3d(3, -1, 2);
  EXPECT_NEAR(e->evaluate(moved, nullptr, nullptr), E0, 1e-9);
  EXPECT_GT(e->evaluate(perturbed(m.rest, 0.01, 5), nullptr, nullptr), E0);
}

TEST(VolumeElasticity, SceneErrorsNameTheirPath) {
  const json ok = {{"type", "volume_elasticity"}, {"young_modulus", 1e4}, {"poisson_ratio", 0.3}};
  EXPECT_EQ(scene_error(ok), "(no error)");
  json both = ok;
  both["mu"] = 1.0;
  EXPECT_EQ(scene_error(both), "effects[0].mu");
  EXPECT_EQ(scene_error({{"type", "volume_elasticity"}}), "effects[0].young_modulus");
  json nu = ok;
  nu["poisson_ratio"] = 0.5;
  EXPECT_EQ(scene_error(nu), "effects[0].poisson_ratio");
  json lame = {{"type", "volume_elasticity"}, {"mu", 1.0}, {"lambda", -1.0}};
  EXPECT_EQ(scene_error(lame), "effects[0].lambda");
  json h = ok;
  h["hessian"] = "exact";
  EXPECT_EQ(scene_error(h), "effects[0].hessian");
  json model = ok;
  model["model"] = "arap";
  EXPECT_EQ(scene_error(model), "effects[0].model");
  EXPECT_EQ(scene_error(ok, {{"linear_density", 1.0}}), "meshes[0].linear_density");
  EXPECT_EQ(scene_error(ok, {{"generator", {{"type", "tet_box"}, {"size", {0.2, 0.2, 0.2}}, {"n", {2, 0, 2}}}}}),
            "meshes[0].generator.n");
  // A cloth alone has no tetrahedra.
  const json cloth = {
      {"dt", 0.01},
      {"frames", 1},
      {"meshes",
       {{{"name", "c"}, {"generator", {{"type", "grid"}, {"width", 1}, {"height", 1}, {"nx", 2}, {"ny", 2}}}}}},
      {"effects", {ok}}};
  try {
    load_scene_text(cloth.dump(), "scene.json", PCE_TEST_TMP);
    ADD_FAILURE() << "a scene without tetrahedra loaded volume_elasticity";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "effects[0]");
  }
}

TEST(VolumeContact, InteriorVerticesAreNoCandidates) {
  // A 2 × 2 × 2 box's centre vertex lies 0.1 m from every boundary face, inside a contact
  // distance of 0.17 m. Its surface alone, as a cloth with the same positions, must give
  // exactly as many vertex-face candidates as the volume: the centre takes part in none.
  const auto candidates = [](const json& mesh) {
    const json j = {{"dt", 0.01},
                    {"frames", 1},
                    {"meshes", {mesh}},
                    {"effects",
                     {{{"type", "self_vertex_face"},
                       {"penalty", {{"type", "quadratic"}, {"stiffness", 1.0}, {"distance", 0.17}}}}}}};
    auto scene = load_scene_text(j.dump(), "scene.json", PCE_TEST_TMP);
    const FrameStats st = scene->simulation.step();
    return st.counters.at(Counter::vertex_face_candidates);
  };
  const json volume = {{"name", "box"},
                       {"generator", {{"type", "tet_box"}, {"size", {0.2, 0.2, 0.2}}, {"n", {2, 2, 2}}}}};
  const Mesh box = tet_box(Eigen::Vector3d(0.2, 0.2, 0.2), Eigen::Vector3i(2, 2, 2));
  Mesh shell;  // the boundary faces on the 26 surface vertices (vertex 13, the centre, removed)
  shell.positions.resize(3, 26);
  shell.positions << box.positions.leftCols(13), box.positions.rightCols(13);
  shell.triangles = box.triangles.unaryExpr([](int v) { return v > 13 ? v - 1 : v; });
  ASSERT_TRUE((box.triangles.array() != 13).all());
  write_obj(std::filesystem::path(PCE_TEST_TMP) / "volume_shell.obj", shell);
  const double with_volume = candidates(volume);
  EXPECT_GT(with_volume, 0.0);
  EXPECT_EQ(with_volume, candidates({{"name", "box"}, {"file", "volume_shell.obj"}}));
}

namespace {
/// Steps `scene_name` from examples/scenes for `frames` frames, checking every frame: no
/// intersecting triangle pair (exact count), no inverted tetrahedron, the volume within 5 %
/// of the rest volume, finite positions, Newton below its cap. Returns the last frame's stats.
FrameStats run_volume_scene(const char* scene_name, int frames) {
  auto scene = load_scene(std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes" / scene_name);
  Simulation& sim = scene->simulation;
  FrameStats st;
  for (int f = 1; f <= frames; ++f) {
    st = sim.step();
    EXPECT_TRUE(sim.x.allFinite()) << scene_name << " frame " << f;
    EXPECT_EQ(intersecting_triangle_pairs(sim.x, sim.model.triangles), 0) << scene_name << " frame " << f;
    EXPECT_EQ(st.counters.at(Counter::inverted_tetrahedra), 0.0) << scene_name << " frame " << f;
    EXPECT_NEAR(st.counters.at(Counter::volume_ratio), 1.0, 0.05) << scene_name << " frame " << f;
    EXPECT_FALSE(st.hit_iteration_cap) << scene_name << " frame " << f;
    if (testing::Test::HasFailure()) break;
  }
  return st;
}
}  // namespace

TEST(VolumeScenes, BallDropSettles) {
  // examples/scenes/ball_drop.json, all 150 frames: the ball lands at frame ~10, bounces and
  // settles; at the end its kinetic energy is below 1e-4 J (it peaks at about 1 J).
  const FrameStats last = run_volume_scene("ball_drop.json", 150);
  EXPECT_LT(last.kinetic_energy, 1e-4);
  EXPECT_GT(last.counters.at(Counter::obstacle_contacts), 0.0);  // resting on the floor
}

TEST(VolumeScenes, PileFirstSixtyFrames) {
  // examples/scenes/pile.json, frames 1-60 (the full 120 frames: docs/simulation.md §9):
  // slab, cube and ball land on the sheet and on each other.
  const FrameStats last = run_volume_scene("pile.json", 60);
  EXPECT_GT(last.counters.at(Counter::vertex_face_contacts), 0.0);
}

TEST(VolumeContact, InteriorVerticesTouchNoObstacle) {
  // A small sphere 5 mm from the centre of a 2 × 2 × 2 box, 7.5 cm from every surface vertex:
  // within the contact distance of the centre vertex only, which takes part in no contact.
  const Model m = box_model();
  Obstacle sphere;
  sphere.name = "sphere";
  sphere.kind = ShapeKind::sphere;
  sphere.radius = 0.01;
  sphere.position = m.rest.col(13) + Eigen::Vector3d(0, 0, 0.015);
  ObstacleContactSettings settings;
  settings.penalty.kind = ContactPenalty::Kind::quadratic;
  settings.penalty.stiffness = 1.0;
  settings.penalty.distance = 0.02;
  // The energy and contact count, unweighted and area weighted, with the sphere where it is.
  const auto contact = [&](bool weighted, double& energy) {
    settings.area_weighted = weighted;
    auto e = make_obstacle_contact(m, {sphere}, settings);
    energy = e->evaluate(m.rest, nullptr, nullptr);
    EffectCounters c;
    e->report(c);
    return c.at(Counter::obstacle_contacts);
  };
  for (bool weighted : {false, true}) {
    double energy = -1;
    EXPECT_EQ(contact(weighted, energy), 0.0) << weighted;
    EXPECT_EQ(energy, 0.0) << weighted;
  }
  // Positive control: the same sphere as near a surface vertex (a corner, outside the box)
  // is in contact, weighted or not.
  sphere.position = m.rest.col(0) + 0.015 * (m.rest.col(0) - m.rest.col(13)).normalized();
  for (bool weighted : {false, true}) {
    double energy = 0;
    EXPECT_EQ(contact(weighted, energy), 1.0) << weighted;
    EXPECT_GT(energy, 0.0) << weighted;
  }
}

TEST(VolumeElasticity, YoungAndPoissonGiveTheTextbookLameParameters) {
  // μ = E/(2(1 + ν)), λ_Lamé = Eν/((1 + ν)(1 − 2ν)), worked by hand for E = 10⁴ Pa, ν = 0.4:
  // μ = 10⁴/2.8 = 3 571.428 571…, λ_Lamé = 4 000/0.28 = 14 285.714 285…; the stable
  // Neo-Hookean λ is λ_Lamé + μ = 17 857.142 857… (Smith et al. 2018, Eq. 16).
  const pce::StableNeoHookean m = pce::StableNeoHookean::from_young_poisson(1e4, 0.4);
  EXPECT_NEAR(m.mu, 3571.4285714285714, 1e-9);
  EXPECT_NEAR(m.lambda, 17857.142857142857, 1e-9);
  // ν = 0: no lateral coupling, λ_Lamé = 0 and λ = μ = E/2.
  const pce::StableNeoHookean z = pce::StableNeoHookean::from_young_poisson(2e3, 0.0);
  EXPECT_NEAR(z.mu, 1000.0, 1e-12);
  EXPECT_NEAR(z.lambda, 1000.0, 1e-12);
}

TEST(VolumeElasticity, EnergiesOfUniformDeformationsMatchClosedForms) {
  // The 0.2 × 0.3 × 0.4 m box (rest volume 0.024 m³) of elasticity() (E = 10⁴, ν = 0.4: μ and λ
  // above), deformed uniformly, so every tetrahedron has the same F and E = V Ψ(F):
  //   scaled by s:   F = s I,            Ψ = μ/2 (3s² − 3) − μ (s³ − 1) + λ/2 (s³ − 1)²
  //   sheared by γ:  F = I + γ e_x e_yᵀ, Ψ = μ γ²/2 (J = 1)
  //   rotated:       F = R,              Ψ = 0
  const Model model = box_model();
  auto e = elasticity(model);
  const double V = 0.2 * 0.3 * 0.4, mu = 3571.4285714285714, lambda = 17857.142857142857;
  for (const double s : {0.8, 1.0, 1.1, 1.5}) {
    const double J = s * s * s;
    const double psi = mu / 2 * (3 * s * s - 3) - mu * (J - 1) + lambda / 2 * (J - 1) * (J - 1);
    EXPECT_NEAR(e->evaluate(s * model.rest, nullptr, nullptr), V * psi, 1e-10 * std::max(1.0, std::abs(V * psi)))
        << "scaled by " << s;
  }
  for (const double gamma : {0.05, 0.3}) {
    Matrix3Xd x = model.rest;
    x.row(0) += gamma * model.rest.row(1);
    EXPECT_NEAR(e->evaluate(x, nullptr, nullptr), V * mu * gamma * gamma / 2, 1e-10) << "sheared by " << gamma;
  }
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  EXPECT_NEAR(e->evaluate(R * model.rest, nullptr, nullptr), 0.0, 1e-9);
}
