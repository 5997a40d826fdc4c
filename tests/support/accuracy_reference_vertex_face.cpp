// SPDX-License-Identifier: MIT
// The 50-digit reference of accuracy_measure.hpp for vertex_face pairs (one translation unit
// per pair kind: the 50-digit instantiations are the slow part of the build).
#include "accuracy_measure.hpp"

namespace pce_test {

Reference reference_vertex_face(const Sample& s, const pce::Vec12<long double>& x) {
  return plane_reference<pce::VertexFace>(s, x);
}

}  // namespace pce_test
