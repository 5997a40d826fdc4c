// SPDX-License-Identifier: MIT
// run_batch<float>: every pair kind, length and penalty in float (batch_impl.hpp).
#include "batch_impl.hpp"

namespace pce_python {
template void run_batch<float>(const BatchCall&, const float*, const pce::BatchOutput<float>&);
}  // namespace pce_python
