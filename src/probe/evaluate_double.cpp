// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: the evaluation of requests with "scalar": "double" (`evaluate_scalar.hpp`).
#include "evaluate_scalar_impl.hpp"

namespace pce_probe {

template Response evaluate_in<double>(const Request&);

}  // namespace pce_probe
