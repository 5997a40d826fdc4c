// SPDX-License-Identifier: MIT
/// @file
/// Vertex-face benchmarks: `vertex_face/<quantity>/<float|double>` (see bench_common.hpp).
#include "bench_common.hpp"

namespace pce_bench {

PoolStats register_vertex_face_benchmarks() { return register_family<pce::VertexFace>(); }

}  // namespace pce_bench
