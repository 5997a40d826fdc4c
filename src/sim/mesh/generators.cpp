// SPDX-License-Identifier: MIT
#include <pce/sim/generators.hpp>
#include <pce/sim/input_error.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

namespace pce::sim {

namespace {
void require(bool ok, const char* generator, const std::string& what) {
  if (!ok) throw InputError(generator, "", what);
}
std::string limit(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

Mesh grid(double width, double height, int nx, int ny) {
  require(std::isfinite(width) && width > 0 && width <= kMaxCoordinate && std::isfinite(height) && height > 0 &&
              height <= kMaxCoordinate,
          "grid", "width and height must be > 0 and <= " + limit(kMaxCoordinate) + " (m)");
  require(nx >= 1 && ny >= 1 && nx <= 4096 && ny <= 4096, "grid",
          "the resolution must be between 1 and 4096 quads per side");
  require((static_cast<long>(nx) + 1) * (static_cast<long>(ny) + 1) <= kMaxVertices, "grid",
          "(nx + 1)(ny + 1) vertices must be at most " + std::to_string(kMaxVertices));
  Mesh m;
  m.positions.resize(3, (nx + 1) * (ny + 1));
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.positions.col(j * (nx + 1) + i) << (double(i) / nx - 0.5) * width, (double(j) / ny - 0.5) * height, 0.0;
  m.triangles.resize(3, 2 * nx * ny);
  int t = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1,
                d = c + 1;  // a b / c d, counter-clockwise seen from +z
      if ((i + j) % 2 == 0) {
        m.triangles.col(t++) << a, b, d;
        m.triangles.col(t++) << a, d, c;
      } else {
        m.triangles.col(t++) << a, b, c;
        m.triangles.col(t++) << b, d, c;
      }
    }
  m.segments.resize(2, 0);
  return m;
}

Mesh strands(int count, int segments, double length, double spacing, double curl) {
  require(count >= 1 && count <= 1 << 20, "strands", "the strand count must be between 1 and 2^20");
  require(segments >= 1 && segments <= 1 << 16, "strands", "the segment count must be between 1 and 2^16");
  // count (segments + 1) in 64 bits: 2^20 strands of 2^16 segments would overflow int.
  require(static_cast<long>(count) * (static_cast<long>(segments) + 1) <= kMaxVertices, "strands",
          "count (segments + 1) vertices must be at most " + std::to_string(kMaxVertices));
  require(std::isfinite(length) && length > 0 && length <= kMaxCoordinate && std::isfinite(spacing) && spacing > 0 &&
              spacing <= kMaxCoordinate,
          "strands", "length and spacing must be > 0 and <= " + limit(kMaxCoordinate) + " (m)");
  require(std::isfinite(curl) && curl >= 0 && curl <= kMaxCoordinate, "strands",
          "curl must be >= 0 and <= " + limit(kMaxCoordinate) + " (m)");
  const int side = static_cast<int>(std::ceil(std::sqrt(double(count))));
  const double pi = std::acos(-1.0);
  Mesh m;
  m.positions.resize(3, count * (segments + 1));
  m.segments.resize(2, count * segments);
  for (int k = 0; k < count; ++k) {
    const double x0 = (k % side - 0.5 * (side - 1)) * spacing, y0 = (k / side - 0.5 * (side - 1)) * spacing;
    const double phase = 2.399963229728653 * k;  // the golden angle: no two neighbours in phase
    for (int s = 0; s <= segments; ++s) {
      const double z = -length * s / segments, angle = phase + 4 * pi * s / segments;
      m.positions.col(k * (segments + 1) + s) << x0 + curl * std::cos(angle), y0 + curl * std::sin(angle), z;
      if (s < segments) m.segments.col(k * segments + s) << k * (segments + 1) + s, k * (segments + 1) + s + 1;
    }
  }
  m.triangles.resize(3, 0);
  return m;
}

Mesh crumpled_grid(int n, unsigned seed, double fold, double jitter) {
  require(std::isfinite(fold) && fold >= 0 && std::isfinite(jitter) && jitter >= 0, "crumpled_grid",
          "fold and jitter must be finite and non-negative");
  Mesh m = grid(1.0, 1.0, n, n);
  const double h = 1.0 / n, pi = std::acos(-1.0);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    const double x = m.positions(0, v), y = m.positions(1, v);
    const double dx = jitter * h * u(rng), dy = jitter * h * u(rng);  // drawn in this order
    const double dz = 2 * jitter * h * u(rng) + fold * std::sin(6 * pi * x) * std::cos(4 * pi * y);
    m.positions.col(v) += Eigen::Vector3d(dx, dy, dz);
  }
  return m;
}

namespace {
/// The tetrahedra of a box of `n` = (nx, ny, nz) unit cubes on the lattice of vertex (i, j,
/// k) = index i + (nx + 1)(j + (ny + 1) k), six per cube by Kuhn's subdivision: the paths
/// from one corner s of the cube to the opposite one along the three axes in each of their
/// six orders, every tetrahedron positively oriented on the lattice. `away_from_centre`
/// false: s is the cube's lowest corner (one diagonal direction for the whole box);
/// true: s is the corner nearest the box's centre along each axis (the subdivision mirrored
/// across the box's mid-planes; n must then be even, so that no cube straddles them).
Eigen::Matrix4Xi kuhn_tetrahedra(const Eigen::Vector3i& n, bool away_from_centre) {
  static constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const auto index = [&](const Eigen::Vector3i& p) { return p[0] + (n[0] + 1) * (p[1] + (n[1] + 1) * p[2]); };
  Eigen::Matrix4Xi tets(4, 6 * static_cast<Eigen::Index>(n[0]) * n[1] * n[2]);
  Eigen::Index t = 0;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const Eigen::Vector3i cube(i, j, k);
        Eigen::Vector3i start = cube, step = Eigen::Vector3i::Ones();
        if (away_from_centre)
          for (int a = 0; a < 3; ++a)
            if (2 * cube[a] < n[a]) start[a] = cube[a] + 1, step[a] = -1;
        // Mirroring an odd number of axes reverses the orientation of the path's tetrahedra;
        // so does an odd order of the axes.
        const int mirrored = (step[0] < 0) + (step[1] < 0) + (step[2] < 0);
        for (int o = 0; o < 6; ++o) {
          Eigen::Vector3i p = start;
          int v[4];
          v[0] = index(p);
          for (int m = 0; m < 3; ++m) {
            p[kOrders[o][m]] += step[kOrders[o][m]];
            v[m + 1] = index(p);
          }
          const bool odd_order = o == 1 || o == 2 || o == 5;
          if (odd_order != (mirrored % 2 == 1)) std::swap(v[2], v[3]);
          tets.col(t++) << v[0], v[1], v[2], v[3];
        }
      }
  return tets;
}

/// The lattice vertices of `kuhn_tetrahedra(n, …)`, vertex (i, j, k) at (i, j, k) / n − ½
/// scaled by `size` per axis.
Eigen::Matrix3Xd box_positions(const Eigen::Vector3d& size, const Eigen::Vector3i& n) {
  Eigen::Matrix3Xd x(3, static_cast<Eigen::Index>(n[0] + 1) * (n[1] + 1) * (n[2] + 1));
  Eigen::Index v = 0;
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i)
        x.col(v++) << (double(i) / n[0] - 0.5) * size[0], (double(j) / n[1] - 0.5) * size[1],
            (double(k) / n[2] - 0.5) * size[2];
  return x;
}
}  // namespace

Mesh tet_box(const Eigen::Vector3d& size, const Eigen::Vector3i& n) {
  require(size.allFinite() && size.minCoeff() > 0 && size.maxCoeff() <= kMaxCoordinate, "tet_box",
          "the sizes must be > 0 and <= " + limit(kMaxCoordinate) + " (m)");
  require(n.minCoeff() >= 1 && n.maxCoeff() <= 256, "tet_box",
          "the resolution must be between 1 and 256 cubes per side");
  require((static_cast<long>(n[0]) + 1) * (static_cast<long>(n[1]) + 1) * (static_cast<long>(n[2]) + 1) <= kMaxVertices,
          "tet_box", "(nx + 1)(ny + 1)(nz + 1) vertices must be at most " + std::to_string(kMaxVertices));
  Mesh m;
  m.positions = box_positions(size, n);
  m.tetrahedra = kuhn_tetrahedra(n, false);
  m.triangles = boundary_faces(m.tetrahedra);
  m.segments.resize(2, 0);
  return m;
}

Mesh tet_ball(double radius, int n) {
  require(std::isfinite(radius) && radius > 0 && radius <= kMaxCoordinate, "tet_ball",
          "the radius must be > 0 and <= " + limit(kMaxCoordinate) + " (m)");
  require(n >= 1 && n <= 127, "tet_ball",
          "the resolution must be between 1 and 127 (2n cubes per side, (2n + 1)^3 vertices at most 2^24)");
  const Eigen::Vector3i cubes = Eigen::Vector3i::Constant(2 * n);
  Mesh m;
  m.positions = box_positions(Eigen::Vector3d::Constant(2.0), cubes);
  for (Eigen::Index v = 0; v < m.positions.cols(); ++v) {
    const double norm = m.positions.col(v).norm();
    if (norm > 0) m.positions.col(v) *= radius * m.positions.col(v).cwiseAbs().maxCoeff() / norm;
  }
  m.tetrahedra = kuhn_tetrahedra(cubes, true);
  m.triangles = boundary_faces(m.tetrahedra);
  m.segments.resize(2, 0);
  return m;
}

}  // namespace pce::sim
