// SPDX-License-Identifier: MIT
// The explicit instantiation declared in eigensolvers.hpp for the 50-digit reference scalar.
#include "eigensolvers.hpp"

namespace pce {
PCE_PSD_PROJECTION_INSTANCES(, pce_test::HighPrecision)
}  // namespace pce
