// SPDX-License-Identifier: MIT
// BlockHessian: blocks land where a dense assembly puts them; undeclared blocks throw;
// kinematic (negative) vertices are skipped; set_zero keeps the structure.
#include <pce/sim/block_hessian.hpp>

#include <gtest/gtest.h>

#include <random>
#include <set>

using namespace pce::sim;

namespace {
Eigen::MatrixXd dense(const BlockHessian& H) {
  const Eigen::SparseMatrix<double> full = H.matrix().selfadjointView<Eigen::Upper>();
  return Eigen::MatrixXd(full);
}

Eigen::Matrix<double, 12, 12> random_symmetric(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix<double, 12, 12> A;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) A(i, j) = u(rng);
  return A + A.transpose();
}
}  // namespace

TEST(BlockHessian, MatchesDenseAssembly) {
  std::mt19937 rng(7);
  const int n = 9;
  const std::vector<std::array<int, 4>> elements = {{0, 3, 5, 8}, {2, 1, 7, 4}, {8, 6, 0, 2}, {5, 3, 4, 1}};
  Pattern p;
  for (const auto& e : elements) p.add(e);
  BlockHessian H;
  H.set_pattern(n, p);
  Eigen::MatrixXd ref = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (const auto& e : elements) {
    const auto A = random_symmetric(rng);
    H.add<4>(e, A);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) ref.block<3, 3>(3 * e[a], 3 * e[b]) += A.block<3, 3>(3 * a, 3 * b);
  }
  Eigen::VectorXd d = Eigen::VectorXd::LinSpaced(3 * n, 1, 2);
  H.add_diagonal(d);
  ref.diagonal() += d;
  EXPECT_LT((dense(H) - ref).cwiseAbs().maxCoeff(), 1e-14);
  H.set_zero();
  EXPECT_EQ(dense(H).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(H.block_count(), static_cast<std::size_t>(n + 4 * 6 - 3));  // 9 diagonal + unique off-diagonal pairs
}

TEST(BlockHessian, SkipsKinematicVerticesAndRejectsUndeclaredBlocks) {
  Pattern p;
  p.add(std::array<int, 2>{0, -1});
  p.add(1);
  BlockHessian H;
  H.set_pattern(3, p);
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Identity();
  H.add<2>({0, -1}, A);
  EXPECT_EQ(dense(H)(0, 0), 1.0);
  EXPECT_THROW(H.add<2>({0, 2}, A), std::logic_error);
}

TEST(BlockHessian, StructureIsThatOfTheDeclaredBlocksInAnyOrder) {
  // Many elements declared in random order, with repeats: every column lists exactly the
  // distinct declared rows i ≤ j in ascending order, whatever order they came in.
  std::mt19937 rng(11);
  const int n = 300;
  std::uniform_int_distribution<int> vertex(0, n - 1);
  Pattern p;
  std::set<std::pair<int, int>> blocks;
  for (int v = 0; v < n; ++v) blocks.insert({v, v});
  for (int e = 0; e < 2000; ++e) {
    const std::array<int, 3> t{vertex(rng), vertex(rng), vertex(rng)};
    p.add(t);
    if (e % 3 == 0) p.add(t);  // repeated declarations
    for (const int a : t)
      for (const int b : t)
        if (a <= b) blocks.insert({b, a});  // (column, row)
  }
  BlockHessian H;
  EXPECT_TRUE(H.set_pattern(n, p));
  EXPECT_EQ(H.block_count(), blocks.size());
  const Eigen::SparseMatrix<double>& m = H.matrix();
  std::set<std::pair<int, int>> found;
  for (Eigen::Index c = 0; c < m.outerSize(); ++c) {
    int previous = -1;
    for (Eigen::SparseMatrix<double>::InnerIterator it(m, c); it; ++it) {
      EXPECT_GT(static_cast<int>(it.row()), previous);  // ascending rows within a column
      previous = static_cast<int>(it.row());
      found.insert({static_cast<int>(it.col()) / 3, static_cast<int>(it.row()) / 3});
    }
  }
  EXPECT_EQ(found, blocks);
  EXPECT_FALSE(H.set_pattern(n, p));  // the same declarations: structure kept
}

TEST(BlockHessian, RejectsAPatternNamingAVertexBeyondN) {
  Pattern p;
  p.add(std::array<int, 2>{1, 5});
  BlockHessian H;
  EXPECT_THROW(H.set_pattern(5, p), std::logic_error);
}

TEST(BlockHessian, ADiagonalBlockIsReadBackSymmetric) {
  Pattern pattern;
  pattern.add(std::array<int, 2>{0, 1});
  BlockHessian H;
  H.set_pattern(2, pattern);
  H.set_zero();
  Eigen::Matrix3d B;
  B << 4, 1, 2, 1, 5, 3, 2, 3, 6;
  H.add_block(1, 1, B);
  H.add_block(1, 1, B);
  EXPECT_EQ(H.diagonal_block(1), 2 * B);
  EXPECT_EQ(H.diagonal_block(0), Eigen::Matrix3d::Zero());
}
