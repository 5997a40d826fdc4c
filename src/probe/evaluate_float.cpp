// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: the evaluation of requests with "scalar": "float" (`evaluate_scalar.hpp`).
#include "evaluate_scalar_impl.hpp"

namespace pce_probe {

template Response evaluate_in<float>(const Request&);

}  // namespace pce_probe
