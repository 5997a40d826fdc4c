// SPDX-License-Identifier: MIT
/// @file
/// One pass of a least-significant-digit counting sort (internal): the broad phases sort
/// their candidate pairs and BlockHessian its pattern keys by two such passes, linear in
/// the element count where `std::sort` of a million elements costs tens of milliseconds.
#pragma once

#include <cstddef>
#include <vector>

namespace pce::sim {

/// Writes `from` into `to` (of the same size) ordered by `key(e)` ∈ [0, size), elements
/// with equal keys in their order in `from` (stable). `start` is a buffer the caller may
/// keep between calls.
template <class T, class Key, class Count> void counting_pass(const std::vector<T>& from, std::vector<T>& to,
                                                              std::size_t size, Key key, std::vector<Count>& start) {
  start.assign(size + 1, 0);
  for (const T& e : from) ++start[static_cast<std::size_t>(key(e)) + 1];
  for (std::size_t i = 0; i < size; ++i) start[i + 1] += start[i];
  for (const T& e : from) to[static_cast<std::size_t>(start[static_cast<std::size_t>(key(e))]++)] = e;
}

}  // namespace pce::sim
