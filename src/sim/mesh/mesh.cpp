// SPDX-License-Identifier: MIT
#include <pce/sim/input_error.hpp>
#include <pce/sim/mesh.hpp>

#include <algorithm>
#include <array>
#include <sstream>
#include <string>
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
}

}  // namespace pce::sim
