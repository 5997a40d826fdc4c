// SPDX-License-Identifier: MIT
/// @file
/// The one parallel loop of the contact passes (internal): a range [0, n) cut into chunks of
/// consecutive items, handed to the threads as they come free (OpenMP, dynamic schedule:
/// the cost per item varies by orders of magnitude, and a static split left one of two
/// threads idle most of a pass), each chunk writing lists of its own; the lists are then
/// read in chunk order, which visits the items in index order whatever the thread count. So
/// sums and scatters made from them are the same, bit for bit, with one thread or many.
///
/// `PairTerms` holds what a pass evaluates this way (per chunk: each active pair's energy
/// and gradient, and the Hessian blocks), and `scatter` sums and adds them serially in that
/// order. Self contact (K = 4 vertices per pair) and obstacle contact (K = 1) both use it.
#pragma once

#include <pce/core/types.hpp>
#include <pce/sim/block_hessian.hpp>

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace pce::sim::contact {

/// The number of chunks of `chunk` items that cover n items.
inline std::size_t chunk_count(long n, long chunk) { return static_cast<std::size_t>((n + chunk - 1) / chunk); }

/// Runs `body(c, begin, end)` for every chunk c = [begin, end) of [0, n) on the threads, one
/// chunk at a time as they come free (a single chunk runs on the calling thread: no parallel
/// region for a pass that has nothing to share). A body may write only chunk c's own outputs.
template <class Body> void for_each_chunk(long n, long chunk, const Body& body) {
  const auto chunks = static_cast<long>(chunk_count(n, chunk));
#pragma omp parallel for schedule(dynamic, 1) if (chunks > 1)
  for (long c = 0; c < chunks; ++c) body(static_cast<std::size_t>(c), c * chunk, std::min(n, (c + 1) * chunk));
}

/// for_each_chunk whose body also lowers a minimum: `body(c, begin, end, t)` gets its
/// chunk's running minimum t, which starts at `start` in every chunk, and may lower it.
/// Returns the smallest of `start` and every chunk's minimum. What a body sees depends on
/// its chunk alone, never on which chunks its thread ran before, so what it records on
/// the way (the pairs whose limit was below the running minimum, say) is the same for any
/// thread count and schedule; so is the result (a minimum is exact).
template <class Body> double min_over_chunks(long n, long chunk, double start, const Body& body) {
  const auto chunks = static_cast<long>(chunk_count(n, chunk));
  double t = start;
#pragma omp parallel for schedule(dynamic, 1) reduction(min : t) if (chunks > 1)
  for (long c = 0; c < chunks; ++c) {
    double running = start;
    body(static_cast<std::size_t>(c), c * chunk, std::min(n, (c + 1) * chunk), running);
    t = std::min(t, running);
  }
  return t;
}

/// Replaces `out` with the first `count` lists of `parts` joined in chunk order.
template <class T> void join_chunks(const std::vector<std::vector<T>>& parts, std::size_t count, std::vector<T>& out) {
  out.clear();
  for (std::size_t c = 0; c < count; ++c) out.insert(out.end(), parts[c].begin(), parts[c].end());
}

/// One active pair's result of an evaluation: its index k in the pass's range, its K
/// vertices, energy, length and gradient (3K).
template <int K> struct PairTerm {
  long k = 0;
  std::array<int, K> vertices{};
  double energy = 0;
  double length = std::numeric_limits<double>::infinity();
  VecN<double, 3 * K> gradient;
};

/// One active pair's projected Hessian (3K × 3K) and its vertices.
template <int K> struct PairBlock {
  std::array<int, K> vertices;
  Eigen::Matrix<double, 3 * K, 3 * K> hessian;
};

/// Per chunk, what a pass evaluated: the active pairs' terms and Hessian blocks. Kept for
/// active pairs only, so the serial scatter touches those alone (a record per candidate
/// made it sweep ~100 MB per evaluation on the hammock; a 12×12 block per candidate would
/// cost ~1 KiB each).
template <int K> struct PairTerms {
  std::vector<std::vector<PairTerm<K>>> terms;
  std::vector<std::vector<PairBlock<K>>> blocks;
  std::size_t chunks = 0;  ///< chunks of the last pass

  /// Prepares `count` chunks (their lists are cleared by the chunks themselves).
  void prepare(std::size_t count) {
    if (terms.size() < count) {
      terms.resize(count);
      blocks.resize(count);
    }
    chunks = count;
  }
  /// Clears chunk c's lists (the chunk's first act in a pass).
  void clear(std::size_t c) {
    terms[c].clear();
    blocks[c].clear();
  }
  /// Visits every term in chunk order (the index order of the pass).
  template <class F> void for_each(const F& f) const {
    for (std::size_t c = 0; c < chunks; ++c)
      for (const PairTerm<K>& t : terms[c]) f(t);
  }
};

/// Sums the terms' energies in chunk order and adds their gradients to `gradient` and their
/// blocks to `hessian` (each when non-null), in that order; a term of infinite energy (a
/// barrier at distance 0) adds nothing but its energy.
template <int K> double scatter(const PairTerms<K>& pairs, Eigen::Matrix3Xd* gradient, BlockHessian* hessian) {
  double energy = 0;
  pairs.for_each([&](const PairTerm<K>& t) {
    energy += t.energy;
    if (!std::isfinite(t.energy) || !gradient) return;
    for (int j = 0; j < K; ++j)
      gradient->col(t.vertices[static_cast<std::size_t>(j)]) += t.gradient.template segment<3>(3 * j);
  });
  if (hessian)
    for (std::size_t c = 0; c < pairs.chunks; ++c)
      for (const PairBlock<K>& b : pairs.blocks[c]) hessian->add<K>(b.vertices, b.hessian);
  return energy;
}

}  // namespace pce::sim::contact
