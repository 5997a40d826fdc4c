// SPDX-License-Identifier: MIT
// pce-accuracy: the float measurement (tests/support/accuracy_measure.hpp), instantiated once
// here so that the scalars compile in parallel.
#include "support/accuracy_measure.hpp"

namespace pce_test {
template SampleOutcome measure_sample<float>(const Sample&);
}  // namespace pce_test
