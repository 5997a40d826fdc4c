// SPDX-License-Identifier: MIT
#include <pce/sim/candidates.hpp>

#include "box_rule.hpp"

#include <stdexcept>

namespace pce::sim {

/// Every pair, tested by the one definition of the rule (`box_rule::accept_vertex_face`,
/// `box_rule::accept_edge_edge`) that the tree broad phases apply to the pairs they report.
Candidates brute_force_candidates(const Eigen::Matrix3Xd& x0, const Eigen::Matrix3Xd& x1,
                                  const Eigen::Matrix3Xi& triangles, const Eigen::Matrix2Xi& edges, double distance) {
  if (x1.cols() != x0.cols())
    throw std::invalid_argument("brute_force_candidates: a sweep's two states have " + std::to_string(x0.cols()) +
                                " and " + std::to_string(x1.cols()) + " vertices");
  Candidates c;
  const int nv = static_cast<int>(x0.cols()), nt = static_cast<int>(triangles.cols()),
            ne = static_cast<int>(edges.cols());
  for (int v = 0; v < nv; ++v)
    for (int t = 0; t < nt; ++t)
      if (box_rule::accept_vertex_face(x0, x1, triangles, v, t, distance)) c.vertex_face.push_back({v, t});
  for (int a = 0; a < ne; ++a)
    for (int b = a + 1; b < ne; ++b)
      if (box_rule::accept_edge_edge(x0, x1, edges, a, b, distance)) c.edge_edge.push_back({a, b});
  return c;  // generated in sorted order
}

Candidates brute_force_candidates(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles,
                                  const Eigen::Matrix2Xi& edges, double distance) {
  return brute_force_candidates(x, x, triangles, edges, distance);
}

}  // namespace pce::sim
