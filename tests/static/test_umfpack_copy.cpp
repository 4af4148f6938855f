// LuReuse::copy_after_solves (static/umfpack_copy): after that many unrefined solves, an UMFPACK
// factor's unrefined solves read a copy of its L by rows. They must be UMFPACK's solves to the
// bit, with row pivoting, row scaling and column permutations all in play, and the copy must be
// made once per factor, at the solve after the given count (never when negative).
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Dense>

#include "lu_test_matrices.hpp"
#include "static/linear_solvers.hpp"

namespace granstab::statics {
namespace {

// A 4900-unknown grid matrix (UMFPACK's size: over LuReuse::klu_max_dofs) with a weak diagonal,
// so that UMFPACK pivots off it, and rows scaled over six decades, so that its row scaling acts.
SparseMatrix scaled_grid_matrix() {
  SparseMatrix k = testing::grid_matrix(70, 7u, 0.05);
  for (int j = 0; j < k.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(k, j); it; ++it)
      it.valueRef() *= std::pow(10.0, static_cast<double>(it.row() % 7) - 3.0);
  return k;
}

// Normwise backward error of x as a solution of K x = b (the rows span six decades).
double backward_error(const SparseMatrix& k, const Eigen::VectorXd& x, const Eigen::VectorXd& b) {
  return (k * x - b).norm() / (k.norm() * x.norm() + b.norm());
}

TEST(LuCopy, UnrefinedSolvesFromTheCopyAreUmfpacksBits) {
  const SparseMatrix k = scaled_grid_matrix();
  ASSERT_GE(k.rows(), LuReuse{}.klu_max_dofs);
  LuReuse reuse;
  reuse.copy_after_solves = 2;
  LuFactor lu(reuse);
  ASSERT_TRUE(lu.factorize(k));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0);
  const long copies = lu_statistics().copies;
  const Eigen::VectorXd umfpack = lu.solve_unrefined(b);
  EXPECT_EQ(lu.solve_unrefined(b), umfpack);  // the second solve is still UMFPACK's
  EXPECT_EQ(lu_statistics().copies, copies);
  const Eigen::VectorXd copied = lu.solve_unrefined(b);
  EXPECT_EQ(lu_statistics().copies, copies + 1);
  EXPECT_EQ(copied, umfpack);
  EXPECT_LE(backward_error(k, copied, b), 1e-14);
  const Eigen::VectorXd b2 = Eigen::VectorXd::LinSpaced(k.rows(), 3.0, -0.5).cwiseProduct(b);
  LuFactor fresh(LuReuse{});  // copy_after_solves at its default, not reached by one solve
  ASSERT_TRUE(fresh.factorize(k));
  EXPECT_EQ(lu.solve_unrefined(b2), fresh.solve_unrefined(b2));
  for (int i = 0; i < 3; ++i) lu.solve_unrefined(b);
  EXPECT_EQ(lu_statistics().copies, copies + 1);  // once per factor
  // Refined and transposed solves stay UMFPACK's.
  const SparseMatrix kt = k.transpose();
  EXPECT_LE(backward_error(kt, lu.solve_transpose(b), b), 1e-14);
  EXPECT_LE(backward_error(k, lu.solve(b), b), 1e-14);
}

TEST(LuCopy, NegativeCountNeverCopies) {
  const SparseMatrix k = scaled_grid_matrix();
  LuReuse reuse;
  reuse.copy_after_solves = -1;
  LuFactor lu(reuse);
  ASSERT_TRUE(lu.factorize(k));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0);
  const long copies = lu_statistics().copies;
  const Eigen::VectorXd first = lu.solve_unrefined(b);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(lu.solve_unrefined(b), first);
  EXPECT_EQ(lu_statistics().copies, copies);
}

}  // namespace
}  // namespace granstab::statics
