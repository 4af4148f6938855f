// reduce (static/linear_solvers): the submatrix on the kept dofs, copied column by column. It must
// hold exactly the kept entries, explicit zeros included: the fixed pattern
// (TangentParts::fixed_pattern) relies on them to keep the reduced pattern, hence LuFactor's
// symbolic analysis, across status changes.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "static/linear_solvers.hpp"

namespace granstab::statics {
namespace {

TEST(Reduce, KeptEntriesInOrderWithExplicitZeros) {
  const int n = 7;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if ((i + 2 * j) % 3 != 1)
        t.emplace_back(i, j, (i == j || (i + j) % 4 == 0) ? 0.0 : i - 0.5 * j);
  SparseMatrix k(n, n);
  k.setFromTriplets(t.begin(), t.end());
  const std::vector<char> keep = {1, 0, 1, 1, 0, 1, 1};
  const Reduction r = make_reduction(keep);
  const SparseMatrix out = reduce(k, r);
  ASSERT_EQ(out.rows(), 5);
  ASSERT_EQ(out.cols(), 5);
  ASSERT_TRUE(out.isCompressed());
  // Every stored entry of k in a kept row and column, and no other.
  long expected = 0;
  for (int j = 0; j < n; ++j)
    for (SparseMatrix::InnerIterator it(k, j); it; ++it) expected += keep[it.row()] && keep[j];
  EXPECT_EQ(out.nonZeros(), expected);
  const Eigen::MatrixXd dense(k);
  for (int j = 0; j < out.outerSize(); ++j) {
    int last = -1;
    for (SparseMatrix::InnerIterator it(out, j); it; ++it) {
      EXPECT_GT(it.row(), last);  // sorted rows, as UMFPACK requires
      last = static_cast<int>(it.row());
      EXPECT_EQ(it.value(), dense(r.reduced_to_full[it.row()], r.reduced_to_full[j]));
    }
  }
  const Eigen::MatrixXd reduced(out);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      EXPECT_EQ(reduced(i, j), dense(r.reduced_to_full[i], r.reduced_to_full[j]));
  // Nothing eliminated: the matrix itself.
  const Reduction all = make_reduction(std::vector<char>(n, 1));
  EXPECT_EQ(reduce(k, all).nonZeros(), k.nonZeros());
}

// The taking overload (a K its caller no longer needs, handed to a factor): with every dof kept
// it takes k's storage, the same matrix without a copy; with some dropped it leaves k as it was
// (solve_kept reads it again for the dropped rows' misfit) and gives the same submatrix.
TEST(Reduce, TakingOverloadTakesOnlyWhenEverythingIsKept) {
  const int n = 5;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if ((i + j) % 2 == 0) t.emplace_back(i, j, 1.0 + i + 10.0 * j);
  SparseMatrix k(n, n);
  k.setFromTriplets(t.begin(), t.end());
  const Eigen::MatrixXd dense(k);

  const Reduction some = make_reduction({1, 1, 0, 1, 1});
  SparseMatrix kept = k;
  const SparseMatrix sub = reduce(std::move(kept), some);
  EXPECT_EQ((Eigen::MatrixXd(kept) - dense).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((Eigen::MatrixXd(sub) - Eigen::MatrixXd(reduce(k, some))).cwiseAbs().maxCoeff(), 0.0);

  const Reduction all = make_reduction(std::vector<char>(n, 1));
  SparseMatrix taken = k;
  const double* storage = taken.valuePtr();
  const SparseMatrix whole = reduce(std::move(taken), all);
  EXPECT_EQ(whole.valuePtr(), storage);  // the same storage: not copied
  EXPECT_EQ(taken.nonZeros(), 0);
  EXPECT_EQ((Eigen::MatrixXd(whole) - dense).cwiseAbs().maxCoeff(), 0.0);

  // kept_part: k itself when everything is kept, the submatrix otherwise.
  SparseMatrix spare;
  EXPECT_EQ(&kept_part(k, all, spare), &k);
  EXPECT_EQ(
      (Eigen::MatrixXd(kept_part(k, some, spare)) - Eigen::MatrixXd(sub)).cwiseAbs().maxCoeff(),
      0.0);
}

}  // namespace
}  // namespace granstab::statics
