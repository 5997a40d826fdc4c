// SPDX-License-Identifier: MIT
/// @file
/// `pce::project_psd` in float (see `fuzz_eigensolvers.hpp`).
#include "fuzz_eigensolvers.hpp"

namespace pce {
PCE_FUZZ_PROJECT_PSD(, float)
}  // namespace pce
