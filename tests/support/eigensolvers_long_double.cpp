// SPDX-License-Identifier: MIT
/// @file
/// The explicit instantiations declared in eigensolvers.hpp for long double, compiled once for all
/// tests in a translation unit of their own (one per scalar type, see eigensolvers.hpp).
#include "eigensolvers.hpp"

namespace pce_test {
PCE_TEST_EIGENSOLVERS(, long double)
}  // namespace pce_test
