// SPDX-License-Identifier: MIT
// The 50-digit reference of accuracy_measure.hpp for point_edge and point_point pairs (the
// unsigned length only: a point kind's distance has no side).
#include "accuracy_measure.hpp"

namespace pce_test {

Reference reference_point(const Sample& s, const pce::Vec12<long double>& x) {
  Reference r;
  const pce::Vec12<HighPrecision> y = cast12<HighPrecision>(x);
  with_builtin_penalty(s.penalty, [&](const auto& pen) {
    if (s.pair == AnyPair::point_edge) {
      pce::PointEdgeEnergy<HighPrecision> e;
      r.status = pce::pair_energy<pce::PointEdge>(pce::Vec9<HighPrecision>(y.head<9>()), pce::UnsignedLength{}, pen, e);
      if (r.status == pce::Status::ok) fill_reference(e, r);
    } else {
      pce::PointPointEnergy<HighPrecision> e;
      r.status =
          pce::pair_energy<pce::PointPoint>(pce::Vec6<HighPrecision>(y.head<6>()), pce::UnsignedLength{}, pen, e);
      if (r.status == pce::Status::ok) fill_reference(e, r);
    }
    r.l = r.length;
    return 0;
  });
  return r;
}

}  // namespace pce_test
