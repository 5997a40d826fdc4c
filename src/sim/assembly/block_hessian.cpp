// SPDX-License-Identifier: MIT
#include <pce/sim/block_hessian.hpp>

#include "util/counting_sort.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace pce::sim {

bool BlockHessian::set_pattern(int n, const Pattern& pattern) {
  if (n == n_ && m_.rows() == 3 * static_cast<Eigen::Index>(n) && pattern.pairs() == last_) {
    set_zero();
    return false;
  }
  last_ = pattern.pairs();
  n_ = n;
  // Block columns: for each j the sorted unique rows i ≤ j, the diagonal always included.
  std::vector<std::uint64_t> keys = pattern.pairs();
  keys.reserve(keys.size() + static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) keys.push_back((static_cast<std::uint64_t>(v) << 32) | static_cast<std::uint32_t>(v));
  for (const std::uint64_t key : keys)
    if ((key >> 32) >= static_cast<std::uint64_t>(n))
      throw std::logic_error("BlockHessian: pattern names vertex " + std::to_string(key >> 32) + " of " +
                             std::to_string(n));
  // Sorted by two counting passes, on i, then stably on j (linear in the key count, where
  // std::sort of the ~300 k keys of a hammock cost 14 ms per pattern change).
  {
    std::vector<std::uint64_t> scratch(keys.size());
    std::vector<std::size_t> start;
    const auto vertices = static_cast<std::size_t>(n);  // the range of either index
    counting_pass(
        keys, scratch, vertices, [](std::uint64_t key) { return key & 0xffffffffu; }, start);
    counting_pass(
        scratch, keys, vertices, [](std::uint64_t key) { return key >> 32; }, start);
  }
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  block_count_ = keys.size();
  rows_.resize(keys.size());
  row_begin_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const int j = static_cast<int>(keys[k] >> 32);
    rows_[k] = static_cast<int>(keys[k] & 0xffffffffu);
    ++row_begin_[static_cast<std::size_t>(j) + 1];
  }
  for (int j = 0; j < n; ++j) row_begin_[j + 1] += row_begin_[j];
  // Scalar columns 3j+c: 3 rows per off-diagonal block, c+1 rows of the diagonal block.
  // The compressed arrays are written directly (no per-entry insertion).
  const Eigen::Index size = 3 * static_cast<Eigen::Index>(n);
  Eigen::Index nnz = 0;
  for (int j = 0; j < n; ++j) {
    const Eigen::Index off = row_begin_[j + 1] - row_begin_[j] - 1;  // blocks above the diagonal
    nnz += 3 * (3 * off) + 6;
  }
  m_ = Eigen::SparseMatrix<double>(size, size);
  m_.makeCompressed();
  m_.resizeNonZeros(nnz);
  auto* outer = m_.outerIndexPtr();
  auto* inner = m_.innerIndexPtr();
  Eigen::Index at = 0;
  for (int j = 0; j < n; ++j)
    for (int c = 0; c < 3; ++c) {
      outer[3 * j + c] = static_cast<Eigen::SparseMatrix<double>::StorageIndex>(at);
      for (int k = row_begin_[j]; k < row_begin_[j + 1]; ++k) {
        const int i = rows_[static_cast<std::size_t>(k)];
        const int rmax = i == j ? c : 2;
        for (int r = 0; r <= rmax; ++r) inner[at++] = static_cast<Eigen::SparseMatrix<double>::StorageIndex>(3 * i + r);
      }
    }
  outer[size] = static_cast<Eigen::SparseMatrix<double>::StorageIndex>(at);
  std::fill(m_.valuePtr(), m_.valuePtr() + nnz, 0.0);
  return true;
}

void BlockHessian::set_zero() { std::fill(m_.valuePtr(), m_.valuePtr() + m_.nonZeros(), 0.0); }

Eigen::Index BlockHessian::offset(int i, int j) const {
  const auto first = rows_.begin() + row_begin_[j], last = rows_.begin() + row_begin_[j + 1];
  const auto it = std::lower_bound(first, last, i);
  if (it == last || *it != i)
    throw std::logic_error("BlockHessian: block (" + std::to_string(i) + ", " + std::to_string(j) +
                           ") was not declared in the pattern");
  return m_.outerIndexPtr()[3 * j] + 3 * static_cast<Eigen::Index>(it - first);
}

void BlockHessian::add_block(int i, int j, const Eigen::Matrix3d& B) {
  const Eigen::Index o0 = offset(i, j);
  double* v = m_.valuePtr();
  const Eigen::SparseMatrix<double>::StorageIndex* outer = m_.outerIndexPtr();
  for (int c = 0; c < 3; ++c) {
    // Row 3i sits at the same position within columns 3j, 3j+1, 3j+2.
    const Eigen::Index o = o0 - outer[3 * j] + outer[3 * j + c];
    const int rmax = i == j ? c : 2;
    for (int r = 0; r <= rmax; ++r) v[o + r] += B(r, c);
  }
}

Eigen::Matrix3d BlockHessian::diagonal_block(int i) const {
  const Eigen::Index o0 = offset(i, i);
  const double* v = m_.valuePtr();
  const Eigen::SparseMatrix<double>::StorageIndex* outer = m_.outerIndexPtr();
  Eigen::Matrix3d B;
  for (int c = 0; c < 3; ++c) {
    const Eigen::Index o = o0 - outer[3 * i] + outer[3 * i + c];
    for (int r = 0; r <= c; ++r) B(r, c) = B(c, r) = v[o + r];
  }
  return B;
}

void BlockHessian::add_diagonal(const Eigen::VectorXd& d) {
  for (int j = 0; j < n_; ++j) {
    const Eigen::Index o0 = offset(j, j);
    for (int c = 0; c < 3; ++c) {
      const Eigen::Index o = o0 - m_.outerIndexPtr()[3 * j] + m_.outerIndexPtr()[3 * j + c];
      m_.valuePtr()[o + c] += d[3 * j + c];
    }
  }
}

}  // namespace pce::sim
