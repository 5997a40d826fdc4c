// SPDX-License-Identifier: MIT
/// @file
/// The Krylov solvers of `linear_solver` pcg and amg (docs/simulation.md §5.3): the full
/// symmetric block-CSR copy of H they multiply with, the block Jacobi preconditioner, and
/// conjugate gradients with any preconditioner. Parallel with OpenMP, and the same bits for
/// any number of threads: each row of a product is one thread's sum in a fixed order, and
/// every dot product is summed in fixed chunks (kDotChunk), the chunks' sums then in order.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace pce::sim::solver {

/// Entries per chunk of a dot product: each chunk is summed serially, then the chunks'
/// sums in order, whatever the number of threads.
inline constexpr Eigen::Index kDotChunk = 4096;

/// H (given as BlockHessian's upper triangle) as a full symmetric matrix of 3×3 blocks in
/// block-row order: row i's blocks sorted by column, each stored row-major.
class BlockCsr {
 public:
  /// The block structure of `upper` (BlockHessian's layout: 3×3 blocks, the diagonal ones
  /// stored as their upper triangles).
  void build(const Eigen::SparseMatrix<double>& upper);
  /// Whether `build` was called for a matrix with `upper`'s size and number of entries.
  bool fits(const Eigen::SparseMatrix<double>& upper) const;
  /// Copies the values of `upper` (same structure as at `build`) into the blocks.
  void update(const Eigen::SparseMatrix<double>& upper);
  /// y = H x (rows in parallel, each summed in column order).
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  /// Number of vertices n (H is 3n×3n).
  int vertex_count() const { return static_cast<int>(row_begin_.size()) - 1; }
  /// Block row i's blocks are [row_begin()[i], row_begin()[i + 1]).
  const std::vector<int>& row_begin() const { return row_begin_; }
  /// Block k's column vertex.
  const std::vector<int>& columns() const { return col_; }
  /// Block k's 9 values, row-major, at 9k.
  const std::vector<double>& values() const { return val_; }
  /// Index of row i's diagonal block.
  int diagonal(int i) const { return diag_[static_cast<std::size_t>(i)]; }

 private:
  std::vector<int> row_begin_, col_, diag_;
  /// Block k's source in `upper`: the upper block column j, the block's index in it, and
  /// whether block k is that block transposed (k below the diagonal).
  std::vector<int> src_col_, src_index_;
  std::vector<char> src_transposed_;
  std::vector<double> val_;
  Eigen::Index rows_ = 0, nnz_ = 0;
};

/// z = M⁻¹ r for a symmetric positive definite M.
class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  /// z = M⁻¹ r (z has r's size afterwards).
  virtual void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const = 0;
};

/// Block Jacobi: M is H's 3×3 diagonal blocks.
class BlockJacobi final : public Preconditioner {
 public:
  /// Inverts each diagonal block of `H`; false when one is not finite and positive definite
  /// (its Cholesky factorisation fails).
  bool setup(const BlockCsr& H);
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

 private:
  std::vector<Eigen::Matrix3d> inverse_;
};

/// Conjugate gradients' vectors and the dot products' chunk sums, kept between solves.
struct Krylov {
  Eigen::VectorXd r, z, p, q;
  mutable std::vector<double> chunks;
  /// aᵀb summed in chunks of kDotChunk (independent of the thread count).
  double dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const;
  /// Solves H dx = rhs by conjugate gradients preconditioned by `M`, from dx = 0. True when
  /// ‖rhs − H dx‖ ≤ `eta` ‖rhs‖ within `max_iterations` and rhsᵀdx > 0; false at the cap,
  /// when pᵀHp or rᵀz is not > 0 (or not finite), or when dx is no descent direction.
  /// Adds the iterations done to `iterations`.
  bool solve(const BlockCsr& H, const Preconditioner& M, const Eigen::VectorXd& rhs, double eta, int max_iterations,
             Eigen::VectorXd& dx, double& iterations);
};

}  // namespace pce::sim::solver
