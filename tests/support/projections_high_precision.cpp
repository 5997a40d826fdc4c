// SPDX-License-Identifier: MIT
/// @file
/// The run-time `pce::projected_hessian` of the plane, point and closest-feature kinds in the
/// 50-digit reference scalar, declared in eigensolvers.hpp: compiled once for
/// test_pair_energy_*, test_point_edge_energy, test_point_point_energy and test_closest_feature.
#include "eigensolvers.hpp"

namespace pce {
PCE_PAIR_ENERGY_INSTANCES(, pce_test::HighPrecision)
PCE_POINT_EDGE_ENERGY_INSTANCES(, pce_test::HighPrecision)
PCE_POINT_POINT_ENERGY_INSTANCES(, pce_test::HighPrecision)
PCE_CLOSEST_FEATURE_INSTANCES(, pce_test::HighPrecision)
}  // namespace pce
