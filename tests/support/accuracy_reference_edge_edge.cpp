// SPDX-License-Identifier: MIT
// The 50-digit reference of accuracy_measure.hpp for edge_edge pairs (one translation unit
// per pair kind: the 50-digit instantiations are the slow part of the build).
#include "accuracy_measure.hpp"

namespace pce_test {

Reference reference_edge_edge(const Sample& s, const pce::Vec12<long double>& x) {
  Reference r;
  const pce::Vec12<HighPrecision> y = cast12<HighPrecision>(x);
  with_builtin_penalty(s.penalty, [&](const auto& pen) {
    with_length(s.length, [&](const auto& len) {
      pce::PairEnergy<HighPrecision> e;
      r.status = pce::pair_energy<pce::EdgeEdge>(y, len, pen, e);
      if (r.status != pce::Status::ok) return 0;
      fill_reference(e, r);
      r.l = static_cast<long double>(e.frame.l);
      return 0;
    });
    return 0;
  });
  return r;
}

}  // namespace pce_test
