// SPDX-License-Identifier: MIT
// run_batch<double>: every pair kind, length and penalty in double (batch_impl.hpp).
#include "batch_impl.hpp"

namespace pce_python {
template void run_batch<double>(const BatchCall&, const double*, const pce::BatchOutput<double>&);
}  // namespace pce_python
