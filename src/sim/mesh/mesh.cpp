// SPDX-License-Identifier: MIT
#include <pce/sim/input_error.hpp>
#include <pce/sim/mesh.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace pce::sim {

void apply(const Transform& t, Mesh& mesh) {
  mesh.positions = (t.rotation * (t.scale * mesh.positions)).colwise() + t.translation;
}

Eigen::Matrix2Xi unique_edges(const Eigen::Matrix3Xi& triangles) {
  std::vector<std::array<int, 2>> e;
  e.reserve(3 * static_cast<std::size_t>(triangles.cols()));
  for (Eigen::Index t = 0; t < triangles.cols(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = triangles(k, t), b = triangles((k + 1) % 3, t);
      e.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  Eigen::Matrix2Xi out(2, static_cast<Eigen::Index>(e.size()));
  for (std::size_t i = 0; i < e.size(); ++i) out.col(static_cast<Eigen::Index>(i)) << e[i][0], e[i][1];
  return out;
}

namespace {
/// The faces of tetrahedron (a, b, c, d), each counter-clockwise seen from outside when
/// the tetrahedron is positively oriented.
constexpr int kTetFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

/// Every face of `tets` as (sorted vertices, tet·4 + face), sorted by vertices.
std::vector<std::pair<std::array<int, 3>, long>> sorted_faces(const Eigen::Matrix4Xi& tets) {
  std::vector<std::pair<std::array<int, 3>, long>> f;
  f.reserve(4 * static_cast<std::size_t>(tets.cols()));
  for (Eigen::Index t = 0; t < tets.cols(); ++t)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> v{tets(kTetFaces[k][0], t), tets(kTetFaces[k][1], t), tets(kTetFaces[k][2], t)};
      std::sort(v.begin(), v.end());
      f.emplace_back(v, 4 * static_cast<long>(t) + k);
    }
  std::sort(f.begin(), f.end());
  return f;
}
}  // namespace

Eigen::Matrix3Xi boundary_faces(const Eigen::Matrix4Xi& tetrahedra) {
  const auto f = sorted_faces(tetrahedra);
  std::vector<long> once;
  for (std::size_t i = 0; i < f.size();) {
    std::size_t j = i + 1;
    while (j < f.size() && f[j].first == f[i].first) ++j;
    if (j == i + 1) once.push_back(f[i].second);
    i = j;
  }
  std::sort(once.begin(), once.end());
  Eigen::Matrix3Xi out(3, static_cast<Eigen::Index>(once.size()));
  for (std::size_t i = 0; i < once.size(); ++i) {
    const Eigen::Index t = once[i] / 4;
    const int k = static_cast<int>(once[i] % 4);
    for (int j = 0; j < 3; ++j) out(j, static_cast<Eigen::Index>(i)) = tetrahedra(kTetFaces[k][j], t);
  }
  return out;
}

namespace {
template <int N> void check_elements(const Eigen::Matrix<int, N, Eigen::Dynamic>& el, Eigen::Index n, const char* kind,
                                     const std::string& source) {
  for (Eigen::Index c = 0; c < el.cols(); ++c)
    for (int k = 0; k < N; ++k) {
      const int i = el(k, c);
      if (i < 0 || i >= n)
        throw InputError(source, "",
                         std::string(kind) + " " + std::to_string(c) + " refers to vertex " + std::to_string(i) +
                             ", but the mesh has " + std::to_string(n) + " vertices");
      for (int m = 0; m < k; ++m)
        if (el(m, c) == i)
          throw InputError(
              source, "", std::string(kind) + " " + std::to_string(c) + " uses vertex " + std::to_string(i) + " twice");
    }
}
}  // namespace

void validate(const Mesh& mesh, const std::string& source) {
  const Eigen::Index n = mesh.vertex_count();
  if (n == 0) throw InputError(source, "", "the mesh has no vertices");
  if (n > kMaxVertices)
    throw InputError(source, "",
                     "the mesh has " + std::to_string(n) + " vertices, more than " + std::to_string(kMaxVertices));
  for (Eigen::Index v = 0; v < n; ++v) {
    if (!mesh.positions.col(v).allFinite())
      throw InputError(source, "", "vertex " + std::to_string(v) + " has a non-finite coordinate");
    if (!(mesh.positions.col(v).cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
      std::ostringstream limit, s;
      limit << kMaxCoordinate;
      s.precision(17);
      s << "vertex " << v << " at (" << mesh.positions(0, v) << ", " << mesh.positions(1, v) << ", "
        << mesh.positions(2, v) << ") is beyond |coordinate| <= " << limit.str()
        << " (the largest coordinate pce::sim accepts, in m)";
      throw InputError(source, "", s.str());
    }
  }
  check_elements<3>(mesh.triangles, n, "triangle", source);
  check_elements<2>(mesh.segments, n, "segment", source);
  if (mesh.tetrahedra.cols() == 0) return;
  check_elements<4>(mesh.tetrahedra, n, "tetrahedron", source);
  if (mesh.segments.cols() != 0) throw InputError(source, "", "a mesh with tetrahedra cannot have segments");
  for (Eigen::Index t = 0; t < mesh.tetrahedra.cols(); ++t) {
    const auto x = [&](int k) { return mesh.positions.col(mesh.tetrahedra(k, t)); };
    const Eigen::Vector3d e1 = x(1) - x(0), e2 = x(2) - x(0), e3 = x(3) - x(0);
    const double volume = e1.dot(e2.cross(e3)) / 6.0;
    const double longest =
        std::max({e1.norm(), e2.norm(), e3.norm(), (x(2) - x(1)).norm(), (x(3) - x(1)).norm(), (x(3) - x(2)).norm()});
    if (!(volume > 1e-12 * longest * longest * longest)) {
      std::ostringstream s;
      s.precision(17);
      s << "tetrahedron " << t << " (vertices " << mesh.tetrahedra(0, t) << ", " << mesh.tetrahedra(1, t) << ", "
        << mesh.tetrahedra(2, t) << ", " << mesh.tetrahedra(3, t) << ") has signed volume " << volume
        << (volume < 0 ? ": it is inverted (expected (b - a)·((c - a) × (d - a)) > 0)"
                       : ": it is flat (expected a volume above 1e-12 of its longest edge cubed)");
      throw InputError(source, "", s.str());
    }
  }
  const auto f = sorted_faces(mesh.tetrahedra);
  for (std::size_t i = 0; i + 2 < f.size(); ++i)
    if (f[i].first == f[i + 2].first)
      throw InputError(source, "",
                       "tetrahedra " + std::to_string(f[i].second / 4) + ", " + std::to_string(f[i + 1].second / 4) +
                           " and " + std::to_string(f[i + 2].second / 4) + " share a face (vertices " +
                           std::to_string(f[i].first[0]) + ", " + std::to_string(f[i].first[1]) + ", " +
                           std::to_string(f[i].first[2]) + "); at most two tetrahedra may");
  const Eigen::Matrix3Xi boundary = boundary_faces(mesh.tetrahedra);
  if (mesh.triangles.cols() != boundary.cols() || mesh.triangles != boundary)
    throw InputError(source, "", "the triangles of a mesh with tetrahedra must be its boundary faces");
}

}  // namespace pce::sim
