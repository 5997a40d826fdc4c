// SPDX-License-Identifier: MIT
// Greedy vertex colouring (colouring.hpp).
#include "solver/colouring.hpp"

#include <algorithm>

namespace pce::sim {

void Colouring::adjacency(int n, const std::vector<std::uint64_t>& declared, std::vector<int>& begin,
                          std::vector<int>& neighbours) {
  std::vector<std::uint64_t> pairs;
  pairs.reserve(declared.size());
  for (const std::uint64_t key : declared)
    if ((key >> 32) != (key & 0xffffffffu)) pairs.push_back(key);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  begin.assign(static_cast<std::size_t>(n) + 1, 0);
  for (const std::uint64_t key : pairs) {
    ++begin[(key >> 32) + 1];
    ++begin[(key & 0xffffffffu) + 1];
  }
  for (std::size_t v = 0; v < static_cast<std::size_t>(n); ++v) begin[v + 1] += begin[v];
  neighbours.resize(static_cast<std::size_t>(begin.back()));
  std::vector<int> fill(begin.begin(), begin.end() - 1);
  for (const std::uint64_t key : pairs) {
    const auto j = static_cast<int>(key >> 32), i = static_cast<int>(key & 0xffffffffu);
    neighbours[static_cast<std::size_t>(fill[static_cast<std::size_t>(i)]++)] = j;
    neighbours[static_cast<std::size_t>(fill[static_cast<std::size_t>(j)]++)] = i;
  }
}

void Colouring::set_static(int n, const std::vector<std::uint64_t>& declared) {
  if (n == n_ && declared == last_) return;
  n_ = n;
  last_ = declared;
  adjacency(n, declared, begin_, neighbours_);
  coloured_ = false;
}

bool Colouring::colour(const std::vector<std::uint64_t>& declared) {
  if (coloured_) {
    bool apart = true;
    for (const std::uint64_t key : declared) {
      const auto j = static_cast<std::size_t>(key >> 32), i = static_cast<std::size_t>(key & 0xffffffffu);
      if (i != j && colour_of_[i] == colour_of_[j]) {
        apart = false;
        break;
      }
    }
    if (apart) return false;
  }
  coloured_ = true;
  adjacency(n_, declared, extra_begin_, extra_neighbours_);
  colour_of_.assign(static_cast<std::size_t>(n_), -1);
  seen_.assign(1, -1);
  colours_.clear();
  for (int v = 0; v < n_; ++v) {
    const auto mark = [&](const std::vector<int>& begin, const std::vector<int>& neighbours) {
      for (int e = begin[static_cast<std::size_t>(v)]; e < begin[static_cast<std::size_t>(v) + 1]; ++e) {
        const int c = colour_of_[static_cast<std::size_t>(neighbours[static_cast<std::size_t>(e)])];
        if (c >= 0) seen_[static_cast<std::size_t>(c)] = v;
      }
    };
    mark(begin_, neighbours_);
    mark(extra_begin_, extra_neighbours_);
    int c = 0;
    while (c < static_cast<int>(seen_.size()) && seen_[static_cast<std::size_t>(c)] == v) ++c;
    if (c == static_cast<int>(seen_.size())) seen_.push_back(-1);
    if (c == static_cast<int>(colours_.size())) colours_.emplace_back();
    colour_of_[static_cast<std::size_t>(v)] = c;
    colours_[static_cast<std::size_t>(c)].push_back(v);
  }
  return true;
}

}  // namespace pce::sim
