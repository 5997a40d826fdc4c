// SPDX-License-Identifier: MIT
/// @file
/// The stability measurement (`stability_measure.hpp`) and the paper's direct forms
/// (`naive_forms.hpp`) for long double, compiled once for test_stability, test_naive_forms and
/// pce-stability-table (one translation unit per scalar type, so that they build in parallel).
#include "naive_forms.hpp"
#include "stability_measure.hpp"

namespace pce_test {
PCE_TEST_MEASURE(, long double)
PCE_TEST_NAIVE_FORMS(, long double)
}  // namespace pce_test
