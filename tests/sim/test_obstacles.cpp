// SPDX-License-Identifier: MIT
// pce::sim kinematic obstacles (src/sim/obstacles, src/sim/effects/obstacle_contact.cpp):
// the closed-form distances agree with FCL's GJK (libccd) at random points OUTSIDE the
// shapes (inside, FCL reports penetration by another algorithm, so inside points are
// checked by finite differences and by the mesh distance instead); normals are unit, point
// from the surface to the point and are the distance's gradient; prescribed poses, by a
// constant velocity and by keyframes (linear and smooth, against poses worked by hand; the
// smooth path C¹ and at rest at every keyframe, the linear one piecewise constant in
// velocity; a keyframed ball pushes a sheet); surface meshes lie on the surface and face
// outward; the obstacle_contact effect's gradient
// matches finite differences, its Hessian is PSD, the barrier's domain is kept; bad scene
// input names its JSON path.
#include "scene/effect_loaders.hpp"

#include <pce/sim/contact_effect.hpp>
#include <pce/sim/fcl_distance.hpp>
#include <pce/sim/input_error.hpp>
#include <pce/sim/obstacle.hpp>
#include <pce/sim/scene.hpp>
#include <pce/sim/simulation.hpp>

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

// --- keyframed motion ------------------------------------------------------------------

using pce::sim::Interpolation;
using pce::sim::Keyframe;
using pce::sim::Motion;

Eigen::Matrix3d rot(double degrees, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(degrees * M_PI / 180, axis.normalized()).toRotationMatrix();
}

Motion keyframed(std::vector<Keyframe> keys, Interpolation interpolation = Interpolation::linear) {
  Motion m;
  m.keyframes = std::move(keys);
  m.interpolation = interpolation;
  return m;
}

/// s(u) = 3u² − 2u³ at u = 1/4: 3/16 − 2/64.
constexpr double kSmoothQuarter = 0.15625;

TEST(ObstacleMotion, KeyframedTranslationAtAndBetweenKeyframes) {
  // From t = 1 s to 3 s the body moves from its rest pose by (2, 0, −1); it holds the first
  // keyframe before 1 s and the last after 3 s.
  Obstacle o = box(Eigen::Vector3d(1, 1, 1));
  o.position = Eigen::Vector3d(1, 2, 3);
  o.rotation = rot(17, Eigen::Vector3d::UnitX());
  for (const Interpolation how : {Interpolation::linear, Interpolation::smooth}) {
    SCOPED_TRACE(how == Interpolation::linear ? "linear" : "smooth");
    o.motion = keyframed({Keyframe{1.0, {0, 0, 0}}, Keyframe{3.0, {2, 0, -1}}}, how);
    const double quarter = how == Interpolation::linear ? 0.25 : kSmoothQuarter;
    const struct {
      double t, w;  // time and the fraction of (2, 0, −1) moved by then
    } cases[] = {{-1.0, 0}, {0.0, 0}, {1.0, 0}, {1.5, quarter}, {2.0, 0.5}, {2.5, 1 - quarter}, {3.0, 1}, {9.0, 1}};
    for (const auto& c : cases) {
      const Eigen::Isometry3d pose = o.pose(c.t);
      EXPECT_LT((pose.translation() - Eigen::Vector3d(1 + 2 * c.w, 2, 3 - c.w)).norm(), 1e-14) << "t " << c.t;
      EXPECT_EQ(pose.linear(), o.rotation) << "t " << c.t;  // no rotation keyframed: exactly R₀
    }
    // At a keyframe the pose is the keyframe's exactly.
    EXPECT_EQ(o.pose(3.0).translation(), Eigen::Vector3d(3, 2, 2));
    EXPECT_EQ(o.pose(1.0).translation(), o.position);
  }
}

TEST(ObstacleMotion, KeyframedRotationAboutTheCentre) {
  // A quarter turn about z from t = 0 to 1 s, about the obstacle's own centre (1, 2, 3),
  // after its orientation at rest R₀.
  Obstacle o = box(Eigen::Vector3d(1, 1, 1));
  o.position = Eigen::Vector3d(1, 2, 3);
  o.rotation = rot(30, Eigen::Vector3d::UnitX());
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  for (const Interpolation how : {Interpolation::linear, Interpolation::smooth}) {
    SCOPED_TRACE(how == Interpolation::linear ? "linear" : "smooth");
    o.motion = keyframed({Keyframe{0.0}, Keyframe{1.0, {0, 0, 0}, rot(90, z)}}, how);
    const double quarter = how == Interpolation::linear ? 0.25 : kSmoothQuarter;
    const struct {
      double t, degrees;
    } cases[] = {{0.0, 0}, {0.25, 90 * quarter}, {0.5, 45}, {0.75, 90 * (1 - quarter)}, {1.0, 90}, {4.0, 90}};
    for (const auto& c : cases) {
      const Eigen::Isometry3d pose = o.pose(c.t);
      EXPECT_EQ(pose.translation(), o.position) << "t " << c.t;
      EXPECT_LT((pose.linear() - rot(c.degrees, z) * o.rotation).norm(), 1e-14) << "t " << c.t;
    }
    // The local point (1, 0, 0) of an unrotated body at the half turn: (cos 45°, sin 45°, 0)
    // from the centre.
    const Eigen::Vector3d p = o.motion.apply(0.5, o.position, o.position + Eigen::Vector3d(1, 0, 0));
    EXPECT_LT((p - o.position - Eigen::Vector3d(std::sqrt(0.5), std::sqrt(0.5), 0)).norm(), 1e-14);
  }
}

TEST(ObstacleMotion, KeyframedTranslationAndRotationCombined) {
  // Three keyframes: at rest at t = 0, then by t = 2 s a quarter turn about z and 1 m along
  // y, then by t = 4 s a half turn and 2 m further along x. A point 1 m along x from the
  // centre c is at c + d(t) + R(t)(1, 0, 0).
  const Eigen::Vector3d c(0.5, -1, 2), z = Eigen::Vector3d::UnitZ();
  Motion m = keyframed({Keyframe{0.0}, Keyframe{2.0, {0, 1, 0}, rot(90, z)}, Keyframe{4.0, {2, 1, 0}, rot(180, z)}});
  const Eigen::Vector3d p = c + Eigen::Vector3d(1, 0, 0);
  const double h = std::sqrt(0.5);
  const struct {
    double t;
    Eigen::Vector3d at;                    // p's position less c, by hand
  } linear[] = {{0.0, {1, 0, 0}},          // rest
                {1.0, {h, 0.5 + h, 0}},    // d = (0, ½, 0), R = Rz(45°)
                {2.0, {0, 2, 0}},          // d = (0, 1, 0), R = Rz(90°)
                {3.0, {1 - h, 1 + h, 0}},  // d = (1, 1, 0), R = Rz(135°)
                {4.0, {1, 1, 0}},          // d = (2, 1, 0), R = Rz(180°)
                {5.0, {1, 1, 0}}};         // holds
  for (const auto& k : linear) EXPECT_LT((m.apply(k.t, c, p) - c - k.at).norm(), 1e-14) << "t " << k.t;
  m.interpolation = Interpolation::smooth;
  // A quarter of the second segment's time: s = 5/32 of the way, 90° + 14.0625° turned.
  const double a = (90 + 90 * kSmoothQuarter) * M_PI / 180;
  const Eigen::Vector3d smooth_at = Eigen::Vector3d(2 * kSmoothQuarter + std::cos(a), 1 + std::sin(a), 0);
  EXPECT_LT((m.apply(2.5, c, p) - c - smooth_at).norm(), 1e-14);
  EXPECT_LT((m.apply(2.0, c, p) - c - Eigen::Vector3d(0, 2, 0)).norm(), 1e-14);
}

TEST(ObstacleMotion, KeyframedRotationTakesTheShortWay) {
  // 0° then 270° about z: the relative rotation is −90°, so half way the body has turned −45°.
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Motion m = keyframed({Keyframe{0.0}, Keyframe{1.0, {0, 0, 0}, rot(270, z)}});
  EXPECT_LT((m.spin(0.5) - rot(-45, z)).norm(), 1e-14);
  // Keyframes that differ about two axes: R(t) = R₀ exp(u log(R₀ᵀ R₁)), by hand half way:
  // R₀ = Rx(90°), R₁ = Rx(90°) Rz(90°), so Rx(90°) Rz(45°).
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX();
  const Motion turn =
      keyframed({Keyframe{0.0, {0, 0, 0}, rot(90, x)}, Keyframe{2.0, {0, 0, 0}, rot(90, x) * rot(90, z)}});
  EXPECT_LT((turn.spin(1.0) - rot(90, x) * rot(45, z)).norm(), 1e-14);
  EXPECT_EQ(turn.spin(-1.0), rot(90, x));  // before the first keyframe: the first, exactly
}

/// Central difference of `m.apply` of point `p` about `c` at time t.
Eigen::Vector3d velocity(const Motion& m, const Eigen::Vector3d& c, const Eigen::Vector3d& p, double t,
                         double h = 1e-6) {
  return (m.apply(t + h, c, p) - m.apply(t - h, c, p)) / (2 * h);
}

TEST(ObstacleMotion, SmoothKeyframesAreC1AndStopAtEveryKeyframeLinearOnesArePiecewiseConstant) {
  // Three keyframes: 1 m along x and a quarter turn about z by t = 1 s, then 1 m along y
  // and a quarter turn back by t = 2 s. A point off the centre both translates and turns.
  const Eigen::Vector3d c(0, 0, 0), p(0.3, 0.2, 0.1), z = Eigen::Vector3d::UnitZ();
  Motion m =
      keyframed({Keyframe{0.0}, Keyframe{1.0, {1, 0, 0}, rot(90, z)}, Keyframe{2.0, {1, 1, 0}}}, Interpolation::smooth);
  // Zero velocity at every keyframe (and before and after them).
  for (double t : {-0.5, 0.0, 1.0, 2.0, 3.0}) EXPECT_LT(velocity(m, c, p, t).norm(), 1e-5) << "t " << t;
  // Continuous across the middle keyframe: the velocity just before and just after it
  // approaches zero from both sides, linearly in the distance d: |s′(u)| = 6u(1 − u) ≤ 6d,
  // times the point's speed per unit of s, at most 1 m (translation) + π/2 |p − c|
  // (turning).
  const double reach = 1 + M_PI / 2 * (p - c).norm();
  for (double d : {1e-2, 1e-3, 1e-4}) {
    EXPECT_LT(velocity(m, c, p, 1 - d).norm(), 6 * d * reach) << "before, d " << d;
    EXPECT_LT(velocity(m, c, p, 1 + d).norm(), 6 * d * reach) << "after, d " << d;
  }
  // Continuous everywhere: velocities 10⁻³ s apart differ by at most 10⁻³ s times the
  // largest acceleration, |s″| reach + (1.5 π/2)² |p − c| ≤ 12 m/s² (1.5 the largest s′).
  double largest = 0;
  for (double t = 0.01; t < 2; t += 0.01) {
    largest = std::max(largest, velocity(m, c, p, t).norm());
    EXPECT_LT((velocity(m, c, p, t + 1e-3) - velocity(m, c, p, t)).norm(), 1e-3 * 12) << "t " << t;
  }
  EXPECT_GT(largest, 1.0);  // it does move: 1.5 m/s peak along x alone
  // Linear: the translation's velocity is constant within a segment and jumps at the keyframe.
  m.interpolation = Interpolation::linear;
  const Eigen::Vector3d o(0, 0, 0);  // the centre itself only translates
  for (double t : {0.1, 0.5, 0.9}) EXPECT_LT((velocity(m, o, o, t) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-8);
  for (double t : {1.1, 1.5, 1.9}) EXPECT_LT((velocity(m, o, o, t) - Eigen::Vector3d(0, 1, 0)).norm(), 1e-8);
  // The point off the centre turns at a constant rate: its speed about c is constant.
  const double r = Eigen::Vector2d(p.x(), p.y()).norm(), rate = M_PI / 2;  // rad/s
  for (double t : {0.1, 0.5, 0.9})
    EXPECT_NEAR((velocity(m, c, p, t) - Eigen::Vector3d(1, 0, 0)).norm(), rate * r, 1e-8) << "t " << t;
}

TEST(ObstacleMotion, OneKeyframeHoldsItsPoseAtEveryTime) {
  Obstacle o = sphere(0.5);
  o.motion = keyframed({Keyframe{2.0, {0, 0, 1}, rot(90, Eigen::Vector3d::UnitY())}});
  for (double t : {0.0, 2.0, 5.0}) {
    EXPECT_EQ(o.pose(t).translation(), Eigen::Vector3d(0, 0, 1));
    EXPECT_EQ(o.pose(t).linear(), o.motion.keyframes[0].rotation);
  }
}

TEST(ObstacleMotion, AKeyframedBallPushesASheetUpAndHolds) {
  // A sheet 0.6 m square, pinned along two opposite edges, no gravity; a ball of radius
  // 0.1 m 0.3 m below its centre rises 0.25 m between t = 0.05 s and 0.25 s (smooth) and then
  // holds, its top 5 cm above the sheet's rest plane: the sheet's centre is pushed up onto
  // it and stays there.
  const nlohmann::json scene = nlohmann::json::parse(R"({
    "dt": 0.01, "frames": 50,
    "meshes": [{"name": "sheet", "generator": {"type": "grid", "width": 0.6, "height": 0.6, "nx": 12, "ny": 12}}],
    "obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.1, "position": [0, 0, -0.3],
                   "motion": {"interpolation": "smooth", "keyframes": [
                     {"time": 0.05}, {"time": 0.25, "translation": [0, 0, 0.25]}]}}],
    "effects": [{"type": "stretching", "stiffness": 100}, {"type": "bending", "stiffness": 1e-4},
                {"type": "damping", "coefficient": 2},
                {"type": "pins", "stiffness": 1e4, "groups": [{"box": {"min": [-1, -1, -1], "max": [-0.29, 1, 1]}},
                                                              {"box": {"min": [0.29, -1, -1], "max": [1, 1, 1]}}]},
                {"type": "obstacle_contact", "penalty": {"type": "quadratic", "stiffness": 1e4, "distance": 0.005}}]
  })");
  auto loaded = pce::sim::load_scene_text(scene.dump(), "push.json", PCE_TEST_TMP);
  pce::sim::Simulation& sim = loaded->simulation;
  const pce::sim::Obstacle& ball = sim.obstacles.at(0);
  int centre = 0;  // the vertex at the sheet's centre
  (sim.model.rest.colwise().norm()).minCoeff(&centre);
  ASSERT_LT(sim.model.rest.col(centre).norm(), 1e-12);
  double contacts_before = 0, contacts_after = 0;
  for (int f = 1; f <= 50; ++f) {
    const pce::sim::FrameStats st = sim.step();
    const double z = sim.x(2, centre);
    if (f <= 15) {
      // The ball's top is below the sheet until t = 0.15 s: the sheet lies still.
      EXPECT_LT(std::abs(z), 1e-9) << "frame " << f;
      contacts_before += st.counters.at("obstacle_contacts");
    } else {
      contacts_after += st.counters.at("obstacle_contacts");
    }
    // Never pushed into the ball beyond the penalty's give.
    EXPECT_GT(pce::sim::surface_distance(ball, ball.pose(sim.time), sim.x.col(centre)).distance, -1e-3)
        << "frame " << f;
  }
  EXPECT_EQ(contacts_before, 0);
  EXPECT_GT(contacts_after, 0);
  // At the end (t = 0.5 s) the ball holds its last keyframe, top at z = 0.05, and the sheet's
  // centre rests on it, within the activation distance.
  EXPECT_LT((ball.pose(0.5).translation() - Eigen::Vector3d(0, 0, -0.05)).norm(), 1e-15);
  EXPECT_EQ(ball.pose(0.3).translation(), ball.pose(0.5).translation());
  const double gap = pce::sim::surface_distance(ball, ball.pose(sim.time), sim.x.col(centre)).distance;
  EXPECT_GT(gap, -1e-3);
  EXPECT_LT(gap, 0.005);
  EXPECT_GT(sim.x(2, centre), 0.045);
  // The pinned edges stay put.
  for (Eigen::Index i = 0; i < sim.x.cols(); ++i)
    if (std::abs(sim.model.rest(0, i)) > 0.29) {
      EXPECT_LT(std::abs(sim.x(2, i)), 1e-3) << "vertex " << i;
    }
}

TEST(ObstacleMotion, PosesPutBetweenStepsReplayAKeyframedRunBitForBit) {
  // A keyframed ball rises through two sheets, each in contact with it through its own
  // obstacle_contact entry; the same scene with the ball still, put before every step at the
  // pose the keyframes give at the step's end (which reaches both entries' copies), runs the
  // same bit for bit, and the put ball's `pose` keeps its history (output draws it).
  nlohmann::json scene = nlohmann::json::parse(R"({
    "dt": 0.01, "frames": 30,
    "meshes": [{"name": "sheet", "generator": {"type": "grid", "width": 0.6, "height": 0.6, "nx": 10, "ny": 10}},
               {"name": "upper", "generator": {"type": "grid", "width": 0.6, "height": 0.6, "nx": 6, "ny": 6},
                "transform": {"translation": [0, 0, 0.02]}}],
    "obstacles": [{"name": "ball", "shape": "sphere", "radius": 0.1, "position": [0, 0, -0.3],
                   "motion": {"interpolation": "smooth", "keyframes": [
                     {"time": 0.02}, {"time": 0.2, "translation": [0, 0, 0.25],
                                      "rotation": {"axis": [1, 0, 0], "degrees": 40}}]}},
                  {"name": "far", "shape": "box", "half_extents": [0.1, 0.1, 0.1], "position": [0, 0, 5]}],
    "effects": [{"type": "stretching", "stiffness": 100}, {"type": "damping", "coefficient": 2},
                {"type": "pins", "stiffness": 1e4, "groups": [{"box": {"min": [-1, -1, -1], "max": [-0.29, 1, 1]}},
                                                              {"box": {"min": [0.29, -1, -1], "max": [1, 1, 1]}}]},
                {"type": "obstacle_contact", "meshes": ["sheet"], "obstacles": ["ball"],
                 "penalty": {"type": "quadratic", "stiffness": 1e4, "distance": 0.005}},
                {"type": "obstacle_contact", "meshes": ["upper"], "obstacles": ["ball", "far"],
                 "penalty": {"type": "cubic", "stiffness": 1e5, "distance": 0.01}}]
  })");
  auto keyed = pce::sim::load_scene_text(scene.dump(), "keyed.json", PCE_TEST_TMP);
  scene["obstacles"][0].erase("motion");
  auto put = pce::sim::load_scene_text(scene.dump(), "put.json", PCE_TEST_TMP);
  pce::sim::Simulation &a = keyed->simulation, &b = put->simulation;
  const pce::sim::Obstacle& path = a.obstacles.at(0);
  double contacts = 0;
  for (int f = 1; f <= 30; ++f) {
    b.set_obstacle_pose("ball", path.pose(b.time + b.solver.dt));
    contacts += a.step().counters.at("obstacle_contacts");
    b.step();
    ASSERT_EQ(a.x, b.x) << "frame " << f;
    ASSERT_EQ(a.v, b.v) << "frame " << f;
    EXPECT_EQ(b.obstacles.at(0).pose(b.time).matrix(), path.pose(a.time).matrix()) << "frame " << f;
  }
  EXPECT_GT(contacts, 0);  // the ball reached the sheets and pushed both up
  const auto& sheets = a.model.meshes;
  EXPECT_GT(a.x.row(2).segment(sheets[0].first_vertex, sheets[0].vertex_count).maxCoeff(), 0.03);
  EXPECT_GT(a.x.row(2).segment(sheets[1].first_vertex, sheets[1].vertex_count).maxCoeff(), 0.04);
  EXPECT_EQ(b.obstacles.at(0).pose(0.0).translation(), Eigen::Vector3d(0, 0, -0.3));  // before the first put
  const std::vector<pce::sim::PlacedPose>& placed = b.obstacles.at(0).placed;
  EXPECT_NEAR(placed.at(10).from, 0.105, 1e-15);  // held from the middle of its step on
  EXPECT_EQ(b.obstacles.at(0).pose(placed[10].from).matrix(), placed[10].pose.matrix());
  EXPECT_EQ(b.obstacles.at(0).pose(placed[10].from - 1e-9).matrix(), placed[9].pose.matrix());
  EXPECT_EQ(b.obstacles.at(0).placed.size(), 30u);

  // Put twice before one step: the second replaces the first. Errors name the argument.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() << 0, 0, 1;
  b.set_obstacle_pose("ball", pose);
  pose.translation() << 0, 0, 2;
  b.set_obstacle_pose("ball", pose);
  EXPECT_EQ(b.obstacles.at(0).placed.size(), 31u);
  EXPECT_EQ(b.obstacles.at(0).pose(b.time + b.solver.dt).translation(), Eigen::Vector3d(0, 0, 2));
  const auto error = [&](const std::string& name, const Eigen::Isometry3d& p) {
    try {
      b.set_obstacle_pose(name, p);
    } catch (const pce::sim::ArgumentError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error("wall", pose), "name: no obstacle named \"wall\" (the obstacles: \"ball\", \"far\")");
  Eigen::Isometry3d bad = pose;
  bad.translation() << 0, 0, 2e6;
  EXPECT_EQ(error("ball", bad).rfind("translation: ", 0), 0u) << error("ball", bad);
  bad = pose;
  bad.linear() = 2 * Eigen::Matrix3d::Identity();
  EXPECT_EQ(error("ball", bad), "rotation: expected a rotation matrix (orthonormal, determinant 1)");
  bad.linear() = -Eigen::Matrix3d::Identity();  // a reflection
  EXPECT_EQ(error("ball", bad), "rotation: expected a rotation matrix (orthonormal, determinant 1)");
  EXPECT_EQ(b.obstacles.at(0).pose(b.time + b.solver.dt).translation(), Eigen::Vector3d(0, 0, 2));  // unchanged
}

TEST(ObstacleMotion, AFloorPutBetweenStepsDragsASheetByFriction) {
  // A sheet rests on a box floor with friction; the floor is put 2 mm further along +x before
  // every step (0.2 m/s). Friction sees the surface move from its pose at the step's start to
  // the new one, so the sheet is dragged along as by the same constant-velocity motion (to
  // rounding: the motion's start pose is taken at t + h − h), and not at all without friction.
  nlohmann::json scene = nlohmann::json::parse(R"({
    "dt": 0.01, "frames": 20,
    "meshes": [{"name": "sheet", "generator": {"type": "grid", "width": 0.2, "height": 0.2, "nx": 4, "ny": 4}}],
    "obstacles": [{"name": "floor", "shape": "box", "half_extents": [1, 1, 0.1], "position": [0, 0, -0.103],
                   "motion": {"velocity": [0.2, 0, 0]}}],
    "effects": [{"type": "gravity"}, {"type": "stretching", "stiffness": 100},
                {"type": "obstacle_contact", "penalty": {"type": "quadratic", "stiffness": 1e4, "distance": 0.005},
                 "friction": {"coefficient": 0.8}}]
  })");
  auto moving = pce::sim::load_scene_text(scene.dump(), "moving.json", PCE_TEST_TMP);
  scene["obstacles"][0].erase("motion");
  auto put = pce::sim::load_scene_text(scene.dump(), "put.json", PCE_TEST_TMP);
  scene["effects"][2].erase("friction");
  auto slippery = pce::sim::load_scene_text(scene.dump(), "slippery.json", PCE_TEST_TMP);
  pce::sim::Simulation &a = moving->simulation, &b = put->simulation, &c = slippery->simulation;
  for (int f = 1; f <= 20; ++f) {
    for (pce::sim::Simulation* s : {&b, &c}) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.translation() << 0.002 * f, 0, -0.103;
      s->set_obstacle_pose("floor", pose);
    }
    a.step();
    b.step();
    c.step();
  }
  const double dragged = (b.x.row(0) - b.model.rest.row(0)).mean(), slid = (c.x.row(0) - c.model.rest.row(0)).mean();
  std::printf("mean x displacement after 20 steps: put %.6f m, moving %.6f m, frictionless %.2g m (floor: 0.04 m)\n",
              dragged, (a.x.row(0) - a.model.rest.row(0)).mean(), slid);
  EXPECT_GT(dragged, 0.03);
  EXPECT_LT(std::abs(slid), 1e-9);
  EXPECT_LT((a.x - b.x).cwiseAbs().maxCoeff(), 1e-9);
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
  const double t = e->begin_line_search(x, dx);
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
  // Non-barrier penalties without a minimum separation allow the full step.
  Scene plain = contact_scene("quadratic");
  plain.effects[0]["min_separation"] = 0.0;
  auto q = build(plain, 0.1);
  EXPECT_EQ(q->begin_line_search(x, dx), 1.0);
  EXPECT_TRUE(std::isfinite(q->evaluate(x + 0.5 * dx, nullptr, nullptr)));
}

/// The smallest distance from a vertex of y to either obstacle of `s` (at time 0.1), over the
/// vertices whose distance at x is at least `from`.
double closest_of(const Scene& s, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& y, double from) {
  double closest = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < x.cols(); ++i)
    for (const Obstacle& o : s.obstacles)
      if (pce::sim::surface_distance(o, o.pose(0.1), x.col(i)).distance >= from)
        closest = std::min(closest, pce::sim::surface_distance(o, o.pose(0.1), y.col(i)).distance);
  return closest;
}

TEST(ObstacleContact, TheFloorKeepsEveryVertexAtItsMinimumSeparationAlongTheStep) {
  // Every penalty, the default floor f d = 0.01 · 0.05 (0.5 mm): the line search's bound
  // keeps every vertex that starts at or above it at least that far from both obstacles at
  // every point of the bounded step (sampled), for a step through the obstacles' centres and
  // for one pressing the vertices, moved to 1.5 floors off their surfaces, straight in; the
  // pairs the floor stopped are held when pressed in (end_line_search); a step that slides
  // those vertices along the surfaces is not bounded.
  const double floor = 0.01 * 0.05;
  for (const char* type : {"quadratic", "cubic", "log_barrier"}) {
    SCOPED_TRACE(type);
    const Scene s = contact_scene(type);
    auto e = build(s, 0.1);
    const Eigen::Matrix3Xd x = s.model.rest;
    Eigen::Matrix3Xd through(3, x.cols()), near = x, press(3, x.cols()), slide(3, x.cols());
    for (Eigen::Index i = 0; i < x.cols(); ++i) {
      const Obstacle& o = s.obstacles[static_cast<std::size_t>(i % 2)];
      through.col(i) = 2 * (o.pose(0.1).translation() - x.col(i));
      const pce::sim::SurfaceDistance sd = pce::sim::surface_distance(o, o.pose(0.1), x.col(i));
      if (i < x.cols() - 4) near.col(i) += (1.5 * floor - sd.distance) * sd.normal;  // the far four stay culled
      const Eigen::Vector3d n = pce::sim::surface_distance(o, o.pose(0.1), near.col(i)).normal;
      press.col(i) = -0.01 * n;
      slide.col(i) = 0.002 * n.unitOrthogonal();
    }
    for (const auto& [from, dx] : {std::pair{x, through}, std::pair{near, press}}) {
      const double t = e->begin_line_search(from, dx);
      EXPECT_GT(t, 0);
      EXPECT_LT(t, 1);
      double closest = std::numeric_limits<double>::infinity();
      for (int j = 0; j <= 64; ++j) closest = std::min(closest, closest_of(s, from, from + (t * j / 64.0) * dx, floor));
      EXPECT_GE(closest, floor * (1 - 1e-9));
      EXPECT_LT(closest, 3 * floor);  // the step went as far as the floor let it
    }
    EXPECT_TRUE(e->end_line_search(near + e->begin_line_search(near, press) * press));  // pressed in: held
    EXPECT_EQ(e->begin_line_search(near, slide), 1.0);
  }
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
