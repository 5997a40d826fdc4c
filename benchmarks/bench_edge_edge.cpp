// SPDX-License-Identifier: MIT
/// @file
/// Edge-edge benchmarks: `edge_edge/<quantity>/<float|double>` (see bench_common.hpp).
#include "bench_common.hpp"

namespace pce_bench {

PoolStats register_edge_edge_benchmarks() { return register_family<pce::EdgeEdge>(); }

}  // namespace pce_bench
