// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: the evaluation of requests with "scalar": "long_double" (`evaluate_scalar.hpp`).
#include "evaluate_scalar_impl.hpp"

namespace pce_probe {

template Response evaluate_in<long double>(const Request&);

}  // namespace pce_probe
