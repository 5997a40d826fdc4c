// SPDX-License-Identifier: MIT
// pce::sim kinematic obstacles (src/sim/obstacles, src/sim/effects/obstacle_contact.cpp):
// the closed-form distances agree with FCL's GJK (libccd) at random points OUTSIDE the
// shapes (inside, FCL reports penetration by another algorithm, so inside points are
// checked by finite differences and by the mesh distance instead); normals are unit, point
// from the surface to the point and are the distance's gradient; prescribed poses; surface
// meshes lie on the surface and face outward; the obstacle_contact effect's gradient
// matches finite differences, its Hessian is PSD, the barrier's domain is kept; bad scene
// input names its JSON path.
#include "scene/effect_loaders.hpp"

#include <pce/sim/contact_effect.hpp>
#include <pce/sim/fcl_distance.hpp>
#include <pce/sim/obstacle.hpp>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace {

using pce::sim::Obstacle;
using pce::sim::ShapeKind;

Obstacle sphere(double r) {
  Obstacle o;
  o.name = "ball";
  o.kind = ShapeKind::sphere;
  o.radius = r;
  return o;
}
Obstacle box(const Eigen::Vector3d& h) {
  Obstacle o;
  o.name = "crate";
  o.kind = ShapeKind::box;
  o.half_extents = h;
  return o;
}
Obstacle capsule(double r, double half_length) {
  Obstacle o;
  o.name = "pill";
  o.kind = ShapeKind::capsule;
  o.radius = r;
  o.half_length = half_length;
  return o;
}

Eigen::Isometry3d random_pose(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0, 1);
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = q.toRotationMatrix();
  pose.translation() = Eigen::Vector3d(g(rng), g(rng), g(rng));
  return pose;
}

/// A random point within `reach` of the pose's origin (in its frame), in world coordinates.
Eigen::Vector3d random_point(std::mt19937_64& rng, const Eigen::Isometry3d& pose, double reach) {
  std::uniform_real_distribution<double> u(-reach, reach);
  return pose * Eigen::Vector3d(u(rng), u(rng), u(rng));
}

std::vector<Obstacle> shapes() { return {sphere(0.3), box(Eigen::Vector3d(0.2, 0.35, 0.1)), capsule(0.15, 0.4)}; }

TEST(ObstacleDistance, ClosedFormsAgreeWithFclGjkOutside) {
  std::mt19937_64 rng(1);
  for (const Obstacle& o : shapes()) {
    int compared = 0;
    double worst = 0;
    for (int trial = 0; trial < 400; ++trial) {
      const Eigen::Isometry3d pose = trial % 4 == 0 ? Eigen::Isometry3d::Identity() : random_pose(rng);
      const Eigen::Vector3d p = random_point(rng, pose, 1.2);
      const pce::sim::SurfaceDistance s = pce::sim::surface_distance(o, pose, p);
      if (!(s.distance > 1e-3)) continue;  // outside only: FCL's answer inside is not a distance
      const double reference = pce::sim::fcl_point_distance(o, pose, p);
      const double error = std::abs(s.distance - reference) / s.distance;
      worst = std::max(worst, error);
      EXPECT_LE(error, 1e-6) << "shape " << static_cast<int>(o.kind) << " closed form " << s.distance << " FCL "
                             << reference << " at " << p.transpose();
      ++compared;
    }
    EXPECT_GT(compared, 150) << "shape " << static_cast<int>(o.kind);
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", worst);
    RecordProperty("worst_relative_error_" + std::to_string(static_cast<int>(o.kind)), text);
  }
}

TEST(ObstacleDistance, NormalsAreUnitPointFromTheSurfaceAndAreTheGradient) {
  std::mt19937_64 rng(2);
  const double h = 1e-6;
  for (const Obstacle& o : shapes()) {
    int inside = 0;
    for (int trial = 0; trial < 300; ++trial) {
      const Eigen::Isometry3d pose = random_pose(rng);
      const Eigen::Vector3d p = random_point(rng, pose, 0.45);
      const pce::sim::SurfaceDistance s = pce::sim::surface_distance(o, pose, p);
      inside += s.distance < 0;
      EXPECT_NEAR(s.normal.norm(), 1.0, 1e-12);
      // The closest surface point p − d n is on the surface (inside and outside alike).
      EXPECT_NEAR(pce::sim::surface_distance(o, pose, p - s.distance * s.normal).distance, 0.0, 1e-12);
      // ∇d = n by central differences (points within h of a ridge of the box's inside
      // distance, where the gradient jumps, are vanishingly rare at random).
      Eigen::Vector3d fd;
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d e = Eigen::Vector3d::Zero();
        e[k] = h;
        fd[k] = (pce::sim::surface_distance(o, pose, p + e).distance -
                 pce::sim::surface_distance(o, pose, p - e).distance) /
                (2 * h);
      }
      EXPECT_LE((fd - s.normal).norm(), 1e-6) << "shape " << static_cast<int>(o.kind) << " d " << s.distance;
    }
    EXPECT_GT(inside, 5) << "the inside branch must be exercised";
  }
}

TEST(ObstacleDistance, BoxInsideAndOnEdgesAndCorners) {
  const Obstacle b = box(Eigen::Vector3d(1, 2, 3));
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  auto d = [&](double x, double y, double z) { return pce::sim::surface_distance(b, I, Eigen::Vector3d(x, y, z)); };
  EXPECT_DOUBLE_EQ(d(0, 0, 0).distance, -1.0);  // nearest face x = ±1
  EXPECT_NEAR(d(0.5, 1.9, 0).distance, -0.1, 1e-15);
  EXPECT_TRUE(d(0.5, 1.9, 0).normal.isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_NEAR(d(0, 0, -2.9).distance, -0.1, 1e-15);
  EXPECT_TRUE(d(0, 0, -2.9).normal.isApprox(-Eigen::Vector3d::UnitZ()));
  EXPECT_DOUBLE_EQ(d(4, 0, 0).distance, 3.0);  // face
  EXPECT_DOUBLE_EQ(d(4, 6, 0).distance, 5.0);  // edge: (3, 4) away
  EXPECT_TRUE(d(4, 6, 0).normal.isApprox(Eigen::Vector3d(0.6, 0.8, 0)));
  EXPECT_NEAR(d(-2, -3, 4).distance, std::sqrt(3.0), 1e-15);  // corner
  EXPECT_TRUE(d(-2, -3, 4).normal.isApprox(Eigen::Vector3d(-1, -1, 1).normalized()));
  EXPECT_DOUBLE_EQ(d(1, 0, 0).distance, 0.0);  // on a face: the face's normal
  EXPECT_TRUE(d(1, 0, 0).normal.isApprox(Eigen::Vector3d::UnitX()));
}

TEST(ObstacleDistance, MeshDistanceIsTheUnsignedBoxDistance) {
  // The 12-triangle surface mesh of a box is the box's surface exactly: the mesh's
  // unsigned distance is |box distance| everywhere, with the same normal outside.
  std::mt19937_64 rng(3);
  const Obstacle b = box(Eigen::Vector3d(0.3, 0.2, 0.5));
  Obstacle m;
  m.kind = ShapeKind::mesh;
  m.mesh = pce::sim::surface_mesh(b, Eigen::Isometry3d::Identity());
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Isometry3d pose = random_pose(rng);
    const Eigen::Vector3d p = random_point(rng, pose, 0.9);
    const pce::sim::SurfaceDistance sb = pce::sim::surface_distance(b, pose, p),
                                    sm = pce::sim::surface_distance(m, pose, p);
    EXPECT_NEAR(sm.distance, std::abs(sb.distance), 1e-12);
    if (sb.distance > 1e-9) {
      EXPECT_LE((sm.normal - sb.normal).norm(), 1e-9);
    } else if (sb.distance < -1e-9) {
      EXPECT_LE((sm.normal + sb.normal).norm(), 1e-9);  // inside: from the face toward p
    }
  }
  // On a face (distance 0): the triangle's normal.
  const pce::sim::SurfaceDistance on =
      pce::sim::surface_distance(m, Eigen::Isometry3d::Identity(), Eigen::Vector3d(0.1, 0.05, 0.5));
  EXPECT_EQ(on.distance, 0.0);
  EXPECT_TRUE(on.normal.isApprox(Eigen::Vector3d::UnitZ()));
}

TEST(ObstacleSurfaceMesh, OnTheSurfaceAndFacingOutward) {
  std::mt19937_64 rng(4);
  for (const Obstacle& o : shapes()) {
    const Eigen::Isometry3d pose = random_pose(rng);
    const pce::sim::Mesh m = pce::sim::surface_mesh(o, pose, 16);
    EXPECT_NO_THROW(pce::sim::validate(m, "surface_mesh"));
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
      EXPECT_NEAR(pce::sim::surface_distance(o, pose, m.positions.col(v)).distance, 0.0, 1e-12);
    double volume = 0;  // divergence theorem: Σ (a · (b × c)) / 6 > 0 when every face points outward
    for (Eigen::Index t = 0; t < m.triangles.cols(); ++t) {
      const Eigen::Vector3d a = m.positions.col(m.triangles(0, t)) - pose.translation(),
                            b = m.positions.col(m.triangles(1, t)) - pose.translation(),
                            c = m.positions.col(m.triangles(2, t)) - pose.translation();
      const Eigen::Vector3d n = (b - a).cross(c - a);
      EXPECT_GT(n.dot((a + b + c) / 3), 0)
          << "shape " << static_cast<int>(o.kind) << " triangle " << t << " faces inward";
      volume += a.dot(b.cross(c)) / 6;
    }
    const double pi = std::acos(-1.0);
    const double exact = o.kind == ShapeKind::sphere ? 4 * pi * std::pow(o.radius, 3) / 3
                         : o.kind == ShapeKind::box  ? 8 * o.half_extents.prod()
                                                    : pi * o.radius * o.radius * (2 * o.half_length + 4 * o.radius / 3);
    EXPECT_GT(volume, 0.8 * exact);  // inscribed polyhedra: a little less than the shape
    EXPECT_LE(volume, exact * (1 + 1e-12));
  }
}

TEST(ObstacleMotion, PoseFollowsThePrescribedPath) {
  Obstacle o = box(Eigen::Vector3d(1, 1, 1));
  o.position = Eigen::Vector3d(1, 2, 3);
  o.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()).toRotationMatrix();
  o.motion.velocity = Eigen::Vector3d(0.5, 0, -1);
  o.motion.angular_velocity = Eigen::Vector3d(0, 0, 2);  // 2 rad/s about world z
  o.motion.start = 1.0;
  o.motion.stop = 3.0;
  for (double t : {-1.0, 0.0, 1.0, 1.5, 2.25, 3.0, 7.0}) {
    const double tau = std::clamp(t - 1.0, 0.0, 2.0);
    const Eigen::Isometry3d pose = o.pose(t);
    EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(1 + 0.5 * tau, 2, 3 - tau), 1e-14)) << "t " << t;
    const Eigen::Matrix3d R = Eigen::AngleAxisd(2 * tau, Eigen::Vector3d::UnitZ()).toRotationMatrix() * o.rotation;
    EXPECT_LE((pose.linear() - R).norm(), 1e-14) << "t " << t;
    EXPECT_LE((pose.linear().transpose() * pose.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  }
  // No motion: the rest pose at every time.
  const Obstacle still = sphere(1);
  EXPECT_TRUE(still.pose(5.0).matrix().isApprox(Eigen::Isometry3d::Identity().matrix()));
}

// --- the obstacle_contact effect -------------------------------------------------------

struct Scene {
  pce::sim::Model model;
  std::vector<Obstacle> obstacles;
  nlohmann::json effects;
};

/// Vertices scattered around a sphere (centre (0, 0, 0), r 0.3) and a rotated box at
/// (1, 0, 0), many within the activation distance, a few far away; all outside.
Scene contact_scene(const std::string& penalty_type) {
  Scene s;
  Obstacle ball = sphere(0.3);
  Obstacle crate = box(Eigen::Vector3d(0.2, 0.1, 0.15));
  crate.position = Eigen::Vector3d(1, 0, 0);
  crate.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  crate.motion.velocity = Eigen::Vector3d(0, 0.1, 0);  // the pose at the END of the step must be used
  s.obstacles = {ball, crate};
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> gap(0.002, 0.06);
  const int n = 40;
  s.model.rest.resize(3, n);
  for (int i = 0; i < n; ++i) {
    const Obstacle& o = s.obstacles[static_cast<std::size_t>(i % 2)];
    const Eigen::Isometry3d pose = o.pose(0.1);
    Eigen::Vector3d p;
    do {
      p = pose * (Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized() * 0.4);
    } while (!(pce::sim::surface_distance(o, pose, p).distance > 0));
    // Move along the normal to a chosen gap.
    const pce::sim::SurfaceDistance sd = pce::sim::surface_distance(o, pose, p);
    p += (gap(rng) - sd.distance) * sd.normal;
    if (i >= n - 4) p += Eigen::Vector3d(0, 0, 3);  // far: culled
    s.model.rest.col(i) = p;
  }
  s.model.mass = Eigen::VectorXd::Ones(n);
  s.effects = nlohmann::json::array();
  nlohmann::json penalty = {{"type", penalty_type}, {"stiffness", 100.0}, {"distance", 0.05}};
  if (penalty_type == "cubic") penalty["delta"] = 1e-4;
  s.effects.push_back({{"type", "obstacle_contact"}, {"penalty", penalty}});
  return s;
}

std::unique_ptr<pce::sim::ContactEffect> build(const Scene& s, double time) {
  pce::sim::BuildContext ctx;
  ctx.model = &s.model;
  ctx.obstacles = &s.obstacles;
  ctx.dt = 0.1;
  const pce::sim::Params p(s.effects[0], "scene.json", "effects[0]");
  auto effect = pce::sim::load_obstacle_contact(p, ctx);
  pce::sim::StepContext step;
  step.frame = 1;
  step.time = time;
  step.dt = 0.1;
  step.model = &s.model;
  step.x_start = &s.model.rest;
  effect->begin_step(step);
  return std::unique_ptr<pce::sim::ContactEffect>(pce::sim::as_contact(effect.release()));
}

Eigen::MatrixXd dense_hessian(pce::sim::Effect& e, const Eigen::Matrix3Xd& x) {
  const int n = static_cast<int>(x.cols());
  pce::sim::Pattern pattern;
  e.declare(pattern);
  pce::sim::BlockHessian H;
  H.set_pattern(n, pattern);
  H.set_zero();
  e.evaluate(x, nullptr, &H);
  const Eigen::MatrixXd upper = Eigen::MatrixXd(H.matrix());
  Eigen::MatrixXd full = upper + upper.transpose();
  full.diagonal() = upper.diagonal();
  return full;
}

TEST(ObstacleContact, GradientMatchesFiniteDifferencesAndHessianIsPsd) {
  for (const char* type : {"quadratic", "cubic", "log_barrier"}) {
    const Scene s = contact_scene(type);
    auto e = build(s, 0.1);
    const Eigen::Matrix3Xd& x = s.model.rest;
    Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, x.cols());
    const double E = e->evaluate(x, &g, nullptr);
    EXPECT_GT(E, 0) << type;
    EXPECT_TRUE(std::isfinite(E)) << type;
    pce::sim::EffectCounters counters;
    e->report(counters);
    EXPECT_GT(counters.at("obstacle_contacts"), 10) << type;
    EXPECT_LT(counters.at("obstacle_contacts"), static_cast<double>(x.cols())) << type;
    EXPECT_GT(counters.at("obstacle_min_distance"), 0.0) << type;
    EXPECT_LT(counters.at("obstacle_min_distance"), 0.01) << type;
    const double h = 1e-7;
    double scale = 0;
    for (Eigen::Index i = 0; i < x.cols(); ++i) scale = std::max(scale, g.col(i).norm());
    for (Eigen::Index i = 0; i < x.cols(); ++i)
      for (int k = 0; k < 3; ++k) {
        Eigen::Matrix3Xd xp = x, xm = x;
        xp(k, i) += h;
        xm(k, i) -= h;
        const double fd = (e->evaluate(xp, nullptr, nullptr) - e->evaluate(xm, nullptr, nullptr)) / (2 * h);
        EXPECT_NEAR(g(k, i), fd, 1e-5 * scale) << type << " vertex " << i << " axis " << k;
      }
    const Eigen::MatrixXd H = dense_hessian(*e, x);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * std::max(1.0, eig.eigenvalues().maxCoeff())) << type;
    EXPECT_GT(eig.eigenvalues().maxCoeff(), 0) << type;
    // Along each active vertex's normal the Hessian is the penalty's ψ″: check one
    // direction against finite differences of the gradient.
    int checked = 0;
    for (Eigen::Index i = 0; i < x.cols() && checked < 5; ++i) {
      if (g.col(i).norm() == 0) continue;
      const Eigen::Vector3d n = -g.col(i).normalized();  // ψ′ < 0: the gradient points into the obstacle
      Eigen::Matrix3Xd xp = x, xm = x;
      xp.col(i) += h * n;
      xm.col(i) -= h * n;
      Eigen::Matrix3Xd gp = Eigen::Matrix3Xd::Zero(3, x.cols()), gm = gp;
      e->evaluate(xp, &gp, nullptr);
      e->evaluate(xm, &gm, nullptr);
      const double fd = n.dot(gp.col(i) - gm.col(i)) / (2 * h);
      const double hn = n.dot(H.block<3, 3>(3 * i, 3 * i) * n);
      EXPECT_NEAR(hn, fd, 1e-4 * std::max(1.0, std::abs(fd))) << type << " vertex " << i;
      ++checked;
    }
  }
}

TEST(ObstacleContact, UsesThePoseAtTheEndOfTheStep) {
  const Scene s = contact_scene("quadratic");
  auto early = build(s, 0.0), late = build(s, 0.1);  // the box moves 0.01 between the two
  EXPECT_NE(early->evaluate(s.model.rest, nullptr, nullptr), late->evaluate(s.model.rest, nullptr, nullptr));
  // Rebuilding for time 0.1 and 0.1 gives the same energy (poses from begin_step only).
  auto again = build(s, 0.1);
  EXPECT_EQ(again->evaluate(s.model.rest, nullptr, nullptr), late->evaluate(s.model.rest, nullptr, nullptr));
}

TEST(ObstacleContact, BarrierIsInfiniteInsideAndMaxStepKeepsDistancesPositive) {
  const Scene s = contact_scene("log_barrier");
  auto e = build(s, 0.1);
  Eigen::Matrix3Xd x = s.model.rest;
  // A step that drives every vertex through the obstacle's centre.
  Eigen::Matrix3Xd dx(3, x.cols());
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    dx.col(i) = 2 * (s.obstacles[static_cast<std::size_t>(i % 2)].pose(0.1).translation() - x.col(i));
  const double t = e->max_step(x, dx);
  EXPECT_GT(t, 0);
  EXPECT_LT(t, 1);
  const Eigen::Matrix3Xd y = x + t * dx;
  const double E = e->evaluate(y, nullptr, nullptr);
  EXPECT_TRUE(std::isfinite(E));
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    for (std::size_t k = 0; k < 2; ++k)
      EXPECT_GT(pce::sim::surface_distance(s.obstacles[k], s.obstacles[k].pose(0.1), y.col(i)).distance, 0);
  // The full step ends inside: +∞, returned (no exception), gradient untouched.
  Eigen::Matrix3Xd g = Eigen::Matrix3Xd::Zero(3, x.cols());
  double inside = 0;
  EXPECT_NO_THROW(inside = e->evaluate(x + 0.5 * dx, &g, nullptr));
  EXPECT_EQ(inside, std::numeric_limits<double>::infinity());
  EXPECT_EQ(g.norm(), 0.0);
  // Non-barrier penalties allow the full step.
  auto q = build(contact_scene("quadratic"), 0.1);
  EXPECT_EQ(q->max_step(x, dx), 1.0);
  EXPECT_TRUE(std::isfinite(q->evaluate(x + 0.5 * dx, nullptr, nullptr)));
}

TEST(ObstacleContact, ObstacleListSelectsAndBadNamesNameTheirPath) {
  Scene s = contact_scene("quadratic");
  s.effects[0]["obstacles"] = {"crate"};
  auto only_box = build(s, 0.1);
  pce::sim::EffectCounters c_box, c_all;
  only_box->evaluate(s.model.rest, nullptr, nullptr);
  only_box->report(c_box);
  auto all = build(contact_scene("quadratic"), 0.1);
  all->evaluate(s.model.rest, nullptr, nullptr);
  all->report(c_all);
  EXPECT_GT(c_box.at("obstacle_contacts"), 0);
  EXPECT_LT(c_box.at("obstacle_contacts"), c_all.at("obstacle_contacts"));

  auto where = [&](const nlohmann::json& obstacles) {
    Scene bad = contact_scene("quadratic");
    bad.effects[0]["obstacles"] = obstacles;
    try {
      build(bad, 0.1);
    } catch (const pce::sim::InputError& e) {
      EXPECT_EQ(e.file(), "scene.json");
      return e.where();
    }
    return std::string("no error");
  };
  EXPECT_EQ(where({"ball", "anvil"}), "effects[0].obstacles[1]");
  EXPECT_EQ(where({"anvil"}), "effects[0].obstacles[0]");
  EXPECT_EQ(where({"ball", "ball"}), "effects[0].obstacles[1]");
  EXPECT_EQ(where({"ball", 3}), "effects[0].obstacles[1]");
  EXPECT_EQ(where(nlohmann::json::array()), "effects[0].obstacles");
  EXPECT_EQ(where("ball"), "effects[0].obstacles");
  Scene typo = contact_scene("quadratic");
  typo.effects[0]["obstacle"] = {"ball"};
  EXPECT_THROW(build(typo, 0.1), pce::sim::InputError);
  Scene no_penalty = contact_scene("quadratic");
  no_penalty.effects[0].erase("penalty");
  EXPECT_THROW(build(no_penalty, 0.1), pce::sim::InputError);
}

}  // namespace
