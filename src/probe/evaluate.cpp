// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: dispatch of a request to its scalar type's evaluation (`evaluate_scalar.hpp`).
#include "evaluate.hpp"

#include "evaluate_scalar.hpp"

namespace pce_probe {

Response evaluate_request(const Request& request) {
  switch (request.scalar) {
    case ScalarKind::float_:
      return evaluate_in<float>(request);
    case ScalarKind::long_double:
      return evaluate_in<long double>(request);
    case ScalarKind::double_:
      break;
  }
  return evaluate_in<double>(request);
}

}  // namespace pce_probe
