// SPDX-License-Identifier: MIT
#include <pce/sim/candidates.hpp>

#include "box_rule.hpp"

namespace pce::sim {

/// Every pair, tested by the one definition of the rule (`box_rule::accept_vertex_face`,
/// `box_rule::accept_edge_edge`) that the tree broad phases apply to the pairs they report.
Candidates brute_force_candidates(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xi& triangles,
                                  const Eigen::Matrix2Xi& edges, double distance) {
  Candidates c;
  const int nv = static_cast<int>(x.cols()), nt = static_cast<int>(triangles.cols()),
            ne = static_cast<int>(edges.cols());
  for (int v = 0; v < nv; ++v)
    for (int t = 0; t < nt; ++t)
      if (box_rule::accept_vertex_face(x, triangles, v, t, distance)) c.vertex_face.push_back({v, t});
  for (int a = 0; a < ne; ++a)
    for (int b = a + 1; b < ne; ++b)
      if (box_rule::accept_edge_edge(x, edges, a, b, distance)) c.edge_edge.push_back({a, b});
  return c;  // generated in sorted order
}

}  // namespace pce::sim
