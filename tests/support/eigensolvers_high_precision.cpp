// SPDX-License-Identifier: MIT
// The explicit instantiation declared in eigensolvers.hpp for the 50-digit reference scalar.
#include "eigensolvers.hpp"

namespace pce {
PCE_TEST_PROJECT_PSD(, pce_test::HighPrecision)
}  // namespace pce
