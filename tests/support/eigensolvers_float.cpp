// SPDX-License-Identifier: MIT
/// @file
/// The explicit instantiations declared in eigensolvers.hpp for float, compiled once for all
/// tests in a translation unit of their own (one per scalar type, see eigensolvers.hpp).
#include "eigensolvers.hpp"

namespace pce_test {
PCE_TEST_EIGENSOLVERS(, float)
}  // namespace pce_test
