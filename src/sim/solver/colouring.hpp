// SPDX-License-Identifier: MIT
// Greedy vertex colouring for block descent (internal; docs/simulation.md §5.5): two
// vertices that share an element or a declared contact get different colours, so that the
// vertices of one colour can be updated side by side.
#pragma once

#include <pce/sim/block_hessian.hpp>

#include <cstdint>
#include <vector>

namespace pce::sim {

/// The colours of a coupling graph (see the file comment). The graph is the union of a
/// static part (the elements', kept while their declaration is unchanged) and a changing
/// one (the contacts').
class Colouring {
 public:
  /// Sets the static couplings of n vertices from a declaration (`Pattern::pairs`).
  void set_static(int n, const std::vector<std::uint64_t>& declared);
  /// Colours the vertices greedily, in index order (each takes the smallest colour none of
  /// its earlier neighbours has), with the static couplings and those `declared` (a
  /// `Pattern::pairs`). Deterministic: the result depends on the graph alone. Returns false,
  /// and keeps the colours, when the static couplings did not change since the last call and
  /// the current colours already keep every pair of `declared` apart.
  bool colour(const std::vector<std::uint64_t>& declared);
  /// Forgets the colours (the next `colour` computes them afresh): a time step starts from
  /// its own couplings, not from what earlier steps left, so a resumed run colours as the
  /// uninterrupted one does.
  void restart() { coloured_ = false; }
  /// The colours, each a list of ascending vertex indices.
  const std::vector<std::vector<int>>& colours() const { return colours_; }

 private:
  /// Compressed symmetric adjacency of the off-diagonal pairs in `declared`.
  static void adjacency(int n, const std::vector<std::uint64_t>& declared, std::vector<int>& begin,
                        std::vector<int>& neighbours);
  int n_ = 0;
  std::vector<std::uint64_t> last_;                  ///< the static declaration, as given
  bool coloured_ = false;                            ///< colours_ belong to the current static couplings
  std::vector<int> begin_, neighbours_;              ///< static adjacency
  std::vector<int> extra_begin_, extra_neighbours_;  ///< the contacts' adjacency
  std::vector<int> colour_of_, seen_;
  std::vector<std::vector<int>> colours_;
};

}  // namespace pce::sim
