// LuReuse::low_rank (static/linear_solvers): a matrix that differs from a recent factorisation in
// a few columns is solved by a low-rank (Woodbury) update of that factorisation. It must give the
// solution, the transposed solution and the determinant (sign and magnitude) of a fresh LU, on
// random matrices and on the tangents of the shipped samples with stick and sliding statuses.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <thread>

#include <Eigen/Dense>

#include "dense_reference.hpp"
#include "common/io/configuration_file.hpp"
#include "static/backbone.hpp"
#include "lu_test_matrices.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "static/numeric_lu.hpp"
#include "static/tangent.hpp"

namespace granstab::statics {
namespace {

// Runs f in a new thread: empty caches of factorisations, and reuse switched on there only.
void in_fresh_thread(const std::function<void()>& f) {
  std::thread worker([&f] {
    default_lu_reuse().low_rank = true;
    f();
  });
  worker.join();
}

Eigen::VectorXd fresh_solve(const SparseMatrix& k, const Eigen::VectorXd& b, bool transposed,
                            int& sign, double& log10_det) {
  LuFactor lu(LuReuse{});  // no reuse: a new factorisation
  EXPECT_TRUE(lu.factorize(k));
  sign = lu.determinant_sign();
  log10_det = lu.log10_abs_determinant();
  return transposed ? lu.solve_transpose(b) : lu.solve(b);
}

// k0 factorised, then k (differing in a few columns) by a low-rank update: same results as a
// fresh LU of k. Returns the rank of the update (-1 when no update was made).
long expect_update_matches_fresh_lu(const SparseMatrix& k0, const SparseMatrix& k,
                                    double tolerance) {
  long rank = -1;
  in_fresh_thread([&] {
    LuFactor base;
    ASSERT_TRUE(base.factorize(k0));
    const LuStatistics before = lu_statistics();
    LuFactor lu;
    ASSERT_TRUE(lu.factorize(k));
    if (lu_statistics().low_rank != before.low_rank + 1) return;
    rank = lu_statistics().rank_sum - before.rank_sum;
    EXPECT_EQ(lu_statistics().numeric, before.numeric);  // no new factorisation
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0);
    for (const bool transposed : {false, true}) {
      int sign = 0;
      double log10_det = 0.0;
      const Eigen::VectorXd x_fresh = fresh_solve(k, b, transposed, sign, log10_det);
      const Eigen::VectorXd x = transposed ? lu.solve_transpose(b) : lu.solve(b);
      EXPECT_LE((x - x_fresh).norm(), tolerance * x_fresh.norm()) << "transposed " << transposed;
      EXPECT_EQ(lu.determinant_sign(), sign);
      EXPECT_NEAR(lu.log10_abs_determinant(), log10_det, 1e-8);
    }
  });
  return rank;
}

using testing::grid_matrix;

// k plus the rank-one change value * e_row (sum of e_cols)^T (new entries where k had none).
SparseMatrix rank_one_change(const SparseMatrix& k, int row, const std::vector<int>& cols,
                             double value) {
  SparseMatrix out = k;
  for (int c : cols) out.coeffRef(row, c) += value;
  out.makeCompressed();
  return out;
}

TEST(LuLowRank, RandomRankOneChangesMatchAFreshLu) {
  const SparseMatrix k0 = grid_matrix(15, 3u, 4.0);
  SparseMatrix k = rank_one_change(k0, 7, {7, 40, 100}, 0.8);
  k = rank_one_change(k, 150, {3, 150}, -1.3);
  EXPECT_EQ(expect_update_matches_fresh_lu(k0, k, 1e-12), 2);
}

// The Woodbury columns K0^-1 U are solved together (KLU sweeps its factors once per four
// columns): the same bits as one solve per column, in both directions, for 1 to 9 columns
// (whole chunks of four and the rest).
TEST(LuLowRank, SolvesOfSeveralColumnsAreTheBitsOfOneColumnSolves) {
  NumericLu lu;
  lu.matrix = std::make_shared<const SparseMatrix>(grid_matrix(12, 7u, 4.0));
  bool reused = false;
  ASSERT_TRUE(factorize_klu(lu, reused));
  const Eigen::Index n = lu.k().rows();
  for (const int sys : {UMFPACK_A, UMFPACK_At})
    for (int columns = 1; columns <= 9; ++columns) {
      Eigen::MatrixXd x(n, columns);
      for (int c = 0; c < columns; ++c)
        x.col(c) = Eigen::VectorXd::LinSpaced(n, -1.0 - c, 2.0 + 0.5 * c).array().sin();
      const Eigen::MatrixXd b = x;
      lu.solve_columns(sys, x);
      for (int c = 0; c < columns; ++c) {
        const Eigen::VectorXd one = lu.solve(sys, b.col(c), false);
        for (Eigen::Index i = 0; i < n; ++i)
          ASSERT_EQ(x(i, c), one[i])
              << "sys " << sys << ", " << columns << " columns, column " << c << ", row " << i;
      }
    }
}

TEST(LuLowRank, DeterminantSignFollowsTheUpdate) {
  // A diagonal entry driven through zero by the change flips det K: the update must see it.
  const SparseMatrix k0 = grid_matrix(10, 5u, 4.0);
  const double d = k0.coeff(33, 33);
  const SparseMatrix k = rank_one_change(k0, 33, {33}, -d - 2.0);
  ASSERT_LT(dense_reference::determinant(Eigen::MatrixXd(k)) *
                dense_reference::determinant(Eigen::MatrixXd(k0)),
            0.0);
  EXPECT_EQ(expect_update_matches_fresh_lu(k0, k, 1e-12), 1);
}

TEST(LuLowRank, LargeChangesAreFactorisedAfresh) {
  const SparseMatrix k0 = grid_matrix(15, 3u, 4.0);
  const SparseMatrix k = grid_matrix(15, 4u, 4.0);  // every column differs
  in_fresh_thread([&] {
    LuFactor base;
    ASSERT_TRUE(base.factorize(k0));
    const LuStatistics before = lu_statistics();
    LuFactor lu;
    ASSERT_TRUE(lu.factorize(k));
    EXPECT_EQ(lu_statistics().low_rank, before.low_rank);
    EXPECT_EQ(lu_statistics().numeric, before.numeric + 1);
    const Eigen::VectorXd b = Eigen::VectorXd::Ones(k.rows());
    EXPECT_LT((k * lu.solve(b) - b).norm(), 1e-12 * b.norm());
  });
}

// The stick tangent of a prepared shipped sample against the tangent with some contacts sliding
// (both directions) and one open, on the kept dofs of the stick statuses.
void expect_sample_statuses_match(const std::string& name) {
  const Configuration config =
      read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) / name);
  Network net = network_from_configuration(config);
  prepare(net, SolverOptions{});
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  std::vector<ContactStatus> stick = classify_contacts(states);
  for (std::size_t c = 0; c < states.size(); ++c)
    if (states[c].frictional && stick[c] != ContactStatus::open) stick[c] = ContactStatus::stick;
  std::vector<ContactStatus> mixed = stick;
  int changed = 0;
  for (std::size_t c = 0; c < states.size() && changed < 6; c += states.size() / 7 + 1) {
    if (!states[c].frictional || stick[c] == ContactStatus::open) continue;
    mixed[c] = changed % 2 == 0 ? ContactStatus::slide_positive : ContactStatus::slide_negative;
    ++changed;
  }
  ASSERT_GT(changed, 1) << name;
  const Reduction r = make_reduction(kept_dofs(net, states, stick));
  const SparseMatrix k0 = reduce(assemble_tangent(net, states, stick), r);
  const SparseMatrix k = reduce(assemble_tangent(net, states, mixed), r);
  // Sliding makes one row of each changed contact follow its normal deflection: rank one each.
  // The cell rows sum over all contacts, so their round-off can add a direction or two above the
  // rank threshold (seen: 7 for 6 contacts at N = 1400); the update then carries it exactly.
  for (const bool reverse : {false, true}) {  // the base may be the unsymmetric one too
    const long rank = reverse ? expect_update_matches_fresh_lu(k, k0, 1e-10)
                              : expect_update_matches_fresh_lu(k0, k, 1e-10);
    EXPECT_GE(rank, changed) << name << " reverse " << reverse;
    EXPECT_LE(rank, changed + 2) << name << " reverse " << reverse;
  }
}

TEST(LuLowRank, ShippedSamplesStickAndSlidingStatusesMatchAFreshLu) {
  expect_sample_statuses_match("tiny-triangular-periodic.granstab");
  expect_sample_statuses_match("periodic-n100-k1e4.granstab");
  expect_sample_statuses_match("series-b-n1400-k1e4-s1.granstab");
}

}  // namespace
}  // namespace granstab::statics
