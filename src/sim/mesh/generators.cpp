// SPDX-License-Identifier: MIT
#include <pce/sim/generators.hpp>
#include <pce/sim/input_error.hpp>

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

}  // namespace pce::sim
