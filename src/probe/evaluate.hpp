// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: evaluation of one parsed request with `pce::evaluate` (or the opt-in
/// `pce::mollified_pair_energy` when the request has a "mollifier" field) in the requested
/// scalar type, and the human-readable explanation of a non-ok library status.
#pragma once

#include "request.hpp"
#include "response.hpp"

namespace pce_probe {

/// Evaluates the request. Returns an "ok" response with every output converted to
/// double (mollified: plus m and X̂, and no length where there is no frame), or a response with the library's status
/// name (`pce::to_string(Status)`) and a message explaining it. Never returns non-finite numbers.
Response evaluate_request(const Request& request);

}  // namespace pce_probe
