// SPDX-License-Identifier: MIT
/// @file
/// The fuzz body for inputs of scalar type `float` (`run_scalar<float>`, `fuzz_common.hpp`):
/// the plane kinds, the point kinds and closest-feature evaluation.
#include "fuzz_closest.hpp"
#include "fuzz_plane.hpp"
#include "fuzz_points.hpp"

namespace pce_fuzz {

template void run_scalar<float>(Bytes&);

}  // namespace pce_fuzz
