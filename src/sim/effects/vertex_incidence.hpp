// SPDX-License-Identifier: MIT
/// @file
/// Which items (elements, contact pairs) each vertex is a corner of, and as which corner
/// (internal): compressed rows, one per vertex, items in ascending order. Block descent's
/// local terms sum, per vertex, over its row.
#pragma once

#include <cstddef>
#include <vector>

namespace pce::sim {

/// One item of a vertex's row: the item's index and the vertex's slot in it.
struct Incident {
  int item = 0;  ///< the item's index in its list
  int slot = 0;  ///< the vertex's position among the item's vertices
};

/// Per vertex, the items it is a corner of (see the file comment).
class VertexIncidence {
 public:
  /// Builds the rows for `n` vertices from `count` items; `vertices_of(i)` returns item i's
  /// vertices (an indexable list; entries < 0 or ≥ n are not vertices and are skipped).
  template <class VerticesOf> void build(int n, std::size_t count, VerticesOf&& vertices_of) {
    begin_.assign(static_cast<std::size_t>(n) + 1, 0);
    for (std::size_t i = 0; i < count; ++i)
      for (const int v : vertices_of(i))
        if (v >= 0 && v < n) ++begin_[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 0; v < static_cast<std::size_t>(n); ++v) begin_[v + 1] += begin_[v];
    entries_.resize(static_cast<std::size_t>(begin_.back()));
    std::vector<int> fill(begin_.begin(), begin_.end() - 1);
    for (std::size_t i = 0; i < count; ++i) {
      int slot = 0;
      for (const int v : vertices_of(i)) {
        if (v >= 0 && v < n)
          entries_[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = {static_cast<int>(i), slot};
        ++slot;
      }
    }
  }
  /// Forgets every row.
  void clear() {
    begin_.clear();
    entries_.clear();
  }
  /// Whether rows were built for vertex v.
  bool has(int v) const { return v >= 0 && static_cast<std::size_t>(v) + 1 < begin_.size(); }
  /// Vertex v's items, ascending: [begin(v), end(v)).
  const Incident* begin(int v) const { return entries_.data() + begin_[static_cast<std::size_t>(v)]; }
  /// The end of vertex v's row.
  const Incident* end(int v) const { return entries_.data() + begin_[static_cast<std::size_t>(v) + 1]; }

 private:
  std::vector<int> begin_;
  std::vector<Incident> entries_;
};

}  // namespace pce::sim
