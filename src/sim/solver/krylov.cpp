// SPDX-License-Identifier: MIT
// The Krylov solvers' matrix, block Jacobi and conjugate gradients (krylov.hpp).
#include "solver/krylov.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace pce::sim::solver {

namespace {

using RowBlock = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;

/// The number of blocks in BlockHessian's upper block column j (its last scalar column
/// holds three rows per block).
int blocks_in_column(const Eigen::SparseMatrix<double>& upper, int j) {
  const auto* outer = upper.outerIndexPtr();
  return static_cast<int>((outer[3 * j + 3] - outer[3 * j + 2]) / 3);
}

/// Σ a[i] b[i] over [lo, hi) in four interleaved partial sums, added in a fixed order.
double chunk_dot(const double* a, const double* b, Eigen::Index lo, Eigen::Index hi) {
  double s[4] = {0, 0, 0, 0};
  Eigen::Index i = lo;
  for (; i + 4 <= hi; i += 4)
    for (int l = 0; l < 4; ++l) s[l] += a[i + l] * b[i + l];
  for (; i < hi; ++i) s[0] += a[i] * b[i];
  return (s[0] + s[1]) + (s[2] + s[3]);
}

}  // namespace

void BlockCsr::build(const Eigen::SparseMatrix<double>& upper) {
  const int n = static_cast<int>(upper.cols() / 3);
  const auto* outer = upper.outerIndexPtr();
  const auto* inner = upper.innerIndexPtr();
  rows_ = upper.rows();
  nnz_ = upper.nonZeros();
  row_begin_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < blocks_in_column(upper, j); ++k) {
      const int i = static_cast<int>(inner[outer[3 * j + 2] + 3 * k] / 3);
      ++row_begin_[static_cast<std::size_t>(i) + 1];
      if (i != j) ++row_begin_[static_cast<std::size_t>(j) + 1];
    }
  for (int i = 0; i < n; ++i) row_begin_[i + 1] += row_begin_[i];
  const auto blocks = static_cast<std::size_t>(row_begin_[static_cast<std::size_t>(n)]);
  col_.resize(blocks);
  src_col_.resize(blocks);
  src_index_.resize(blocks);
  src_transposed_.resize(blocks);
  diag_.resize(static_cast<std::size_t>(n));
  val_.assign(9 * blocks, 0.0);
  // Column j in increasing order fills row j's blocks left of the diagonal (transposed),
  // its diagonal block, then the blocks (i, j) of the rows above: every row in column order.
  std::vector<int> next(row_begin_.begin(), row_begin_.end() - 1);
  const auto place = [&](int row, int col, int j, int k, bool transposed) {
    const auto at = static_cast<std::size_t>(next[static_cast<std::size_t>(row)]++);
    col_[at] = col;
    src_col_[at] = j;
    src_index_[at] = k;
    src_transposed_[at] = transposed;
    if (row == col) diag_[static_cast<std::size_t>(row)] = static_cast<int>(at);
  };
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < blocks_in_column(upper, j); ++k) {
      const int i = static_cast<int>(inner[outer[3 * j + 2] + 3 * k] / 3);
      if (i != j) place(j, i, j, k, true);
      place(i, j, j, k, false);
    }
}

bool BlockCsr::fits(const Eigen::SparseMatrix<double>& upper) const {
  return rows_ == upper.rows() && nnz_ == upper.nonZeros() && !row_begin_.empty();
}

void BlockCsr::update(const Eigen::SparseMatrix<double>& upper) {
  const auto* outer = upper.outerIndexPtr();
  const double* v = upper.valuePtr();
  const long blocks = static_cast<long>(col_.size());
#pragma omp parallel for schedule(static)
  for (long b = 0; b < blocks; ++b) {
    const auto k = static_cast<std::size_t>(b);
    const int j = src_col_[k], index = src_index_[k];
    const bool diagonal = index == blocks_in_column(upper, j) - 1;
    double* out = &val_[9 * k];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) {
        // Entry (r, c) of upper block (i, j); a diagonal block stores r ≤ c only.
        const int rr = diagonal ? std::min(r, c) : r, cc = diagonal ? std::max(r, c) : c;
        const double value = v[outer[3 * j + cc] + 3 * index + rr];
        if (src_transposed_[k])
          out[3 * c + r] = value;
        else
          out[3 * r + c] = value;
      }
  }
}

void BlockCsr::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  const int n = vertex_count();
  y.resize(x.size());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = row_begin_[static_cast<std::size_t>(i)]; k < row_begin_[static_cast<std::size_t>(i) + 1]; ++k)
      sum += RowBlock(&val_[9 * static_cast<std::size_t>(k)]) * x.segment<3>(3 * col_[static_cast<std::size_t>(k)]);
    y.segment<3>(3 * i) = sum;
  }
}

bool BlockJacobi::setup(const BlockCsr& H) {
  const int n = H.vertex_count();
  inverse_.resize(static_cast<std::size_t>(n));
  bool ok = true;
#pragma omp parallel for schedule(static) reduction(&& : ok)
  for (int i = 0; i < n; ++i) {
    const Eigen::Matrix3d B = RowBlock(&H.values()[9 * static_cast<std::size_t>(H.diagonal(i))]);
    const Eigen::LLT<Eigen::Matrix3d> llt(B);
    const bool good = B.allFinite() && llt.info() == Eigen::Success;
    inverse_[static_cast<std::size_t>(i)] =
        good ? Eigen::Matrix3d(llt.solve(Eigen::Matrix3d::Identity())) : Eigen::Matrix3d::Zero();
    ok = ok && good;
  }
  return ok;
}

void BlockJacobi::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  const int n = static_cast<int>(inverse_.size());
  z.resize(r.size());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) z.segment<3>(3 * i) = inverse_[static_cast<std::size_t>(i)] * r.segment<3>(3 * i);
}

double Krylov::dot(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
  const Eigen::Index size = a.size();
  const long count = static_cast<long>((size + kDotChunk - 1) / kDotChunk);
  chunks.resize(static_cast<std::size_t>(count));
#pragma omp parallel for schedule(static)
  for (long c = 0; c < count; ++c)
    chunks[static_cast<std::size_t>(c)] =
        chunk_dot(a.data(), b.data(), c * kDotChunk, std::min<Eigen::Index>((c + 1) * kDotChunk, size));
  double sum = 0;
  for (const double s : chunks) sum += s;
  return sum;
}

bool Krylov::solve(const BlockCsr& H, const Preconditioner& M, const Eigen::VectorXd& rhs, double eta,
                   int max_iterations, Eigen::VectorXd& dx, double& iterations) {
  const double rhs_norm = std::sqrt(dot(rhs, rhs));
  const double target = eta * rhs_norm;
  dx.setZero(rhs.size());
  if (rhs_norm == 0) return true;
  r = rhs;
  M.apply(r, z);
  p = z;
  double rz = dot(r, z);
  for (int k = 0; k < max_iterations; ++k) {
    H.multiply(p, q);
    const double pq = dot(p, q);
    if (!(pq > 0) || !(rz > 0)) return false;  // breakdown (or a non-finite value)
    const double alpha = rz / pq;
    dx += alpha * p;
    r -= alpha * q;
    iterations += 1;
    if (std::sqrt(dot(r, r)) <= target) return dot(rhs, dx) > 0;  // converged: a descent direction?
    M.apply(r, z);
    const double rz_next = dot(r, z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return false;  // the cap
}

}  // namespace pce::sim::solver
