// SPDX-License-Identifier: MIT
/// @file
/// The Python module's batched pair evaluation: one call evaluates `count` pairs with
/// `pce::evaluate_batch` (or `pce::closest_feature_batch`) in `threads` threads, each
/// handed a contiguous range of rows. `run_batch<Scalar>` is instantiated once per scalar,
/// in batch_double.cpp and batch_float.cpp.
#pragma once

#include <pce/energy/evaluate_batch.hpp>

#include <cstddef>

namespace pce_python {

/// The pair kinds, in the order `pce.evaluate` names them.
enum class Kind { vertex_face = 0, edge_edge = 1, point_edge = 2, point_point = 3 };
/// The penalties, in the order of `pce.Quadratic`, `pce.Cubic`, `pce.LogBarrier`.
enum class PenaltyKind { quadratic = 0, cubic = 1, log_barrier = 2 };

/// One batched evaluation, as checked by the Python layer (python/pce/__init__.py).
struct BatchCall {
  Kind kind = Kind::vertex_face;
  bool signed_length = false;  ///< SignedLength{side}, else UnsignedLength
  pce::Side side = pce::Side::positive;
  PenaltyKind penalty = PenaltyKind::quadratic;
  double parameters[3] = {0, 0, 0};  ///< (k, eps, -), (k, eps, delta), (k, dhat, -)
  pce::Projection projection = pce::Projection::analytic;
  bool closest_feature = false;
  int threads = 1;  ///< ≥ 1
  std::size_t count = 0;
};

/// Coordinates per pair of `kind` (12, 9 or 6).
int dofs(Kind kind);
/// Frame-space eigenvalues per pair (9, 6 or 3; 9 with closest features).
int frame_dofs(Kind kind, bool closest_feature);

/// Evaluates `call.count` pairs at `x` (row-major, `dofs` per pair) into `out` (each
/// output's rows as `pce::BatchOutput` documents; null outputs skipped).
template <class Scalar> void run_batch(const BatchCall& call, const Scalar* x, const pce::BatchOutput<Scalar>& out);

extern template void run_batch<double>(const BatchCall&, const double*, const pce::BatchOutput<double>&);
extern template void run_batch<float>(const BatchCall&, const float*, const pce::BatchOutput<float>&);

}  // namespace pce_python
