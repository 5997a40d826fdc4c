// SPDX-License-Identifier: MIT
// Block descent (solver/block_descent.cpp, docs/simulation.md §5.5): the contact effects'
// per-vertex bounds are never crossed by any motion within them (random and adversarial
// motions, every pair checked by brute force), their local terms within a sweep are the
// whole evaluation's columns and blocks, and a run does not depend on the thread count.
#include "two_sheets.hpp"

#include <pce/energy/closest_feature.hpp>
#include <pce/penalties/quadratic.hpp>
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/intersections.hpp>
#include <pce/sim/scene.hpp>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace pce::sim;
using nlohmann::json;

namespace {

constexpr double kD = 0.01;     // the contact distance d of the scenes below
constexpr double kFloor = 0.1;  // their min_separation f: floors at f d

/// Two crumpled 5 × 5 sheets, the upper `gap` above the lower, over a sphere; self contact
/// of both kinds and obstacle contact with friction. `jitter` roughens each sheet by up to
/// that much along z (seeded).
std::unique_ptr<Scene> crumpled_sheets(double gap, double jitter, unsigned seed, const std::string& extra_solver = "",
                                       bool friction = true) {
  json j = json::parse(R"({
    "dt": 0.01, "frames": 1,
    "meshes": [
      {"name": "a", "generator": {"type": "grid", "width": 0.1, "height": 0.1, "nx": 5, "ny": 5}},
      {"name": "b", "generator": {"type": "grid", "width": 0.1, "height": 0.1, "nx": 5, "ny": 5},
       "transform": {"rotation": {"axis": [0, 0, 1], "degrees": 17}}}
    ],
    "obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.05, "position": [0, 0, -0.06]}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 10}]
  })");
  j["meshes"][1]["transform"]["translation"] = {0.004, -0.003, gap};
  const json penalty = {{"type", "quadratic"}, {"stiffness", 100.0}, {"distance", kD}};
  j["effects"].push_back({{"type", "self_vertex_face"}, {"penalty", penalty}, {"min_separation", kFloor}});
  if (friction) j["effects"].back()["friction"] = {{"coefficient", 0.3}};
  j["effects"].push_back(
      {{"type", "self_edge_edge"}, {"penalty", penalty}, {"min_separation", kFloor}, {"closest_features", true}});
  j["effects"].push_back({{"type", "obstacle_contact"}, {"penalty", penalty}, {"min_separation", kFloor}});
  if (friction) j["effects"].back()["friction"] = {{"coefficient", 0.5}};
  if (!extra_solver.empty()) j["solver"] = json::parse(extra_solver);
  auto scene = load_scene_text(j.dump(), "sheets.json", PCE_TEST_TMP);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix3Xd& x = scene->simulation.x;
  for (Eigen::Index i = 0; i < x.cols(); ++i) x(2, i) += jitter * u(rng);
  return scene;
}

using Vec12 = Eigen::Matrix<double, 12, 1>;

/// The distance between the primitives of a pair (12 coordinates).
template <class Kind> double distance(const Vec12& xp) {
  pce::ClosestFeatureEnergy<double> ce;
  if (pce::closest_feature_energy<Kind>(xp, pce::UnsignedLength{}, pce::QuadraticPenalty{1.0, 0.0}, ce) !=
      pce::Status::ok)
    return 0;
  return ce.length;
}

Vec12 gather(const Eigen::Matrix3Xd& x, const std::array<int, 4>& v) {
  Vec12 xp;
  for (int a = 0; a < 4; ++a) xp.segment<3>(3 * a) = x.col(v[static_cast<std::size_t>(a)]);
  return xp;
}

/// Every vertex-face and edge-edge pair of the model that shares no vertex.
std::vector<std::pair<bool, std::array<int, 4>>> all_pairs(const Model& m) {
  std::vector<std::pair<bool, std::array<int, 4>>> pairs;
  for (int v = 0; v < m.vertex_count(); ++v)
    for (Eigen::Index t = 0; t < m.triangles.cols(); ++t)
      if (v != m.triangles(0, t) && v != m.triangles(1, t) && v != m.triangles(2, t))
        pairs.push_back({true, {v, m.triangles(0, t), m.triangles(1, t), m.triangles(2, t)}});
  for (Eigen::Index a = 0; a < m.edges.cols(); ++a)
    for (Eigen::Index b = a + 1; b < m.edges.cols(); ++b) {
      const int a0 = m.edges(0, a), a1 = m.edges(1, a), b0 = m.edges(0, b), b1 = m.edges(1, b);
      if (a0 != b0 && a0 != b1 && a1 != b0 && a1 != b1) pairs.push_back({false, {a0, a1, b0, b1}});
    }
  return pairs;
}

double pair_distance(bool vf, const Eigen::Matrix3Xd& x, const std::array<int, 4>& v) {
  return vf ? distance<pce::VertexFace>(gather(x, v)) : distance<pce::EdgeEdge>(gather(x, v));
}

/// The sphere's signed distance at p.
double sphere_distance(const Eigen::Vector3d& p) { return (p - Eigen::Vector3d(0, 0, -0.06)).norm() - 0.05; }

/// Every vertex's bound from the scene's contact effects at x (a step started there).
Eigen::VectorXd bounds_at(Scene& s, const Eigen::Matrix3Xd& x) {
  fixtures::begin_at(s, x);
  Eigen::VectorXd bound = Eigen::VectorXd::Constant(x.cols(), std::numeric_limits<double>::infinity());
  for (auto& e : s.simulation.effects)
    if (ContactEffect* c = as_contact(e.get())) c->vertex_bounds(x, bound);
  return bound;
}

/// No pair of the model is closer at `y` than min(its floor, 0.9 × its distance at x), none
/// crosses the sphere's surface; returns the number of pairs that closed in at all.
int expect_kept(const Model& m, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y,
                const std::vector<std::pair<bool, std::array<int, 4>>>& pairs, const std::string& what) {
  int closer = 0;
  for (const auto& [vf, v] : pairs) {
    const double d0 = pair_distance(vf, x, v), d1 = pair_distance(vf, y, v);
    closer += d1 < d0;
    // a fold pair's floor is f times its reach (≤ d): f d bounds every floor from above
    const double keep = std::min(kFloor * kD * 0.5, 0.9 * d0);
    EXPECT_GE(d1, keep * (1 - 1e-9)) << what << (vf ? ": vertex-face " : ": edge-edge ") << v[0] << " " << v[1] << " "
                                     << v[2] << " " << v[3] << " from " << d0;
  }
  for (int i = 0; i < m.vertex_count(); ++i) {
    const double d0 = sphere_distance(x.col(i)), d1 = sphere_distance(y.col(i));
    if (d0 > 0) {
      EXPECT_GE(d1, std::min(kFloor * kD, 0.9 * d0) * (1 - 1e-9)) << what << ": vertex " << i;
    }
  }
  return closer;
}

}  // namespace

TEST(BlockDescent, NoMotionWithinTheBoundsBringsAPairBelowItsFloor) {
  // Property test: sheets at gaps from below the floor to beyond the query radius, crumpled;
  // random motions (every vertex at its full bound or a random share of it, random
  // directions) and an adversarial one per close pair (its vertices at their full bounds
  // along the directions that close it fastest).
  int closing = 0, adversarial = 0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    const double gap = 0.0006 * seed * seed;  // 0.6 mm … 21.6 mm, d = 10 mm
    auto s = crumpled_sheets(gap, 0.3 * gap, seed);
    const Model& m = s->simulation.model;
    const Eigen::Matrix3Xd x = s->simulation.x;
    const Eigen::VectorXd bound = bounds_at(*s, x);
    SCOPED_TRACE("gap " + std::to_string(gap));
    for (int i = 0; i < m.vertex_count(); ++i) {
      EXPECT_GT(bound[i], 0) << i;
      EXPECT_TRUE(std::isfinite(bound[i])) << i;
    }
    const auto pairs = all_pairs(m);
    std::mt19937 rng(seed);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> share(0, 1);
    for (int trial = 0; trial < 8; ++trial) {
      Eigen::Matrix3Xd y = x;
      for (int i = 0; i < m.vertex_count(); ++i) {
        const Eigen::Vector3d dir = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
        y.col(i) += (trial % 2 ? 1.0 : share(rng)) * bound[i] * dir;
      }
      closing += expect_kept(m, x, y, pairs, "random motion " + std::to_string(trial));
    }
    // Adversarial: each pair closer than the query radius, its four vertices moved by their
    // bounds along −∂D/∂xᵢ (central differences).
    for (const auto& [vf, v] : pairs) {
      const double d0 = pair_distance(vf, x, v);
      if (!(d0 < 1.5 * kD)) continue;
      Eigen::Matrix3Xd y = x;
      for (const int i : v) {
        Eigen::Vector3d grad;
        for (int c = 0; c < 3; ++c) {
          Eigen::Matrix3Xd p = x, q = x;
          p(c, i) += 1e-7;
          q(c, i) -= 1e-7;
          grad[c] = (pair_distance(vf, p, v) - pair_distance(vf, q, v)) / 2e-7;
        }
        if (grad.norm() > 0) y.col(i) -= bound[i] * grad.normalized();
      }
      const double d1 = pair_distance(vf, y, v);
      ++adversarial;
      EXPECT_GE(d1, std::min(kFloor * kD * 0.5, 0.9 * d0) * (1 - 1e-9))
          << (vf ? "vertex-face " : "edge-edge ") << v[0] << " " << v[1] << " " << v[2] << " " << v[3];
    }
  }
  EXPECT_GT(closing, 1000);     // the motions did bring pairs closer
  EXPECT_GT(adversarial, 100);  // and close pairs were attacked
}

class ContactLocalTerms : public testing::TestWithParam<bool> {};

TEST_P(ContactLocalTerms, WithinASweepAreTheWholeEvaluations) {
  // After vertex_bounds and begin_sweep (reaches beyond every distance, so every candidate
  // is listed), each contact effect's local terms at a state within the sweep are the
  // columns and diagonal blocks of its whole evaluation there (with friction, the blocks
  // exceed them by a PSD matrix: friction's majorizer).
  const bool friction = GetParam();
  auto s = crumpled_sheets(0.004, 0.002, 3, "", friction);
  Simulation& sim = s->simulation;
  const Eigen::Matrix3Xd x = sim.x;
  bounds_at(*s, x);
  const Eigen::VectorXd reach = Eigen::VectorXd::Constant(x.cols(), 1.0);
  Eigen::Matrix3Xd y = x;
  for (Eigen::Index i = 0; i < y.cols(); ++i) y(2, i) -= 0.0015 * std::cos(0.7 * static_cast<double>(i));
  int active = 0;
  for (auto& e : sim.effects) {
    ContactEffect* c = as_contact(e.get());
    if (!c) continue;
    SCOPED_TRACE(c->name());
    Pattern couplings;
    c->begin_sweep(x, reach, couplings);
    std::vector<int> vertices(static_cast<std::size_t>(y.cols()));
    for (std::size_t i = 0; i < vertices.size(); ++i) vertices[i] = static_cast<int>(i);
    LocalTerms local;
    local.reset(vertices.size());
    c->evaluate_local(y, vertices, local);
    c->begin_iteration(y);
    Pattern pattern;
    c->declare(pattern);
    for (const int i : vertices) pattern.add(i);
    BlockHessian H;
    H.set_pattern(static_cast<int>(y.cols()), pattern);
    H.set_zero();
    Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, y.cols());
    c->evaluate(y, &g, &H);
    const double scale = std::max(g.cwiseAbs().maxCoeff(), 1e-300);
    for (const int i : vertices) {
      EXPECT_LE((local.gradient.col(i) - g.col(i)).cwiseAbs().maxCoeff(), 1e-12 * scale) << "vertex " << i;
      // friction's block is its majorizer (⪰ the Hessian's), the rest the Hessian's own
      const Eigen::Matrix3d B = H.diagonal_block(i), D = local.hessian[static_cast<std::size_t>(i)] - B;
      const double tol = 1e-12 * std::max(B.cwiseAbs().maxCoeff(), 1.0);
      if (friction)
        EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(D).eigenvalues().minCoeff(), -tol) << "vertex " << i;
      else
        EXPECT_LE(D.cwiseAbs().maxCoeff(), tol) << "vertex " << i;
      active += g.col(i).norm() > 0;
    }
  }
  EXPECT_GT(active, 20);  // contact (and friction) at work
}

INSTANTIATE_TEST_SUITE_P(BlockDescent, ContactLocalTerms, testing::Values(false, true),
                         [](const testing::TestParamInfo<bool>& i) { return i.param ? "friction" : "frictionless"; });

TEST(BlockDescent, ARunDoesNotDependOnTheThreadCount) {
  // at the default substeps, so the substeps' hand-over is covered too
  const std::string solver1 = R"({"mode": "block_descent", "iterations": 12, "threads": 1})";
  const std::string solver2 = R"({"mode": "block_descent", "iterations": 12, "threads": 2})";
  auto a = crumpled_sheets(0.003, 0.001, 5, solver1);
  auto b = crumpled_sheets(0.003, 0.001, 5, solver2);
  double contacts = 0;
  for (int f = 1; f <= 12; ++f) {
    const FrameStats sa = a->simulation.step(), sb = b->simulation.step();
    ASSERT_EQ(a->simulation.x, b->simulation.x) << "frame " << f;
    EXPECT_EQ(sa.counters.at("colours"), sb.counters.at("colours"));
    contacts += sa.counters.at("vertex_face_contacts") + sa.counters.at("obstacle_contacts");
    EXPECT_EQ(sa.stop, StopReason::sweeps);
    EXPECT_EQ(sa.substeps, kDefaultBlockSubsteps);
    EXPECT_EQ(sa.sweeps, 12 * kDefaultBlockSubsteps);
    EXPECT_EQ(sa.newton_iterations, 0);
    EXPECT_EQ(sa.sweep_records.size(), static_cast<std::size_t>(12 * kDefaultBlockSubsteps));
    EXPECT_TRUE(sa.iterations.empty());
  }
  EXPECT_GT(contacts, 0);
}

TEST(BlockDescent, SheetsLandOnTheBallWithoutCrossing) {
  // Dropped from 3 cm: every frame ends with no pair below min(its floor, 0.9 × its distance
  // at the frame's start) and every vertex outside the ball; the sheets come to rest on it.
  auto s = crumpled_sheets(0.006, 0.0, 7, R"({"mode": "block_descent", "iterations": 15})");
  Simulation& sim = s->simulation;
  sim.x.row(2).array() += 0.03;
  const auto pairs = all_pairs(sim.model);
  for (int f = 1; f <= 40; ++f) {
    const Eigen::Matrix3Xd before = sim.x;
    sim.step();
    expect_kept(sim.model, before, sim.x, pairs, "frame " + std::to_string(f));
    if (HasFailure()) return;
  }
  // on the ball (its top at z = −0.01, its equator at −0.06), held there by friction: slower
  // than the ~0.8 m/s of the landing (block descent's sweeps leave some jitter)
  EXPECT_LT(sim.v.colwise().norm().maxCoeff(), 0.5);
  EXPECT_LT(sim.x.row(2).minCoeff(), -0.02);
  EXPECT_GT(sim.x.row(2).minCoeff(), -0.06);
}

TEST(BlockDescent, ARedetectShareMeasuresTheBoundsLessAndKeepsEveryPairApart) {
  // The sheets dropped on the ball, 1 step of 15 sweeps a frame, with every cut measuring the
  // bounds again and with only a cut of more than 5 % of the vertices doing so: fewer
  // measurements (and queries) with the share, and every frame still keeps every pair.
  double measured[2] = {0, 0};
  for (const int with_share : {0, 1}) {
    SCOPED_TRACE(with_share);
    auto s = crumpled_sheets(0.006, 0.0, 7,
                             with_share ? R"({"mode": "block_descent", "substeps": 1, "iterations": 15,
                                             "redetect_share": 0.05})"
                                        : R"({"mode": "block_descent", "substeps": 1, "iterations": 15})");
    Simulation& sim = s->simulation;
    sim.x.row(2).array() += 0.03;
    const auto pairs = all_pairs(sim.model);
    for (int f = 1; f <= 20; ++f) {
      const Eigen::Matrix3Xd before = sim.x;
      measured[with_share] += sim.step().counters.at("bound_measurements");
      expect_kept(sim.model, before, sim.x, pairs, "frame " + std::to_string(f));
      if (HasFailure()) return;
    }
  }
  EXPECT_LT(measured[1], measured[0]);
  EXPECT_GE(measured[1], 20);  // at least once a step
}

TEST(BlockDescent, SceneKeysAreChecked) {
  const auto error_of = [](const std::string& solver) {
    auto j = json::parse(R"({"dt": 0.01, "frames": 1,
      "meshes": [{"name": "a", "generator": {"type": "grid", "width": 0.1, "height": 0.1, "nx": 2, "ny": 2}}],
      "effects": [{"type": "gravity"}]})");
    j["solver"] = json::parse(solver);
    try {
      load_scene_text(j.dump(), "s.json", PCE_TEST_TMP);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error_of(R"({"mode": "block_descent", "iterations": 7})"), "(no error)");
  EXPECT_NE(error_of(R"({"iterations": 7})").find("solver.iterations"), std::string::npos);
  EXPECT_NE(error_of(R"({"mode": "block_descent", "iterations": 0})").find("solver.iterations"), std::string::npos);
  EXPECT_NE(error_of(R"({"mode": "vbd"})").find("block_descent"), std::string::npos);
  EXPECT_EQ(error_of(R"({"mode": "block_descent", "substeps": 5, "acceleration": "chebyshev", "chebyshev_rho": 0.9,
      "sweep_tolerance": 0.01})"),
            "(no error)");
  EXPECT_EQ(error_of(R"({"substeps": 3})"), "(no error)");  // Newton takes substeps too
  EXPECT_NE(error_of(R"({"substeps": 0})").find("solver.substeps"), std::string::npos);
  EXPECT_NE(error_of(R"({"substeps": 1001})").find("solver.substeps"), std::string::npos);
  EXPECT_NE(error_of(R"({"acceleration": "chebyshev"})").find("solver.acceleration"), std::string::npos);
  EXPECT_NE(error_of(R"({"mode": "block_descent", "acceleration": "momentum"})").find("solver.acceleration"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"mode": "block_descent", "chebyshev_rho": 0.9})").find("solver.chebyshev_rho"),
            std::string::npos);  // without the acceleration it would do nothing
  EXPECT_NE(error_of(R"({"mode": "block_descent", "acceleration": "chebyshev", "chebyshev_rho": 1})")
                .find("solver.chebyshev_rho"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"sweep_tolerance": 0.01})").find("solver.sweep_tolerance"), std::string::npos);
  EXPECT_EQ(error_of(R"({"mode": "block_descent", "redetect_share": 0.05})"), "(no error)");
  EXPECT_NE(error_of(R"({"redetect_share": 0.05})").find("solver.redetect_share"), std::string::npos);
  EXPECT_NE(error_of(R"({"mode": "block_descent", "redetect_share": 1.5})").find("solver.redetect_share"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"mode": "block_descent", "sweep_tolerance": -1})").find("solver.sweep_tolerance"),
            std::string::npos);
  // --iterations (an override) on a Newton scene names the key it would replace
  SceneOverrides o;
  o.iterations = 5;
  try {
    load_scene_text(R"({"dt": 0.01, "frames": 1, "meshes": [{"name": "a", "generator": {"type": "grid", "width": 0.1,
      "height": 0.1, "nx": 2, "ny": 2}}], "effects": [{"type": "gravity"}]})",
                    "s.json", PCE_TEST_TMP, o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("solver.iterations: a number of sweeps"), std::string::npos) << e.what();
  }
}

TEST(BlockDescent, TheModesDefaultsAreItsOwn) {
  // A scene without solver.substeps takes its mode's steps per frame, also when --mode
  // changes the mode; a scene's or --substeps' value stands in either mode; the C++ defaults
  // are the scene's. A frame at the defaults is their substeps × sweeps.
  const std::string base = R"({"dt": 0.01, "frames": 1, "meshes": [{"name": "a", "generator": {"type": "grid",
    "width": 0.1, "height": 0.1, "nx": 2, "ny": 2}}], "effects": [{"type": "gravity"}, {"type": "stretching",
    "stiffness": 10}, {"type": "pins", "groups": [{"vertices": [0]}]}], "solver": )";
  const auto load = [&](const std::string& solver, SceneOverrides o = {}) {
    return load_scene_text(base + solver + "}", "s.json", PCE_TEST_TMP, o);
  };
  EXPECT_EQ(load(R"({})")->simulation.solver.steps_per_frame(), 1);
  auto bd = load(R"({"mode": "block_descent"})");
  EXPECT_EQ(bd->simulation.solver.steps_per_frame(), kDefaultBlockSubsteps);
  EXPECT_EQ(bd->simulation.solver.iterations, kDefaultBlockIterations);
  EXPECT_EQ(bd->simulation.solver.acceleration, Acceleration::none);
  EXPECT_EQ(load(R"({"mode": "block_descent", "substeps": 1})")->simulation.solver.steps_per_frame(), 1);
  EXPECT_EQ(load(R"({"substeps": 3})")->simulation.solver.steps_per_frame(), 3);
  SceneOverrides to_block;
  to_block.mode = SolverMode::block_descent;
  EXPECT_EQ(load(R"({})", to_block)->simulation.solver.steps_per_frame(), kDefaultBlockSubsteps);
  SceneOverrides to_newton;
  to_newton.mode = SolverMode::newton;
  EXPECT_EQ(load(R"({"mode": "block_descent"})", to_newton)->simulation.solver.steps_per_frame(), 1);
  to_block.substeps = 2;
  EXPECT_EQ(load(R"({})", to_block)->simulation.solver.steps_per_frame(), 2);
  SolverSettings settings;
  EXPECT_EQ(settings.steps_per_frame(), 1);
  settings.mode = SolverMode::block_descent;
  EXPECT_EQ(settings.steps_per_frame(), kDefaultBlockSubsteps);
  const FrameStats st = bd->simulation.step();
  EXPECT_EQ(st.substeps, kDefaultBlockSubsteps);
  EXPECT_EQ(st.sweeps, kDefaultBlockSubsteps * kDefaultBlockIterations);
}

TEST(BlockDescent, TheLargeShippedSceneRunsReduced) {
  // examples/scenes/drop_130k.json at 30 × 30 quads (its contact distances, half an edge,
  // scaled with the edge and its stiffnesses inversely, as benchmarks/scale_ladder.py's
  // levels): 12 frames land the sheet on the ball, with no intersecting triangle pair in any
  // frame and every vertex outside the ball and above the floor.
  std::ifstream in(std::filesystem::path(PCE_SOURCE_DIR) / "examples" / "scenes" / "drop_130k.json");
  json j = json::parse(in);
  const double scale = j["meshes"][0]["generator"]["nx"].get<double>() / 30;
  j["meshes"][0]["generator"]["nx"] = 30;
  j["meshes"][0]["generator"]["ny"] = 30;
  for (json& e : j["effects"])
    if (e.contains("penalty")) {
      e["penalty"]["distance"] = e["penalty"]["distance"].get<double>() * scale;
      e["penalty"]["stiffness"] = e["penalty"]["stiffness"].get<double>() / scale;
    }
  j["frames"] = 12;
  auto s = load_scene_text(j.dump(), "drop_130k.json", PCE_TEST_TMP);
  Simulation& sim = s->simulation;
  ASSERT_EQ(sim.solver.mode, SolverMode::block_descent);
  const Eigen::Vector3d centre(j["obstacles"][0]["position"][0], j["obstacles"][0]["position"][1],
                               j["obstacles"][0]["position"][2]);
  const double radius = j["obstacles"][0]["radius"];
  double touching = 0;
  for (int f = 1; f <= 12; ++f) {
    const FrameStats st = sim.step();
    ASSERT_TRUE(sim.x.allFinite());
    EXPECT_EQ(intersecting_triangle_pairs(sim.x, sim.model.triangles), 0) << "frame " << f;
    for (Eigen::Index i = 0; i < sim.x.cols(); ++i) {
      EXPECT_GT((sim.x.col(i) - centre).norm(), radius) << "frame " << f << ", vertex " << i;
      EXPECT_GT(sim.x(2, i), 0.0) << "frame " << f << ", vertex " << i;
    }
    touching += st.counters.at("obstacle_contacts");
    if (HasFailure()) return;
  }
  EXPECT_GT(touching, 0);  // it landed
}

TEST(BlockDescent, ConvergesToNewtonsStepAsSweepsGrow) {
  // A 13 × 13 sheet hanging from one edge (stretching, bending, damping, pins): after 10
  // frames, block descent's positions approach Newton's (tolerance 10⁻⁶) as the sweeps per
  // step grow, and at 2 000 sweeps lie within 5 mm; so its per-vertex terms are
  // those of the potential Newton minimises, and only the sweeps stand between them.
  const std::string scene = R"({"dt": 0.025, "frames": 10,
    "meshes": [{"name": "sheet", "generator": {"type": "grid", "width": 0.3, "height": 0.3, "nx": 12, "ny": 12}}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 60}, {"type": "bending", "stiffness": 2e-5},
      {"type": "damping", "coefficient": 0.2},
      {"type": "pins", "stiffness": 1e4, "groups": [{"mesh": "sheet", "box": {"min": [-1, 0.14, -1], "max": [1, 1, 1]}}]}]})";
  const auto run = [&](SceneOverrides o) {
    auto s = load_scene_text(scene, "hang.json", PCE_TEST_TMP, o);
    for (int f = 0; f < 10; ++f) s->simulation.step();
    return Eigen::Matrix3Xd(s->simulation.x);
  };
  SceneOverrides newton;
  newton.tolerance = 1e-6;
  const Eigen::Matrix3Xd reference = run(newton);
  double previous = std::numeric_limits<double>::infinity();
  for (const int sweeps : {20, 200, 2000}) {
    SceneOverrides o;
    o.mode = SolverMode::block_descent;
    o.substeps = 1;  // Newton's step, one per frame
    o.iterations = sweeps;
    const double error = (run(o) - reference).colwise().norm().maxCoeff();
    EXPECT_LT(error, previous) << sweeps << " sweeps";
    previous = error;
  }
  // (measured: 131 mm at 20 sweeps, 70 mm at 200, 3.1 mm at 2 000)
  EXPECT_LT(previous, 5e-3);
}

namespace {

/// The hanging sheet of ConvergesToNewtonsStepAsSweepsGrow after `frames` frames, solved as
/// `o` says.
Eigen::Matrix3Xd hanging_sheet(const SceneOverrides& o, const std::string& solver = "{}", int frames = 10) {
  json j = json::parse(R"({"dt": 0.025, "frames": 10,
    "meshes": [{"name": "sheet", "generator": {"type": "grid", "width": 0.3, "height": 0.3, "nx": 12, "ny": 12}}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 60}, {"type": "bending", "stiffness": 2e-5},
      {"type": "damping", "coefficient": 0.2},
      {"type": "pins", "stiffness": 1e4, "groups": [{"mesh": "sheet", "box": {"min": [-1, 0.14, -1], "max": [1, 1, 1]}}]}]})");
  j["solver"] = json::parse(solver);
  auto s = load_scene_text(j.dump(), "hang.json", PCE_TEST_TMP, o);
  for (int f = 0; f < frames; ++f) s->simulation.step();
  return s->simulation.x;
}

}  // namespace

class Accelerations : public testing::TestWithParam<const char*> {};

TEST_P(Accelerations, ConvergeToNewtonsStepsAsSubstepsAndSweepsGrow) {
  // With S substeps a frame, block descent's frames approach Newton's with the same
  // substeps (tolerance 10⁻⁶) as the sweeps per substep grow, with and without Chebyshev's
  // acceleration; and with S = 4 they get closer with fewer sweeps than one step does.
  const std::string solver = std::string(R"({"mode": "block_descent", "acceleration": ")") + GetParam() + "\"}";
  std::vector<double> last;
  for (const int substeps : {1, 4}) {
    SceneOverrides newton;
    newton.tolerance = 1e-6;
    newton.substeps = substeps;
    const Eigen::Matrix3Xd reference = hanging_sheet(newton);
    double previous = std::numeric_limits<double>::infinity();
    for (const int sweeps : {10, 50, 250}) {
      SceneOverrides o;
      o.iterations = sweeps;
      o.substeps = substeps;
      const double error = (hanging_sheet(o, solver) - reference).colwise().norm().maxCoeff();
      EXPECT_LT(error, previous) << substeps << " substeps, " << sweeps << " sweeps";
      previous = error;
    }
    last.push_back(previous);
  }
  EXPECT_LT(last[1], last[0]);  // 4 × 250 sweeps of dt/4 are closer than 250 of dt
}

TEST_P(Accelerations, SubstepsAndTheAccelerationDoNotDependOnTheThreadCount) {
  const std::string base =
      std::string(R"("mode": "block_descent", "iterations": 6, "substeps": 3, "acceleration": ")") + GetParam() + "\"";
  auto a = crumpled_sheets(0.003, 0.001, 5, "{" + base + R"(, "threads": 1})");
  auto b = crumpled_sheets(0.003, 0.001, 5, "{" + base + R"(, "threads": 2})");
  for (int f = 1; f <= 8; ++f) {
    const FrameStats sa = a->simulation.step(), sb = b->simulation.step();
    ASSERT_EQ(a->simulation.x, b->simulation.x) << "frame " << f;
    EXPECT_EQ(sa.sweeps, 18);
    EXPECT_EQ(sa.substeps, 3);
    EXPECT_EQ(sa.sweep_records.size(), 18u);
  }
}

INSTANTIATE_TEST_SUITE_P(BlockDescent, Accelerations, testing::Values("none", "chebyshev"),
                         [](const testing::TestParamInfo<const char*>& i) { return std::string(i.param); });

TEST(BlockDescent, ChebyshevKeepsNoExtrapolationThatRaisesTheEnergy) {
  // Sheets landing on each other and the ball with ρ = 0.99 (an overestimate: extrapolations
  // overshoot): every kept extrapolation's energy is at most the iterate's before it, some
  // are undone, some are kept, and no pair crosses.
  auto s = crumpled_sheets(0.006, 0.0, 7,
                           R"({"mode": "block_descent", "iterations": 15, "acceleration": "chebyshev",
                               "chebyshev_rho": 0.99})");
  Simulation& sim = s->simulation;
  sim.x.row(2).array() += 0.03;
  const auto pairs = all_pairs(sim.model);
  double kept = 0, undone = 0;
  for (int f = 1; f <= 25; ++f) {
    const Eigen::Matrix3Xd before = sim.x;
    const FrameStats st = sim.step();
    for (std::size_t k = 1; k < st.sweep_records.size(); ++k) {
      const SweepRecord& r = st.sweep_records[k];
      ASSERT_TRUE(std::isfinite(r.energy)) << "frame " << f << ", sweep " << k;
      if (r.accelerated) {
        EXPECT_LE(r.energy, st.sweep_records[k - 1].energy) << "frame " << f << ", sweep " << k;
      }
    }
    kept += st.counters.at(Counter::accelerated_sweeps) - st.counters.at(Counter::acceleration_restarts);
    undone += st.counters.at(Counter::acceleration_restarts);
    expect_kept(sim.model, before, sim.x, pairs, "frame " + std::to_string(f));
    if (HasFailure()) return;
  }
  EXPECT_GT(kept, 0);
  EXPECT_GT(undone, 0);
}

TEST(BlockDescent, ASweepWithinTheSweepToleranceEndsTheStep) {
  // The hanging sheet settles: with a sweep tolerance some of its steps end early (stop
  // "tolerance", fewer sweeps than the cap, the last sweep's residual within it); the
  // others take every sweep.
  SceneOverrides o;
  o.iterations = 400;
  const std::string with = R"({"mode": "block_descent", "sweep_tolerance": 0.002})";
  json j = json::parse(R"({"dt": 0.025, "frames": 10,
    "meshes": [{"name": "sheet", "generator": {"type": "grid", "width": 0.3, "height": 0.3, "nx": 12, "ny": 12}}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 60},
      {"type": "pins", "stiffness": 1e4, "groups": [{"mesh": "sheet", "box": {"min": [-1, 0.14, -1], "max": [1, 1, 1]}}]}]})");
  j["solver"] = json::parse(with);
  auto s = load_scene_text(j.dump(), "hang.json", PCE_TEST_TMP, o);
  int early = 0;
  for (int f = 0; f < 10; ++f) {
    const FrameStats st = s->simulation.step();
    if (st.stop == StopReason::tolerance) {
      ++early;
      EXPECT_LT(st.sweeps, 400);
      EXPECT_LE(st.sweep_records.back().residual, 0.002);
    } else {
      EXPECT_EQ(st.sweeps, 400);
    }
  }
  EXPECT_GT(early, 0);
}
