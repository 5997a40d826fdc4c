// SPDX-License-Identifier: MIT
/// @file
/// The global Hessian as a block-sparse symmetric matrix of 3×3 vertex blocks, assembled
/// into a **reused sparsity pattern**: effects first declare the vertex tuples they couple
/// (`Pattern`), the pattern is built once per time step (it changes only when the contact
/// set does), and every Newton iteration then adds element blocks by direct offsets into
/// the compressed storage — no triplet lists, no sorting, no allocation per iteration.
///
/// Storage: the upper triangle of the 3n×3n scalar matrix in Eigen's compressed
/// column-major format (what CHOLMOD and Eigen's LDLᵀ read with an `Upper` view).
/// A vertex index < 0 stands for a kinematic vertex (an obstacle's): its rows and columns
/// are not unknowns and are skipped.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <array>
#include <cstdint>
#include <vector>

namespace pce::sim {

/// The vertex pairs (i, j) whose 3×3 blocks may be non-zero.
class Pattern {
 public:
  /// Declares that an element couples all the vertices in `v` (entries < 0 are ignored).
  template <std::size_t K> void add(const std::array<int, K>& v) {
    for (std::size_t a = 0; a < K; ++a)
      for (std::size_t b = 0; b < K; ++b)
        if (v[a] >= 0 && v[b] >= 0 && v[a] <= v[b]) pairs_.push_back(key(v[a], v[b]));
  }
  /// Declares the diagonal block of `vertex` (≥ 0).
  void add(int vertex) { pairs_.push_back(key(vertex, vertex)); }
  /// Forgets every declaration.
  void clear() { pairs_.clear(); }
  /// The declared pairs (i ≤ j), packed as (j << 32) | i, unsorted and possibly repeated.
  const std::vector<std::uint64_t>& pairs() const { return pairs_; }

 private:
  static std::uint64_t key(int i, int j) {
    return (static_cast<std::uint64_t>(j) << 32) | static_cast<std::uint32_t>(i);
  }
  std::vector<std::uint64_t> pairs_;
};

/// The Hessian of the incremental potential: 3×3 blocks over vertex pairs, stored as the
/// upper triangle of a sparse 3n×3n matrix (see the file comment) with the structure a
/// `Pattern` declares.
class BlockHessian {
 public:
  /// Builds the compressed structure for `n` vertices from `pattern` (every diagonal block
  /// is always present, so the mass matrix fits). Values are zero afterwards. Returns false,
  /// and keeps the structure, when `pattern` declares exactly what the previous call did
  /// (effects declare in a fixed order, so an unchanged pattern is one comparison away):
  /// the linear solver's symbolic analysis stays valid then.
  bool set_pattern(int n, const Pattern& pattern);
  /// Zeroes the values, keeping the structure.
  void set_zero();
  /// Adds `H` (3K×3K, symmetric) for vertices `v`; entries of `v` < 0 are skipped.
  /// Every pair must have been declared (checked; a missing block throws std::logic_error).
  template <int K> void add(const std::array<int, K>& v, const Eigen::Matrix<double, 3 * K, 3 * K>& H) {
    for (int b = 0; b < K; ++b) {
      if (v[b] < 0) continue;
      for (int a = 0; a < K; ++a) {
        if (v[a] < 0 || v[a] > v[b]) continue;
        add_block(v[a], v[b], H.template block<3, 3>(3 * a, 3 * b));
      }
    }
  }
  /// Adds the 3×3 block `B` at vertex pair (i, j), i ≤ j (only the upper part of a
  /// diagonal block is stored).
  void add_block(int i, int j, const Eigen::Matrix3d& B);
  /// The symmetric 3×3 diagonal block of vertex `i` (0 ≤ i < n).
  Eigen::Matrix3d diagonal_block(int i) const;
  /// Adds `d` to the scalar diagonal (the mass term M/h²), length 3n.
  void add_diagonal(const Eigen::VectorXd& d);
  /// The assembled upper triangle.
  const Eigen::SparseMatrix<double>& matrix() const { return m_; }
  /// The assembled upper triangle, writable (the linear solvers read it in place).
  Eigen::SparseMatrix<double>& matrix() { return m_; }
  /// Number of vertices n (the matrix is 3n×3n).
  int vertex_count() const { return n_; }
  /// Number of stored 3×3 blocks (the pattern's size).
  std::size_t block_count() const { return block_count_; }

 private:
  /// Offset of row 3i in column 3j (k = 0), found by binary search in column j's rows.
  Eigen::Index offset(int i, int j) const;
  int n_ = 0;
  std::size_t block_count_ = 0;
  Eigen::SparseMatrix<double> m_;
  std::vector<int> rows_;            ///< per block column j: its row vertices i ≤ j, sorted
  std::vector<int> row_begin_;       ///< start of block column j in rows_
  std::vector<std::uint64_t> last_;  ///< the previous call's declarations, as given
};

}  // namespace pce::sim
