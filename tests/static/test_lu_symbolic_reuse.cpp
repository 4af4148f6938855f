// LuFactor reuses the symbolic analysis of an identical sparsity pattern (static/linear_solvers):
// the reuse must be detected exactly (same pattern only), and a reused analysis must give the
// same bits as a fresh one (the q1 stepping follows round-off, docs/static.md "Performance").
#include <gtest/gtest.h>

#include <cmath>
#include <thread>
#include <vector>

#include <Eigen/Dense>

#include "lu_test_matrices.hpp"
#include "static/linear_solvers.hpp"

namespace granstab::statics {
namespace {

using testing::grid_matrix;

Eigen::VectorXd fresh_solve(const SparseMatrix& k, const Eigen::VectorXd& b, int& sign) {
  // A new thread has an empty cache: the analysis is made from scratch.
  Eigen::VectorXd x;
  std::thread worker([&] {
    LuFactor lu;
    EXPECT_TRUE(lu.factorize(k));
    EXPECT_FALSE(lu.symbolic_reused());
    x = lu.solve(b);
    sign = lu.determinant_sign();
  });
  worker.join();
  return x;
}

TEST(LuSymbolicReuse, SamePatternReusedBitIdenticalDifferentPatternNot) {
  const SparseMatrix a = grid_matrix(12, 1u, 4.0, false);
  const SparseMatrix b = grid_matrix(12, 2u, 4.0, false);  // same pattern, other values
  const SparseMatrix c = grid_matrix(12, 3u, 4.0, true);   // one more entry
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  LuFactor lu;
  ASSERT_TRUE(lu.factorize(a));
  ASSERT_TRUE(lu.factorize(b));
  EXPECT_TRUE(lu.symbolic_reused());
  const Eigen::VectorXd x = lu.solve(rhs);
  EXPECT_LT((b * x - rhs).norm(), 1e-12 * rhs.norm());
  int sign = 0;
  const Eigen::VectorXd x_fresh = fresh_solve(b, rhs, sign);
  EXPECT_EQ(sign, lu.determinant_sign());
  for (Eigen::Index i = 0; i < x.size(); ++i) EXPECT_EQ(x[i], x_fresh[i]) << "entry " << i;
  LuFactor other;
  ASSERT_TRUE(other.factorize(c));
  EXPECT_FALSE(other.symbolic_reused());
  EXPECT_LT((c * other.solve(rhs) - rhs).norm(), 1e-12 * rhs.norm());
}

TEST(LuSymbolicReuse, DeterminantSignWithReusedAnalysis) {
  // Same pattern, diagonal shifted through the spectrum: the sign must follow the dense value.
  LuFactor lu;
  int negative = 0;
  for (double diagonal : {4.0, 0.3, -0.2, -4.0}) {
    const SparseMatrix k = grid_matrix(8, 7u, diagonal, false);
    ASSERT_TRUE(lu.factorize(k));
    const double det = Eigen::MatrixXd(k).determinant();
    EXPECT_EQ(lu.determinant_sign(), det > 0.0 ? 1 : -1) << "diagonal " << diagonal;
    EXPECT_NEAR(lu.log10_abs_determinant(), std::log10(std::abs(det)), 1e-8);
    if (diagonal != 4.0) {
      EXPECT_TRUE(lu.symbolic_reused());
    }
    negative += det < 0.0;
  }
  EXPECT_GT(negative, 0);  // both signs are exercised
}

}  // namespace
}  // namespace granstab::statics

namespace granstab::statics {
namespace {

// LuReuse::metis_min_dofs: from that size on UMFPACK orders by METIS. The factors differ (other
// pivots, other round-off), the solution and the determinant do not beyond round-off.
TEST(LuOrdering, MetisAboveTheThresholdSameSolutionAndDeterminant) {
  const SparseMatrix k = testing::grid_matrix(30, 5u, -0.3, false);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0);
  std::vector<Eigen::VectorXd> x;
  std::vector<int> sign;
  std::vector<double> log10_det;
  // One thread, the same pattern twice: the symbolic cache must not hand the AMD analysis to the
  // METIS factorisation (its entries are keyed by the ordering too).
  std::thread worker([&] {
    for (const int min_dofs : {1 << 30, 0}) {
      LuReuse reuse = default_lu_reuse();
      reuse.metis_min_dofs = min_dofs;
      reuse.refine = false;
      LuFactor lu(reuse);
      ASSERT_TRUE(lu.factorize(k));
      EXPECT_FALSE(lu.symbolic_reused()) << "metis_min_dofs " << min_dofs;
      x.push_back(lu.solve(rhs));
      sign.push_back(lu.determinant_sign());
      log10_det.push_back(lu.log10_abs_determinant());
    }
  });
  worker.join();
  ASSERT_EQ(x.size(), 2u);
  EXPECT_LT((k * x[1] - rhs).norm(), 1e-12 * rhs.norm());
  EXPECT_LT((x[1] - x[0]).norm(), 1e-10 * x[0].norm());
  EXPECT_NE(x[1], x[0]) << "the same bits: the METIS ordering did not reach UMFPACK";
  EXPECT_EQ(sign[0], sign[1]);
  EXPECT_NEAR(log10_det[0], log10_det[1], 1e-9 * std::abs(log10_det[0]));
}

}  // namespace
}  // namespace granstab::statics
