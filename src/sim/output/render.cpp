// SPDX-License-Identifier: MIT
// The frame picture (pce/sim/render.hpp): fit a perspective camera, rasterize triangles and
// segment tubes into a supersampled colour + inverse-depth buffer, average down, write PNG.
#include <pce/sim/render.hpp>

#include <stb/stb_image_write.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace pce::sim {
namespace {

constexpr double pi = 3.14159265358979323846;
constexpr double field_of_view = 30.0 * pi / 180.0;

/// The projection of a view: (screen x, screen y, 1 / z); 1/z ≤ 0 for a point not in front
/// of the camera.
Eigen::Vector3d project(const RenderView& cam, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - cam.eye;
  const double z = cam.forward.dot(d);
  if (!(z > 0)) return Eigen::Vector3d(0, 0, -1);
  return Eigen::Vector3d(cam.cx + cam.focal * cam.right.dot(d) / z, cam.cy - cam.focal * cam.up.dot(d) / z, 1.0 / z);
}

bool usable(const RenderMesh& m, int vertex) {
  return vertex >= 0 && vertex < m.positions.cols() && m.positions.col(vertex).allFinite();
}

/// The supersampled image: colour and inverse depth (0 = nothing drawn, larger = nearer).
struct Canvas {
  int w, h;
  std::vector<Eigen::Vector3f> color;
  std::vector<float> inverse_depth;

  Canvas(int w_, int h_, const Eigen::Vector3f& background)
      : w(w_), h(h_), color(static_cast<std::size_t>(w_) * h_, background), inverse_depth(color.size(), 0.0f) {}
  std::size_t at(int x, int y) const { return static_cast<std::size_t>(y) * w + x; }
};

double edge(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

struct Lights {
  Eigen::Vector3d key;  ///< unit direction towards the key light
};

/// Area-weighted vertex normals of the usable triangles (zero where no triangle touches).
Eigen::Matrix3Xd vertex_normals(const RenderMesh& m, const std::vector<bool>& triangle_ok) {
  Eigen::Matrix3Xd n = Eigen::Matrix3Xd::Zero(3, m.positions.cols());
  for (Eigen::Index t = 0; t < m.triangles.cols(); ++t) {
    if (!triangle_ok[static_cast<std::size_t>(t)]) continue;
    const auto i = m.triangles.col(t);
    const Eigen::Vector3d c =
        (m.positions.col(i[1]) - m.positions.col(i[0])).cross(m.positions.col(i[2]) - m.positions.col(i[0]));
    for (int k = 0; k < 3; ++k) n.col(i[k]) += c;
  }
  return n;
}

void draw_triangles(const RenderMesh& m, const RenderView& cam, const Lights& lights, Canvas& canvas) {
  const Eigen::Index nt = m.triangles.cols();
  std::vector<bool> ok(static_cast<std::size_t>(nt), false);
  for (Eigen::Index t = 0; t < nt; ++t) {
    const auto i = m.triangles.col(t);
    ok[static_cast<std::size_t>(t)] = usable(m, i[0]) && usable(m, i[1]) && usable(m, i[2]);
  }
  const Eigen::Matrix3Xd normals = vertex_normals(m, ok);
  const Eigen::Vector3d base = m.color.cast<double>().cwiseMax(0.0).cwiseMin(1.0);

  for (Eigen::Index t = 0; t < nt; ++t) {
    if (!ok[static_cast<std::size_t>(t)]) continue;
    const auto i = m.triangles.col(t);
    Eigen::Vector3d p[3], s[3], n[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = m.positions.col(i[k]);
      s[k] = project(cam, p[k]);
      n[k] = normals.col(i[k]);
    }
    if (!(s[0].z() > 0 && s[1].z() > 0 && s[2].z() > 0)) continue;
    Eigen::Vector3d face = (p[1] - p[0]).cross(p[2] - p[0]);
    if (!(face.norm() > 0) || !face.allFinite()) continue;
    face.normalize();
    const Eigen::Vector2d a = s[0].head<2>(), b = s[1].head<2>(), c = s[2].head<2>();
    const double area = edge(a, b, c);
    if (!(std::abs(area) > 1e-12) || !std::isfinite(area)) continue;

    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 = std::min(canvas.w - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 = std::min(canvas.h - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    // Barycentric coordinates are affine on the screen: stepped along each row.
    const double inverse_area = 1.0 / area;
    const double d0 = (b.y() - c.y()) * inverse_area, d1 = (c.y() - a.y()) * inverse_area,
                 d2 = (a.y() - b.y()) * inverse_area;
    for (int y = y0; y <= y1; ++y) {
      const Eigen::Vector2d q0(x0 + 0.5, y + 0.5);
      double l0 = edge(b, c, q0) * inverse_area - d0, l1 = edge(c, a, q0) * inverse_area - d1,
             l2 = edge(a, b, q0) * inverse_area - d2;
      for (int x = x0; x <= x1; ++x) {
        l0 += d0, l1 += d1, l2 += d2;
        if (l0 < 0 || l1 < 0 || l2 < 0) continue;
        const double w = l0 * s[0].z() + l1 * s[1].z() + l2 * s[2].z();
        const std::size_t at = canvas.at(x, y);
        if (!(w > canvas.inverse_depth[at])) continue;
        // Perspective-correct weights of the vertices.
        const double b0 = l0 * s[0].z() / w, b1 = l1 * s[1].z() / w, b2 = l2 * s[2].z() / w;
        const Eigen::Vector3d point = b0 * p[0] + b1 * p[1] + b2 * p[2];
        Eigen::Vector3d normal = b0 * n[0] + b1 * n[1] + b2 * n[2];
        if (!(normal.dot(face) > 0)) normal = face;
        normal.normalize();
        const Eigen::Vector3d to_eye = (cam.eye - point).normalized();
        if (face.dot(to_eye) < 0) normal = -normal;  // two-sided
        const double light =
            0.22 + 0.5 * std::max(0.0, normal.dot(to_eye)) + 0.4 * std::max(0.0, normal.dot(lights.key));
        canvas.inverse_depth[at] = static_cast<float>(w);
        canvas.color[at] = (light * base).cwiseMin(1.0).cast<float>();
      }
    }
  }
}

void draw_segments(const RenderMesh& m, const RenderView& cam, const Lights& lights, double width, Canvas& canvas) {
  const Eigen::Vector3d base = m.color.cast<double>().cwiseMax(0.0).cwiseMin(1.0);
  const double half = 0.5 * std::max(width, 1.0);
  for (Eigen::Index e = 0; e < m.segments.cols(); ++e) {
    const auto i = m.segments.col(e);
    if (!usable(m, i[0]) || !usable(m, i[1])) continue;
    const Eigen::Vector3d pa = m.positions.col(i[0]), pb = m.positions.col(i[1]);
    const Eigen::Vector3d sa = project(cam, pa), sb = project(cam, pb);
    if (!(sa.z() > 0 && sb.z() > 0)) continue;
    const Eigen::Vector2d a = sa.head<2>(), ab = sb.head<2>() - a;
    const double length2 = ab.squaredNorm();
    // A tube lit by the key light: Lambert for a line is the sine of the light's angle to it.
    const Eigen::Vector3d tangent = (pb - pa).norm() > 0 ? (pb - pa).normalized() : Eigen::Vector3d::Zero();
    const double cos_key = tangent.dot(lights.key);
    const double diffuse = std::sqrt(std::max(0.0, 1 - cos_key * cos_key));

    const int x0 = std::max(0, static_cast<int>(std::floor(std::min(sa.x(), sb.x()) - half)));
    const int x1 = std::min(canvas.w - 1, static_cast<int>(std::ceil(std::max(sa.x(), sb.x()) + half)));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min(sa.y(), sb.y()) - half)));
    const int y1 = std::min(canvas.h - 1, static_cast<int>(std::ceil(std::max(sa.y(), sb.y()) + half)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d q(x + 0.5, y + 0.5);
        const double t = length2 > 0 ? std::clamp((q - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
        const double r = (q - a - t * ab).norm() / half;
        if (r > 1) continue;
        const double w = (1 - t) * sa.z() + t * sb.z();  // 1/z is linear on the screen
        const std::size_t at = canvas.at(x, y);
        if (!(w * 1.002 > canvas.inverse_depth[at])) continue;
        const double round = std::sqrt(1 - r * r);  // the tube's normal turning away at its rim
        const double light = 0.3 + 0.4 * round + 0.35 * diffuse * round;
        canvas.inverse_depth[at] = static_cast<float>(w * 1.002);
        canvas.color[at] = (light * base).cwiseMin(1.0).cast<float>();
      }
  }
}

}  // namespace

ViewFit::ViewFit(const RenderOptions& opts) : opts_(opts) {}

void ViewFit::include(const Eigen::Matrix3Xd& points) {
  if (placed_) throw std::logic_error("pce::sim::ViewFit::include: called after cover (the first pass is over)");
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (points.col(i).allFinite()) box_.extend(points.col(i));
}

void ViewFit::cover(const Eigen::Matrix3Xd& points) {
  if (!placed_) {
    // The camera's place: looking along the view direction at the box's centre, from far
    // enough for the box's bounding sphere to be in the field of view. Focal length 1 and no
    // shift until the projections are known (view()).
    placed_ = true;
    view_.width = opts_.width * std::clamp(opts_.supersampling, 1, 4);
    view_.height = opts_.height * std::clamp(opts_.supersampling, 1, 4);
    view_.supersampling = std::clamp(opts_.supersampling, 1, 4);
    view_.valid = !box_.isEmpty();
    if (!view_.valid) return;
    Eigen::Vector3d forward = opts_.view_direction;
    if (!forward.allFinite() || forward.norm() == 0) forward = RenderOptions().view_direction;
    forward.normalize();
    Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    if (std::abs(forward.dot(up)) > 0.999) up = Eigen::Vector3d::UnitY();
    view_.forward = forward;
    view_.right = forward.cross(up).normalized();
    view_.up = view_.right.cross(forward);
    const double radius = std::max(0.5 * box_.diagonal().norm(), 1e-9 * (1 + box_.center().norm()));
    view_.eye = box_.center() - forward * (1.05 * radius / std::sin(0.5 * field_of_view));
    view_.focal = 1, view_.cx = 0, view_.cy = 0;
  }
  if (!view_.valid) return;
  for (Eigen::Index i = 0; i < points.cols(); ++i)
    if (points.col(i).allFinite()) screen_.extend(project(view_, points.col(i)).head<2>());
}

RenderView ViewFit::view() const {
  if (!placed_) {  // no second pass: nothing was covered
    ViewFit copy = *this;
    copy.cover(Eigen::Matrix3Xd(3, 0));
    return copy.view();
  }
  RenderView cam = view_;
  if (!cam.valid || screen_.isEmpty()) {
    cam.valid = false;
    return cam;
  }
  // Zoom and shift so that the projected points fit.
  const double w = cam.width, h = cam.height;
  const double margin = std::clamp(opts_.margin, 0.0, 0.45);
  const Eigen::Vector2d extent = screen_.sizes().cwiseMax(1e-12);
  const double focal_x = (1 - 2 * margin) * w / extent.x(), focal_y = (1 - 2 * margin) * h / extent.y();
  cam.focal = std::min(focal_x, focal_y);
  if (screen_.sizes().x() < 1e-12 && screen_.sizes().y() < 1e-12) cam.focal = 1;  // a single point
  cam.cx = 0.5 * w - cam.focal * screen_.center().x();
  cam.cy = 0.5 * h - cam.focal * screen_.center().y();  // project() already flips y
  return cam;
}

namespace {

void check_size(const RenderOptions& opts) {
  if (opts.width <= 0 || opts.height <= 0 || opts.width > 16384 || opts.height > 16384)
    throw std::invalid_argument("render_png: image size " + std::to_string(opts.width) + " x " +
                                std::to_string(opts.height) + " is not in 1..16384");
}

}  // namespace

std::vector<std::uint8_t> render_rgb(const std::vector<RenderMesh>& meshes, const RenderOptions& opts,
                                     const RenderView& view) {
  check_size(opts);
  const int ss = std::clamp(opts.supersampling, 1, 4);
  if (view.width != opts.width * ss || view.height != opts.height * ss || view.supersampling != ss)
    throw std::invalid_argument("render_rgb: the view was fitted for another image size or supersampling");
  const Eigen::Vector3f background = opts.background.cwiseMax(0.0f).cwiseMin(1.0f);
  Canvas canvas(opts.width * ss, opts.height * ss, background);

  if (view.valid) {
    const Lights lights{(-0.5 * view.right + 0.8 * view.up - 0.4 * view.forward).normalized()};
    for (const RenderMesh& m : meshes) draw_triangles(m, view, lights, canvas);
    for (const RenderMesh& m : meshes) draw_segments(m, view, lights, opts.line_width * ss, canvas);
  }

  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(opts.width) * opts.height * 3);
  for (int y = 0; y < opts.height; ++y)
    for (int x = 0; x < opts.width; ++x) {
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      for (int dy = 0; dy < ss; ++dy)
        for (int dx = 0; dx < ss; ++dx) sum += canvas.color[canvas.at(x * ss + dx, y * ss + dy)];
      const Eigen::Vector3f c = sum / static_cast<float>(ss * ss);
      for (int k = 0; k < 3; ++k)
        pixels[(static_cast<std::size_t>(y) * opts.width + x) * 3 + k] =
            static_cast<std::uint8_t>(std::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
    }
  return pixels;
}

void render_png(const std::string& path, const std::vector<RenderMesh>& meshes, const RenderOptions& opts) {
  check_size(opts);
  ViewFit fit(opts);
  for (const RenderMesh& m : meshes) fit.include(m.positions);
  for (const RenderMesh& m : meshes) fit.cover(m.positions);
  const std::vector<std::uint8_t> pixels = render_rgb(meshes, opts, fit.view());
  if (stbi_write_png(path.c_str(), opts.width, opts.height, 3, pixels.data(), opts.width * 3) == 0)
    throw std::runtime_error(path + ": cannot write PNG");
}

}  // namespace pce::sim
