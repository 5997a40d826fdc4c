// SPDX-License-Identifier: MIT
/// @file
/// `pce::project_psd` in double (see `fuzz_eigensolvers.hpp`).
#include "fuzz_eigensolvers.hpp"

namespace pce {
PCE_FUZZ_PROJECT_PSD(, double)
}  // namespace pce
