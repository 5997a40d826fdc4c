// SPDX-License-Identifier: MIT
/// @file
/// pce::precompiled for long double: the run-time dispatch `projected_hessian(e, strategy)` of every
/// energy type (`pce/core/precompiled.hpp`); the eigensolvers they call are in
/// `eigensolvers_long_double.cpp`.
#include <pce/energy/closest_feature.hpp>
#include <pce/energy/mollified_energy.hpp>

namespace pce {
PCE_PAIR_ENERGY_INSTANCES(, long double)
PCE_POINT_EDGE_ENERGY_INSTANCES(, long double)
PCE_POINT_POINT_ENERGY_INSTANCES(, long double)
PCE_MOLLIFIED_ENERGY_INSTANCES(, long double)
PCE_CLOSEST_FEATURE_INSTANCES(, long double)
}  // namespace pce
