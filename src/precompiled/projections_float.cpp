// SPDX-License-Identifier: MIT
/// @file
/// pce::precompiled for float: the run-time dispatch `projected_hessian(e, strategy)` of every
/// energy type (`pce/core/precompiled.hpp`); the eigensolvers they call are in
/// `eigensolvers_float.cpp`.
#include <pce/energy/closest_feature.hpp>
#include <pce/energy/mollified_energy.hpp>

namespace pce {
PCE_PAIR_ENERGY_INSTANCES(, float)
PCE_POINT_EDGE_ENERGY_INSTANCES(, float)
PCE_POINT_POINT_ENERGY_INSTANCES(, float)
PCE_MOLLIFIED_ENERGY_INSTANCES(, float)
PCE_CLOSEST_FEATURE_INSTANCES(, float)
}  // namespace pce
