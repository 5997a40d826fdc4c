// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: the parts of a response that do not depend on the scalar type of the
/// evaluation, compiled once (`evaluate_messages.cpp`) for the three per-scalar
/// evaluations of `evaluate_scalar_impl.hpp`: texts explaining a non-ok status, and the
/// labelling of a successful evaluation.
#pragma once

#include "request.hpp"
#include "response.hpp"

#include <string>

namespace pce_probe {

/// A number for a message; never prints a bare non-finite token.
std::string describe(double v);

/// Which penalty parameter the library rejected (empty if none).
std::string penalty_problem(const pce::QuadraticPenalty& p);
std::string penalty_problem(const pce::CubicPenalty& p);
std::string penalty_problem(const pce::LogBarrierPenalty& p);

/// Why the library reported `degenerate` for this request's pair kind (or closest-feature
/// evaluation).
const char* degenerate_message(const Request& req);

/// A successful response: the evaluation, labelled with the request's projection and scalar.
Response ok_response(Evaluation e, const Request& req);

}  // namespace pce_probe
