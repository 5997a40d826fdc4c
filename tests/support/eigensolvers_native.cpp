// SPDX-License-Identifier: MIT
// The explicit instantiations declared in eigensolvers.hpp for the native scalars,
// compiled once for all tests (the 50-digit one is in eigensolvers_high_precision.cpp, so
// that the two halves build in parallel).
#include "eigensolvers.hpp"

namespace pce_test {
PCE_TEST_EIGENSOLVERS(, float)
PCE_TEST_EIGENSOLVERS(, double)
PCE_TEST_EIGENSOLVERS(, long double)
}  // namespace pce_test

namespace pce {
PCE_TEST_PROJECT_PSD(, float)
PCE_TEST_PROJECT_PSD(, double)
PCE_TEST_PROJECT_PSD(, long double)
}  // namespace pce
