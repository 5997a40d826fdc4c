// SPDX-License-Identifier: MIT
/// @file
/// PointEdge benchmarks: `point_edge/<quantity>/<float|double>` (see bench_common.hpp).
#include "bench_common.hpp"

namespace pce_bench {

PoolStats register_point_edge_benchmarks() { return register_family<pce::PointEdge>(); }

}  // namespace pce_bench
