// SPDX-License-Identifier: MIT
// BlockHessian: blocks land where a dense assembly puts them; undeclared blocks throw;
// kinematic (negative) vertices are skipped; set_zero keeps the structure.
#include <pce/sim/block_hessian.hpp>

#include <gtest/gtest.h>

#include <random>

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
