// SPDX-License-Identifier: MIT
/// @file
/// pce-probe: the evaluation of a request in one scalar type. Each scalar type is compiled
/// in a translation unit of its own (`evaluate_float.cpp`, `evaluate_double.cpp`,
/// `evaluate_long_double.cpp`, from the templates of `evaluate_scalar_impl.hpp`), since each
/// instantiates every pair kind × length × penalty × plain/mollified/closest-feature
/// evaluation: split, the three build in parallel. `evaluate_request` (`evaluate.cpp`)
/// picks one by the request's "scalar".
#pragma once

#include "request.hpp"
#include "response.hpp"

namespace pce_probe {

/// `evaluate_request` (`evaluate.hpp`) with every number of the evaluation in `Scalar`
/// (`float`, `double` or `long double`), whatever the request's "scalar" says.
template <class Scalar> Response evaluate_in(const Request& request);

extern template Response evaluate_in<float>(const Request&);
extern template Response evaluate_in<double>(const Request&);
extern template Response evaluate_in<long double>(const Request&);

}  // namespace pce_probe
