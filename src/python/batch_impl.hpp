// SPDX-License-Identifier: MIT
/// @file
/// The template of `run_batch` (batch.hpp), included by batch_double.cpp and batch_float.cpp
/// only: dispatch to the pair kind, length and penalty, then the rows split across threads.
#pragma once

// GCC 12 at -O3 reports `-Wmaybe-uninitialized` inside `pce::closest_feature_energy` (a
// false positive in the header, as pce-probe notes): silenced for the library's headers only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <pce/pce.hpp>
#pragma GCC diagnostic pop
#else
#include <pce/pce.hpp>
#endif

#include "batch.hpp"

#include <algorithm>
#include <system_error>
#include <thread>
#include <vector>

namespace pce_python {

namespace detail {

/// `out` moved on by `first` rows.
template <class Scalar>
pce::BatchOutput<Scalar> rows_from(const pce::BatchOutput<Scalar>& out, std::size_t first, int d, int f) {
  const auto shift = [first](auto* p, std::size_t width) { return p ? p + first * width : p; };
  const auto D = static_cast<std::size_t>(d);
  pce::BatchOutput<Scalar> r;
  r.status = shift(out.status, 1);
  r.length = shift(out.length, 1);
  r.value = shift(out.value, 1);
  r.gradient = shift(out.gradient, D);
  r.hessian = shift(out.hessian, D * D);
  r.projected = shift(out.projected, D * D);
  r.eigenvalues = shift(out.eigenvalues, static_cast<std::size_t>(f));
  r.feature = shift(out.feature, 1);
  return r;
}

/// `body(first, count)` over `count` rows in `threads` contiguous ranges, the first in this
/// thread. A range whose thread cannot be started (the system's limit) runs in this thread.
template <class F> void in_threads(std::size_t count, int threads, F body) {
  const std::size_t t =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(threads, 1)), std::max<std::size_t>(count, 1));
  const std::size_t chunk = (count + t - 1) / t;
  std::vector<std::thread> pool;
  std::vector<std::size_t> not_started;
  pool.reserve(t - 1);
  for (std::size_t k = 1; k < t; ++k) {
    const std::size_t first = std::min(count, k * chunk), last = std::min(count, first + chunk);
    try {
      pool.emplace_back([=] { body(first, last - first); });
    } catch (const std::system_error&) {
      not_started.push_back(k);
    }
  }
  body(std::size_t(0), std::min(count, chunk));
  for (const std::size_t k : not_started) {
    const std::size_t first = std::min(count, k * chunk), last = std::min(count, first + chunk);
    body(first, last - first);
  }
  for (auto& th : pool) th.join();
}

template <class Pair, class Scalar, class Length, class Penalty>
void plain(const BatchCall& call, const Scalar* x, const pce::BatchOutput<Scalar>& out, const Length& length,
           const Penalty& penalty) {
  in_threads(call.count, call.threads, [&](std::size_t first, std::size_t n) {
    pce::evaluate_batch<Pair>(x + first * Pair::dofs, n, length, penalty, call.projection,
                              rows_from(out, first, Pair::dofs, Pair::frame_dofs));
  });
}

template <class Pair, class Scalar, class Penalty>
void closest(const BatchCall& call, const Scalar* x, const pce::BatchOutput<Scalar>& out, const Penalty& penalty) {
  in_threads(call.count, call.threads, [&](std::size_t first, std::size_t n) {
    pce::closest_feature_batch<Pair>(x + first * 12, n, penalty, call.projection, rows_from(out, first, 12, 9));
  });
}

template <class Scalar, class Penalty>
void with_penalty(const BatchCall& call, const Scalar* x, const pce::BatchOutput<Scalar>& out, const Penalty& p) {
  const pce::UnsignedLength unsigned_length;
  const pce::SignedLength signed_length{call.side};
  switch (call.kind) {
    case Kind::vertex_face:
      if (call.closest_feature) return closest<pce::VertexFace>(call, x, out, p);
      if (call.signed_length) return plain<pce::VertexFace>(call, x, out, signed_length, p);
      return plain<pce::VertexFace>(call, x, out, unsigned_length, p);
    case Kind::edge_edge:
      if (call.closest_feature) return closest<pce::EdgeEdge>(call, x, out, p);
      if (call.signed_length) return plain<pce::EdgeEdge>(call, x, out, signed_length, p);
      return plain<pce::EdgeEdge>(call, x, out, unsigned_length, p);
    case Kind::point_edge:
      return plain<pce::PointEdge>(call, x, out, unsigned_length, p);
    case Kind::point_point:
      return plain<pce::PointPoint>(call, x, out, unsigned_length, p);
  }
}

}  // namespace detail

template <class Scalar> void run_batch(const BatchCall& call, const Scalar* x, const pce::BatchOutput<Scalar>& out) {
  const double* a = call.parameters;
  switch (call.penalty) {
    case PenaltyKind::quadratic:
      return detail::with_penalty(call, x, out, pce::QuadraticPenalty{a[0], a[1]});
    case PenaltyKind::cubic:
      return detail::with_penalty(call, x, out, pce::CubicPenalty{a[0], a[1], a[2]});
    case PenaltyKind::log_barrier:
      return detail::with_penalty(call, x, out, pce::LogBarrierPenalty{a[0], a[1]});
  }
}

}  // namespace pce_python
