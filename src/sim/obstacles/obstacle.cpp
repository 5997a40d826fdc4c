// SPDX-License-Identifier: MIT
/// @file
/// Kinematic obstacles: the prescribed pose, the closed-form signed distances and the
/// drawing meshes (`pce/sim/obstacle.hpp`). The closed forms are tested against FCL's GJK
/// distance (`pce/sim/fcl_distance.hpp`, tests/sim/test_obstacles.cpp).
#include <pce/sim/obstacle.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

namespace pce::sim {

namespace {

/// Where time t falls among a keyframed motion's keyframes: keyframe k and the weight w of
/// keyframe k + 1 (w = u or s(u) = 3u² − 2u³ with u = (t − t_k)/(t_{k+1} − t_k) ∈ [0, 1));
/// w = 0 at and before the first keyframe and at and after the last, which then hold.
struct Segment {
  std::size_t k = 0;
  double w = 0;
};

Segment segment_at(const Motion& m, double t) {
  const std::vector<Keyframe>& f = m.keyframes;
  // The first keyframe later than t (a NaN time is later than none: the last one holds).
  const auto next =
      std::upper_bound(f.begin(), f.end(), t, [](double time, const Keyframe& key) { return time < key.time; });
  if (next == f.begin()) return {0, 0.0};
  const auto k = static_cast<std::size_t>(next - f.begin()) - 1;
  if (next == f.end()) return {k, 0.0};
  const double u = (t - f[k].time) / (f[k + 1].time - f[k].time);
  return {k, m.interpolation == Interpolation::smooth ? u * u * (3 - 2 * u) : u};
}

}  // namespace

double Motion::elapsed(double t) const {
  // τ = clamp(t − start, 0, stop − start): at rest before `start`, frozen after `stop`.
  return std::clamp(t - start, 0.0, std::max(0.0, stop - start));
}

Eigen::Vector3d Motion::shift(double t) const {
  if (keyframes.empty()) return velocity * elapsed(t);
  // d_k + w (d_{k+1} − d_k).
  const Segment s = segment_at(*this, t);
  const Keyframe& a = keyframes[s.k];
  if (s.w == 0) return a.translation;
  return a.translation + s.w * (keyframes[s.k + 1].translation - a.translation);
}

Eigen::Matrix3d Motion::spin(double t) const {
  if (keyframes.empty()) {
    // exp([ω]× τ): a constant angular velocity given in world axes (Rodrigues' formula
    // through Eigen's AngleAxis).
    const double angle = angular_velocity.norm() * elapsed(t);
    if (!(angle > 0)) return Eigen::Matrix3d::Identity();
    return Eigen::AngleAxisd(angle, angular_velocity.normalized()).toRotationMatrix();
  }
  // R_k exp(w log(R_kᵀ R_{k+1})): the relative rotation as an axis and an angle in [0, π]
  // (the shortest way round), the angle scaled by w.
  const Segment s = segment_at(*this, t);
  const Keyframe& a = keyframes[s.k];
  if (s.w == 0) return a.rotation;
  const Eigen::AngleAxisd relative(Eigen::Matrix3d(a.rotation.transpose() * keyframes[s.k + 1].rotation));
  return a.rotation * Eigen::AngleAxisd(s.w * relative.angle(), relative.axis()).toRotationMatrix();
}

void Obstacle::place(const PlacedPose& p) {
  while (!placed.empty() && !(placed.back().from < p.from)) placed.pop_back();
  placed.push_back(p);
}

Eigen::Isometry3d Obstacle::pose(double t) const {
  // The last placed pose at or before t (a NaN t is before none: the motion's).
  const auto after =
      std::upper_bound(placed.begin(), placed.end(), t, [](double time, const PlacedPose& p) { return time < p.from; });
  if (after != placed.begin()) return std::prev(after)->pose;
  // R(t) = spin(t) R0 about the obstacle's centre, c(t) = position + shift(t).
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = position + motion.shift(t);
  pose.linear() = motion.spin(t) * rotation;
  return pose;
}

Eigen::Matrix3d axis_rotation(const Eigen::Vector3d& axis, double degrees) {
  constexpr double kPi = 3.14159265358979323846;
  // Scaled by the largest component first: a tiny axis (1e-200) would underflow its norm.
  const double largest = axis.cwiseAbs().maxCoeff();
  return Eigen::AngleAxisd(degrees * kPi / 180.0, (axis / largest).normalized()).toRotationMatrix();
}

namespace {

/// The point of triangle (a, b, c) closest to p, by the Voronoi-region walk of Ericson,
/// Real-Time Collision Detection (2005), Sec. 5.1.5 (barycentric tests on the vertex, edge
/// and face regions in turn).
Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                    const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Sphere of radius r at the origin: d = |q| − r, n = q/|q| (local +z at the centre).
SurfaceDistance sphere_distance(double r, const Eigen::Vector3d& q) {
  const double len = q.norm();
  if (len > 0) return {len - r, q / len};
  return {-r, Eigen::Vector3d::UnitZ()};
}

/// Box [−h, h]: outside, the distance to the clamped point q̄ = clamp(q, −h, h), n =
/// (q − q̄)/|q − q̄| (faces, edges and corners alike); inside or on the surface,
/// d = maxᵢ(|qᵢ| − hᵢ) ≤ 0 with n = sign(qᵢ) eᵢ of the nearest face i.
SurfaceDistance box_distance(const Eigen::Vector3d& h, const Eigen::Vector3d& q) {
  const Eigen::Vector3d clamped = q.cwiseMax(-h).cwiseMin(h);
  const Eigen::Vector3d diff = q - clamped;
  const double len = diff.norm();
  if (len > 0) return {len, diff / len};
  int face = 0;
  const Eigen::Vector3d gap = q.cwiseAbs() - h;  // ≤ 0 componentwise
  const double d = gap.maxCoeff(&face);
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n[face] = q[face] < 0 ? -1.0 : 1.0;
  return {d, n};
}

/// Capsule: the points within r of the segment z ∈ [−l, l] on the local z axis:
/// d = |q − (0, 0, clamp(q_z, −l, l))| − r, n along that difference (local x on the axis).
SurfaceDistance capsule_distance(double r, double l, const Eigen::Vector3d& q) {
  const Eigen::Vector3d axis_point(0, 0, std::clamp(q.z(), -l, l));
  const Eigen::Vector3d diff = q - axis_point;
  const double len = diff.norm();
  if (len > 0) return {len - r, diff / len};
  return {-r, Eigen::Vector3d::UnitX()};
}

/// Unsigned distance to the nearest triangle (brute force over the triangles). When the
/// closest point is inside a triangle (the face region), the offset is computed as the
/// projection ((q − a)·n̂) n̂ on the unit normal n̂ rather than q minus the barycentric
/// point: it is then exactly along n̂ and exactly zero for points on an axis-aligned face,
/// where the barycentric point would leave a rounding residue pointing anywhere.
SurfaceDistance mesh_distance(const Mesh& mesh, const Eigen::Vector3d& q) {
  SurfaceDistance best{std::numeric_limits<double>::infinity(), Eigen::Vector3d::UnitZ()};
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    const Eigen::Vector3d a = mesh.positions.col(mesh.triangles(0, t)), b = mesh.positions.col(mesh.triangles(1, t)),
                          c = mesh.positions.col(mesh.triangles(2, t));
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double area2 = cross.norm();
    const Eigen::Vector3d unit = area2 > 0 ? Eigen::Vector3d(cross / area2) : Eigen::Vector3d::UnitZ();
    Eigen::Vector3d diff = q - closest_on_triangle(q, a, b, c);
    if (area2 > 0) {
      const double height = (q - a).dot(unit);
      const Eigen::Vector3d in_plane = diff - height * unit;
      // Face region: q − closest is (up to rounding) along the normal.
      if (in_plane.norm() <= 1e-12 * (diff.norm() + (b - a).norm() + (c - a).norm())) diff = height * unit;
    }
    const double len = diff.norm();
    if (!(len < best.distance)) continue;
    best.distance = len;
    best.normal = len > 0 ? Eigen::Vector3d(diff / len) : unit;
  }
  return best;
}

}  // namespace

SurfaceDistance surface_distance(const Obstacle& o, const Eigen::Isometry3d& pose, const Eigen::Vector3d& p) {
  const Eigen::Matrix3d R = pose.linear();
  const Eigen::Vector3d q = R.transpose() * (p - pose.translation());  // local coordinates
  SurfaceDistance s;
  switch (o.kind) {
    case ShapeKind::sphere:
      s = sphere_distance(o.radius, q);
      break;
    case ShapeKind::box:
      s = box_distance(o.half_extents, q);
      break;
    case ShapeKind::capsule:
      s = capsule_distance(o.radius, o.half_length, q);
      break;
    case ShapeKind::mesh:
      s = mesh_distance(o.mesh, q);
      break;
  }
  s.normal = R * s.normal;
  return s;
}

namespace {

/// A latitude-longitude sphere of radius r with `around` segments around the z axis and
/// `rings` bands from pole to pole; the bands between the two equator rows are stretched
/// by `stretch` along z (a capsule's cylinder when stretch > 0; `rings` must be even then).
Mesh round_mesh(double r, double stretch, int around, int rings) {
  const double pi = std::acos(-1.0);
  // Rows of vertices from the north pole (exclusive) to the south pole (exclusive).
  const int row_count = stretch > 0 ? rings : rings - 1;  // a capsule duplicates the equator row
  std::vector<double> zs, rs;
  for (int k = 1; k < rings; ++k) {
    const double theta = pi * k / rings;
    const double z = r * std::cos(theta), rr = r * std::sin(theta);
    if (stretch > 0 && 2 * k == rings) {
      zs.push_back(stretch);
      rs.push_back(rr);
      zs.push_back(-stretch);
      rs.push_back(rr);
      continue;
    }
    zs.push_back(z + (stretch > 0 ? (2 * k < rings ? stretch : -stretch) : 0.0));
    rs.push_back(rr);
  }
  Mesh m;
  const int n = row_count * around + 2;
  m.positions.resize(3, n);
  m.positions.col(0) << 0, 0, r + stretch;
  m.positions.col(n - 1) << 0, 0, -r - stretch;
  for (int k = 0; k < row_count; ++k)
    for (int i = 0; i < around; ++i) {
      const double phi = 2 * pi * i / around;
      m.positions.col(1 + k * around + i) << rs[k] * std::cos(phi), rs[k] * std::sin(phi), zs[k];
    }
  std::vector<Eigen::Vector3i> tris;
  auto at = [&](int k, int i) { return 1 + k * around + (i % around); };
  for (int i = 0; i < around; ++i) tris.emplace_back(0, at(0, i), at(0, i + 1));  // outward, seen from outside
  for (int k = 0; k + 1 < row_count; ++k)
    for (int i = 0; i < around; ++i) {
      tris.emplace_back(at(k, i), at(k + 1, i), at(k + 1, i + 1));
      tris.emplace_back(at(k, i), at(k + 1, i + 1), at(k, i + 1));
    }
  for (int i = 0; i < around; ++i) tris.emplace_back(n - 1, at(row_count - 1, i + 1), at(row_count - 1, i));
  m.triangles.resize(3, static_cast<Eigen::Index>(tris.size()));
  for (std::size_t t = 0; t < tris.size(); ++t) m.triangles.col(static_cast<Eigen::Index>(t)) = tris[t];
  m.segments.resize(2, 0);
  return m;
}

Mesh box_mesh(const Eigen::Vector3d& h) {
  Mesh m;
  m.positions.resize(3, 8);
  for (int c = 0; c < 8; ++c)
    m.positions.col(c) << ((c & 1) ? h.x() : -h.x()), ((c & 2) ? h.y() : -h.y()), ((c & 4) ? h.z() : -h.z());
  // Two counter-clockwise triangles per face, seen from outside.
  m.triangles.resize(3, 12);
  const int faces[12][3] = {{0, 2, 3}, {0, 3, 1},   // −z
                            {4, 5, 7}, {4, 7, 6},   // +z
                            {0, 1, 5}, {0, 5, 4},   // −y
                            {2, 7, 3}, {2, 6, 7},   // +y
                            {0, 4, 6}, {0, 6, 2},   // −x
                            {1, 3, 7}, {1, 7, 5}};  // +x
  for (int t = 0; t < 12; ++t) m.triangles.col(t) << faces[t][0], faces[t][1], faces[t][2];
  m.segments.resize(2, 0);
  return m;
}

}  // namespace

Mesh surface_mesh(const Obstacle& o, const Eigen::Isometry3d& pose, int resolution) {
  const int around = std::max(resolution, 3);
  const int rings = std::max(2, 2 * ((around + 3) / 4));  // even, about around/2
  Mesh m;
  switch (o.kind) {
    case ShapeKind::sphere:
      m = round_mesh(o.radius, 0.0, around, rings);
      break;
    case ShapeKind::capsule:
      m = round_mesh(o.radius, o.half_length, around, rings);
      break;
    case ShapeKind::box:
      m = box_mesh(o.half_extents);
      break;
    case ShapeKind::mesh:
      m = o.mesh;
      break;
  }
  for (Eigen::Index v = 0; v < m.positions.cols(); ++v) m.positions.col(v) = pose * Eigen::Vector3d(m.positions.col(v));
  return m;
}

}  // namespace pce::sim
