// SPDX-License-Identifier: MIT
#include "batch.hpp"

namespace pce_python {

int dofs(Kind kind) {
  switch (kind) {
    case Kind::point_edge:
      return 9;
    case Kind::point_point:
      return 6;
    default:
      return 12;
  }
}

int frame_dofs(Kind kind, bool closest_feature) {
  if (closest_feature) return 9;
  switch (kind) {
    case Kind::point_edge:
      return 6;
    case Kind::point_point:
      return 3;
    default:
      return 9;
  }
}

}  // namespace pce_python
