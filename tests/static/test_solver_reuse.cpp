// The shortcuts of the negative-eigenvalue count (static/hill, docs/static.md "Performance"):
// SymmetricFactor reuses its analysis for the same pattern and must then give the factor a fresh
// analysis gives, also after a failed (indefinite) factorisation; LuFactor::solve_unrefined is
// the inverse of the computed factors (what the Arnoldi iteration applies), refinement aside.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "lu_test_matrices.hpp"
#include "static/linear_solvers.hpp"
#include "dense_reference.hpp"

namespace granstab::statics {
namespace {

using testing::grid_matrix;

SparseMatrix symmetric_part(const SparseMatrix& k) {
  return 0.5 * (k + SparseMatrix(k.transpose()));
}

TEST(SymmetricFactorReuse, ReusedAnalysisGivesTheFreshFactorAlsoAfterAFailure) {
  const SparseMatrix a = symmetric_part(grid_matrix(12, 1u, 4.0));
  const SparseMatrix b = symmetric_part(grid_matrix(12, 2u, 4.0));           // same pattern
  const SparseMatrix indefinite = symmetric_part(grid_matrix(12, 3u, 0.0));  // same pattern
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  SymmetricFactor fresh;
  ASSERT_TRUE(fresh.factorize(b));
  const Eigen::VectorXd expected = fresh.solve(rhs);
  EXPECT_LT((b * expected - rhs).norm(), 1e-12 * rhs.norm());

  SymmetricFactor reused;
  ASSERT_TRUE(reused.factorize(a));
  EXPECT_FALSE(reused.factorize(indefinite));  // the dense check: it has negative eigenvalues
  EXPECT_LT(dense_reference::symmetric_eigenvalues(Eigen::MatrixXd(indefinite))[0], 0.0);
  ASSERT_TRUE(reused.factorize(b));
  const Eigen::VectorXd x = reused.solve(rhs);
  for (Eigen::Index i = 0; i < x.size(); ++i) EXPECT_EQ(x[i], expected[i]) << "entry " << i;

  // Several right-hand sides at once: the same solutions.
  Eigen::MatrixXd columns(a.rows(), 3);
  columns << rhs, Eigen::VectorXd::Ones(a.rows()), Eigen::VectorXd::LinSpaced(a.rows(), 3.0, 0.5);
  const Eigen::MatrixXd xs = reused.solve_columns(columns);
  for (int c = 0; c < 3; ++c)
    EXPECT_LT((xs.col(c) - reused.solve(Eigen::VectorXd(columns.col(c)))).norm(),
              1e-13 * xs.col(c).norm());

  // Another pattern is analysed afresh.
  const SparseMatrix c = symmetric_part(grid_matrix(12, 4u, 4.0, true));
  ASSERT_TRUE(reused.factorize(c));
  EXPECT_LT((c * reused.solve(rhs) - rhs).norm(), 1e-12 * rhs.norm());
}

TEST(LuSolveUnrefined, SolvesToRoundOffOfTheFactors) {
  const SparseMatrix k = grid_matrix(15, 5u, 0.3);  // unsymmetric, indefinite
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(k.rows(), -2.0, 1.0);
  LuFactor lu;
  ASSERT_TRUE(lu.factorize(k));
  const Eigen::VectorXd x = lu.solve_unrefined(rhs), x_refined = lu.solve(rhs);
  const Eigen::VectorXd x_dense = dense_reference::lu_solve(Eigen::MatrixXd(k), rhs);
  EXPECT_LT((x - x_dense).norm(), 1e-10 * x_dense.norm());
  EXPECT_LT((x_refined - x_dense).norm(), 1e-10 * x_dense.norm());
  EXPECT_LT((k * x - rhs).norm(), 1e-12 * rhs.norm());
}

}  // namespace
}  // namespace granstab::statics
