// SPDX-License-Identifier: MIT
/// @file
/// pce::precompiled for double: Eigen's dense symmetric eigensolvers behind the `numerical`
/// strategies (`pce/core/precompiled.hpp`). One translation unit per scalar type and part,
/// so that they build in parallel.
// Eigen's eigensolvers trip GCC's -Wmaybe-uninitialized at -O2 (false positives inside Eigen).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <pce/energy/psd_projection.hpp>
#include <pce/volumes/stable_neo_hookean.hpp>

namespace pce {
PCE_PSD_PROJECTION_INSTANCES(, double)
namespace detail {
PCE_SNH_INSTANCES(, double)
}  // namespace detail
}  // namespace pce
