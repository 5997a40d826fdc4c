// SPDX-License-Identifier: MIT
/// @file
/// PointPoint benchmarks: `point_point/<quantity>/<float|double>` (see bench_common.hpp).
#include "bench_common.hpp"

namespace pce_bench {

PoolStats register_point_point_benchmarks() { return register_family<pce::PointPoint>(); }

}  // namespace pce_bench
