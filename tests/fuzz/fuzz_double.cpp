// SPDX-License-Identifier: MIT
/// @file
/// The fuzz body for inputs of scalar type `double` (`run_scalar<double>`, `fuzz_common.hpp`):
/// the plane kinds, the point kinds and closest-feature evaluation.
#include "fuzz_closest.hpp"
#include "fuzz_plane.hpp"
#include "fuzz_points.hpp"

namespace pce_fuzz {

template void run_scalar<double>(Bytes&);

}  // namespace pce_fuzz
