// SPDX-License-Identifier: MIT
// The 50-digit reference of accuracy_measure.hpp for edge_edge pairs (one translation unit
// per pair kind: the 50-digit instantiations are the slow part of the build).
#include "accuracy_measure.hpp"

namespace pce_test {

Reference reference_edge_edge(const Sample& s, const pce::Vec12<long double>& x) {
  return plane_reference<pce::EdgeEdge>(s, x);
}

}  // namespace pce_test
