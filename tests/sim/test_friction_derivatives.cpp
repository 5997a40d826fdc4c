// SPDX-License-Identifier: MIT
// The contact effects' assembled derivatives with friction and area weighting on
// (effects/friction.hpp, effects/contact/self_contact.cpp, effects/obstacle_contact.cpp),
// for self vertex-face, self edge-edge (plane and closest-feature modes) and obstacle
// contact, at a state displaced from the step's start (where friction is frozen) so that
// some contacts slip by less than ε_v h (static) and some by more (sliding):
// - the gradient equals central differences of the energy;
// - friction's Hessian, the difference of an effect's assembled Hessian with and without
//   friction, equals central differences of the gradients' difference (the friction
//   potential's Hessian is exact: its tangent block's eigenvalues f₁′ and f₁/y are ≥ 0, so
//   nothing is projected and a sign or scale error shows);
// - one area-weighted pair: its energy is the unweighted one times the rest-area weight of
//   docs/simulation.md §4.8, worked out by hand, and its Hessian is the nearest PSD matrix
//   to central differences of its gradient (`numerical`);
// - obstacle contact on a box face, where its Hessian ψ″ n nᵀ plus friction's is exact,
//   equals central differences of its gradient outright.
#include <pce/sim/contact_effect.hpp>
#include <pce/sim/scene.hpp>

#include "two_sheets.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <functional>
#include <random>
#include <string>

using namespace pce::sim;
using nlohmann::json;

namespace {

using fixtures::begin_at;
using fixtures::contact_of;
using fixtures::dense_hessian;
using fixtures::two_sheets;

constexpr double kH = 1e-7;             // central-difference step (m)
constexpr double kSlipVelocity = 0.05;  // ε_v: ε_v h = 0.5 mm at dt 0.01 s

json self_contact(const char* type, bool closest, bool friction) {
  json c = {{"type", type},          {"length", "unsigned"},
            {"hessian", "analytic"}, {"closest_features", closest},
            {"area_weighted", true}, {"penalty", {{"type", "quadratic"}, {"stiffness", 4e4}, {"distance", 0.02}}}};
  if (friction) c["friction"] = {{"coefficient", 0.5}, {"slip_velocity", kSlipVelocity}};
  return c;
}

Eigen::Matrix3Xd gradient_at(ContactEffect& e, const Eigen::Matrix3Xd& x) {
  Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, x.cols());
  e.evaluate(x, &g, nullptr);
  return g;
}

/// Largest |central difference of E − g| over every coordinate, relative to max |g|.
double gradient_error(ContactEffect& e, const Eigen::Matrix3Xd& x) {
  const Eigen::Matrix3Xd g = gradient_at(e, x);
  double worst = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    Eigen::Matrix3Xd xp = x, xm = x;
    xp.data()[i] += kH;
    xm.data()[i] -= kH;
    const double fd = (e.evaluate(xp, nullptr, nullptr) - e.evaluate(xm, nullptr, nullptr)) / (2 * kH);
    worst = std::max(worst, std::abs(fd - g.data()[i]));
  }
  return worst / g.cwiseAbs().maxCoeff();
}

/// Central differences of a gradient field: column j is (g(x + h eⱼ) − g(x − h eⱼ))/(2h),
/// symmetrised.
Eigen::MatrixXd difference_hessian(const std::function<Eigen::Matrix3Xd(const Eigen::Matrix3Xd&)>& g,
                                   const Eigen::Matrix3Xd& x) {
  const Eigen::Index n = x.size();
  Eigen::MatrixXd H(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    Eigen::Matrix3Xd xp = x, xm = x;
    xp.data()[j] += kH;
    xm.data()[j] -= kH;
    const Eigen::Matrix3Xd d = (g(xp) - g(xm)) / (2 * kH);
    H.col(j) = Eigen::Map<const Eigen::VectorXd>(d.data(), n);
  }
  return 0.5 * (H + H.transpose());
}

/// The nearest PSD matrix: V max(Λ, 0) Vᵀ.
Eigen::MatrixXd nearest_psd(const Eigen::MatrixXd& A) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * eig.eigenvectors().transpose();
}

/// Sheet b (the second half of the vertices) slid in its plane by a random 0 … 2.1 mm per
/// vertex (0 to ~4 ε_v h) and lifted by a little out-of-plane noise (so edge-edge pairs have
/// frames and distances differ).
Eigen::Matrix3Xd slid(const Eigen::Matrix3Xd& x0, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.5e-3, 1.5e-3);
  Eigen::Matrix3Xd x = x0;
  for (Eigen::Index i = x.cols() / 2; i < x.cols(); ++i) {
    x(0, i) += u(rng);
    x(1, i) += u(rng);
  }
  for (Eigen::Index i = 0; i < x.cols(); ++i) x(2, i) += 1e-3 * std::sin(1.7 * static_cast<double>(i));
  return x;
}

}  // namespace

TEST(FrictionDerivatives, SelfContactGradientAndFrictionHessianMatchCentralDifferences) {
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    for (const bool closest : {false, true}) {
      SCOPED_TRACE(std::string(type) + (closest ? " closest" : " plane"));
      // Two copies of the area-weighted effect, with and without friction, frozen at the
      // same start (the sheets 8 mm apart, within d = 20 mm).
      auto with = two_sheets(self_contact(type, closest, true), 0.008);
      auto without = two_sheets(self_contact(type, closest, false), 0.008);
      begin_at(*with, with->simulation.x);
      begin_at(*without, without->simulation.x);
      ContactEffect& ef = contact_of(with->simulation.effects[0]);
      ContactEffect& e0 = contact_of(without->simulation.effects[0]);
      const Eigen::Matrix3Xd x = slid(with->simulation.x, 7);

      EXPECT_LT(gradient_error(ef, x), 1e-5);
      EffectCounters c;
      ef.report(c);
      const std::string kind = std::string(type) == "self_vertex_face" ? "vertex_face" : "edge_edge";
      const double frozen = c.at(kind + "_friction_contacts"), sticking = c.at(kind + "_friction_sticking");
      std::printf("%s %s: %g frozen friction contacts, %g of them static at x\n", type, closest ? "closest" : "plane",
                  frozen, sticking);
      EXPECT_GT(frozen, 5);
      EXPECT_GT(sticking, 0);  // both regimes of the mollifier are evaluated
      EXPECT_LT(sticking, frozen);

      // Friction's share of the Hessian against central differences of its share of the
      // gradient.
      const Eigen::MatrixXd Hf = dense_hessian(ef, x) - dense_hessian(e0, x);
      const Eigen::MatrixXd fd = difference_hessian(
          [&](const Eigen::Matrix3Xd& y) -> Eigen::Matrix3Xd { return gradient_at(ef, y) - gradient_at(e0, y); }, x);
      const double scale = Hf.cwiseAbs().maxCoeff();
      EXPECT_GT(scale, 0);
      EXPECT_LT((Hf - fd).cwiseAbs().maxCoeff(), 1e-5 * scale);
    }
  }
}

namespace {

/// Two single triangles: "floor", a right triangle of legs 0.2 m in z = 0 (area 0.02 m²),
/// and "tip" (area `tip_area`, computed from its corners), placed so that exactly one pair
/// of the effect `type` is within d = 20 mm: vertex-face, the tip's lowest corner 8 mm over
/// the floor's interior (42 mm and more from its edges); edge-edge, the tip's lowest edge
/// crossing the floor's hypotenuse 8 mm above its midpoint (its other edges 30 mm and more
/// from every floor edge).
std::unique_ptr<Scene> one_pair(const char* type, bool weighted, double& tip_area) {
  const bool vf = std::string(type) == "self_vertex_face";
  const Eigen::Vector3d v(1 / std::sqrt(2.0), 1 / std::sqrt(2.0), 0);
  const Eigen::Vector3d p0 =
      vf ? Eigen::Vector3d(-0.03, -0.03, 0.008) : Eigen::Vector3d(-0.03 * v + Eigen::Vector3d(0, 0, 0.006));
  const Eigen::Vector3d p1 =
      vf ? Eigen::Vector3d(0.0, -0.03, 0.06) : Eigen::Vector3d(0.03 * v + Eigen::Vector3d(0, 0, 0.010));
  const Eigen::Vector3d p2 = vf ? Eigen::Vector3d(-0.03, 0.0, 0.07) : Eigen::Vector3d(0.0, 0.0, 0.08);
  tip_area = 0.5 * (p1 - p0).cross(p2 - p0).norm();
  const std::string dir = PCE_TEST_TMP;
  std::ofstream(dir + "/friction_floor.obj") << "v -0.1 -0.1 0\nv 0.1 -0.1 0\nv -0.1 0.1 0\nf 1 2 3\n";
  std::ofstream tip(dir + "/friction_tip.obj");
  tip.precision(17);
  for (const Eigen::Vector3d& p : {p0, p1, p2}) tip << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  tip << "f 1 2 3\n";
  tip.close();
  json effect = self_contact(type, false, false);
  effect["hessian"] = "numerical";
  effect["area_weighted"] = weighted;  // the same k either way (J/m⁴ or J/m²), so E_w/E = w
  const json scene = {
      {"dt", 0.01},
      {"frames", 1},
      {"meshes",
       {{{"name", "floor"}, {"file", "friction_floor.obj"}}, {{"name", "tip"}, {"file", "friction_tip.obj"}}}},
      {"effects", {effect}}};
  return load_scene_text(scene.dump(), "one_pair.json", dir);
}

}  // namespace

TEST(FrictionDerivatives, OneAreaWeightedPairIsItsWeightTimesThePairAndItsHessianTheNearestPsd) {
  for (const char* type : {"self_vertex_face", "self_edge_edge"}) {
    SCOPED_TRACE(type);
    double tip_area = 0;
    auto weighted = one_pair(type, true, tip_area);
    auto plain = one_pair(type, false, tip_area);
    begin_at(*weighted, weighted->simulation.x);
    begin_at(*plain, plain->simulation.x);
    ContactEffect& ew = contact_of(weighted->simulation.effects[0]);
    ContactEffect& eu = contact_of(plain->simulation.effects[0]);
    Eigen::Matrix3Xd x = weighted->simulation.x;
    x.col(3) += Eigen::Vector3d(1e-3, -2e-3, 5e-4);  // the tip's lowest corner, off the placement above
    const double Ew = ew.evaluate(x, nullptr, nullptr), Eu = eu.evaluate(x, nullptr, nullptr);
    EffectCounters c;
    ew.report(c);
    const bool vf = std::string(type) == "self_vertex_face";
    ASSERT_EQ(c.at(vf ? "vertex_face_contacts" : "edge_edge_contacts"), 1.0);  // the setup: one pair
    ASSERT_GT(Eu, 0);
    // The weight by hand (§4.8): vertex-face, the face's rest area plus the vertex's lumped
    // area (a third of the one triangle at it); edge-edge, the two edges' lumped areas (a
    // third of the one triangle at each).
    const double floor_area = 0.02;
    const double w = vf ? floor_area + tip_area / 3 : floor_area / 3 + tip_area / 3;
    EXPECT_NEAR(Ew / Eu, w, 1e-12 * w);
    EXPECT_LT(gradient_error(ew, x), 1e-5);
    const Eigen::MatrixXd H = dense_hessian(ew, x);
    const Eigen::MatrixXd fd =
        difference_hessian([&](const Eigen::Matrix3Xd& y) -> Eigen::Matrix3Xd { return gradient_at(ew, y); }, x);
    const double scale = H.cwiseAbs().maxCoeff();
    EXPECT_GT(scale, 0);
    EXPECT_LT((H - nearest_psd(fd)).cwiseAbs().maxCoeff(), 1e-5 * scale);
    // The projection does something here (the pair's exact Hessian is indefinite), so the
    // comparison is not with the exact Hessian by accident.
    EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(fd).eigenvalues().minCoeff(), -1e-3 * scale);
  }
}

TEST(FrictionDerivatives, ObstacleContactOnABoxFaceMatchesCentralDifferencesOutright) {
  // A 6 × 6-vertex sheet 10 mm over the top face of a box that translates and turns about z
  // during the step (friction's slip is measured against the surface point's motion), area
  // weighted, μ = 0.4; every vertex over the face's interior, where the distance's Hessian
  // is zero and the effect's ψ″ n nᵀ + friction is the exact Hessian.
  const json scene = {{"dt", 0.01},
                      {"frames", 1},
                      {"meshes",
                       {{{"name", "sheet"},
                         {"generator", {{"type", "grid"}, {"width", 0.3}, {"height", 0.3}, {"nx", 5}, {"ny", 5}}},
                         {"transform", {{"translation", {0, 0, 0.06}}}}}}},
                      {"obstacles",
                       {{{"name", "box"},
                         {"shape", "box"},
                         {"half_extents", {1, 1, 0.05}},
                         {"motion", {{"velocity", {0.03, 0.02, 0}}, {"angular_velocity", {0, 0, 0.2}}}}}}},
                      {"effects",
                       {{{"type", "obstacle_contact"},
                         {"area_weighted", true},
                         {"penalty", {{"type", "quadratic"}, {"stiffness", 4e4}, {"distance", 0.02}}},
                         {"friction", {{"coefficient", 0.4}, {"slip_velocity", kSlipVelocity}}}}}}};
  auto s = load_scene_text(scene.dump(), "box_face.json", PCE_TEST_TMP);
  begin_at(*s, s->simulation.x);
  ContactEffect& e = contact_of(s->simulation.effects[0]);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-6e-4, 6e-4);
  Eigen::Matrix3Xd x = s->simulation.x;
  for (Eigen::Index i = 0; i < x.cols(); ++i) x.col(i) += Eigen::Vector3d(u(rng), u(rng), u(rng));
  EXPECT_LT(gradient_error(e, x), 1e-5);
  EffectCounters c;
  e.report(c);
  EXPECT_EQ(c.at("obstacle_friction_contacts"), 36.0);
  EXPECT_GT(c.at("obstacle_friction_sticking"), 0);
  EXPECT_LT(c.at("obstacle_friction_sticking"), 36.0);
  const Eigen::MatrixXd H = dense_hessian(e, x);
  const Eigen::MatrixXd fd =
      difference_hessian([&](const Eigen::Matrix3Xd& y) -> Eigen::Matrix3Xd { return gradient_at(e, y); }, x);
  const double scale = H.cwiseAbs().maxCoeff();
  EXPECT_GT(scale, 0);
  EXPECT_LT((H - fd).cwiseAbs().maxCoeff(), 1e-5 * scale);
}
