// SPDX-License-Identifier: MIT
#include <pce/sim/candidates.hpp>

namespace pce::sim {

Candidates brute_force_candidates(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles,
                                  const Eigen::Matrix2Xi& edges, double distance) {
  Candidates c;
  for (Eigen::Index v = 0; v < x.cols(); ++v)
    for (Eigen::Index t = 0; t < triangles.cols(); ++t) {
      const Eigen::Vector3i tri = triangles.col(t);
      if (tri[0] == v || tri[1] == v || tri[2] == v) continue;
      const Eigen::Vector3d lo = x.col(tri[0]).cwiseMin(x.col(tri[1])).cwiseMin(x.col(tri[2])).array() - distance;
      const Eigen::Vector3d hi = x.col(tri[0]).cwiseMax(x.col(tri[1])).cwiseMax(x.col(tri[2])).array() + distance;
      if ((x.col(v).array() >= lo.array()).all() && (x.col(v).array() <= hi.array()).all())
        c.vertex_face.push_back({static_cast<int>(v), static_cast<int>(t)});
    }
  for (Eigen::Index a = 0; a < edges.cols(); ++a)
    for (Eigen::Index b = a + 1; b < edges.cols(); ++b) {
      const int a0 = edges(0, a), a1 = edges(1, a), b0 = edges(0, b), b1 = edges(1, b);
      if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) continue;
      const Eigen::Vector3d alo = x.col(a0).cwiseMin(x.col(a1)), ahi = x.col(a0).cwiseMax(x.col(a1));
      const Eigen::Vector3d blo = x.col(b0).cwiseMin(x.col(b1)), bhi = x.col(b0).cwiseMax(x.col(b1));
      if (((blo - ahi).array() <= distance).all() && ((alo - bhi).array() <= distance).all())
        c.edge_edge.push_back({static_cast<int>(a), static_cast<int>(b)});
    }
  return c;  // generated in sorted order
}

}  // namespace pce::sim
