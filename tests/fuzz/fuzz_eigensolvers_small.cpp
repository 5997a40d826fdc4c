// SPDX-License-Identifier: MIT
// See fuzz_eigensolvers.hpp: pce::project_psd for the point kinds (9×9 point_edge, 6×6
// point_point), apart from the 12×12 instantiations so that the two build in parallel.
#include "fuzz_eigensolvers.hpp"

namespace pce {
PCE_FUZZ_PROJECT_PSD_SMALL(, float)
PCE_FUZZ_PROJECT_PSD_SMALL(, double)
PCE_FUZZ_PROJECT_PSD_SMALL(, long double)
}  // namespace pce
