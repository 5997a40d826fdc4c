// SPDX-License-Identifier: MIT
#include "batch.hpp"

namespace pce_python {

int dofs(Kind kind) {
  switch (kind) {
    case Kind::edge_edge:
      return pce::EdgeEdge::dofs;
    case Kind::point_edge:
      return pce::PointEdge::dofs;
    case Kind::point_point:
      return pce::PointPoint::dofs;
    case Kind::vertex_face:
      break;
  }
  return pce::VertexFace::dofs;
}

int frame_dofs(Kind kind, bool closest_feature) {
  if (closest_feature) return pce::VertexFace::frame_dofs;  // every feature's eigenvalues fit in 9
  switch (kind) {
    case Kind::edge_edge:
      return pce::EdgeEdge::frame_dofs;
    case Kind::point_edge:
      return pce::PointEdge::frame_dofs;
    case Kind::point_point:
      return pce::PointPoint::frame_dofs;
    case Kind::vertex_face:
      break;
  }
  return pce::VertexFace::frame_dofs;
}

}  // namespace pce_python
