// LuFactor reuses the symbolic analysis of an identical sparsity pattern (static/linear_solvers):
// the reuse must be detected exactly (same pattern only), and a reused analysis must give the
// same bits as a fresh one (the q1 stepping follows round-off, docs/static.md "Performance").
// Both backends: UMFPACK, and KLU below LuReuse::klu_max_dofs (klu_factor.cpp), which must agree
// with each other and with dense LU to round-off, the determinant's sign exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Dense>

#include "lu_test_matrices.hpp"
#include "static/linear_solvers.hpp"
#include "dense_reference.hpp"

namespace granstab::statics {
namespace {

using testing::grid_matrix;

// The reuse of a backend: KLU (the default for these small matrices) or UMFPACK.
LuReuse backend(bool klu) {
  LuReuse reuse = default_lu_reuse();
  reuse.klu_max_dofs = klu ? 1 << 30 : 0;
  return reuse;
}

class LuBackends : public ::testing::TestWithParam<bool> {};
INSTANTIATE_TEST_SUITE_P(Lu, LuBackends, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& i) {
                           return std::string(i.param ? "klu" : "umfpack");
                         });

Eigen::VectorXd fresh_solve(const SparseMatrix& k, const Eigen::VectorXd& b, int& sign,
                            const LuReuse& reuse) {
  // A new thread has an empty cache: the analysis is made from scratch.
  Eigen::VectorXd x;
  std::thread worker([&] {
    LuFactor lu(reuse);
    EXPECT_TRUE(lu.factorize(k));
    EXPECT_FALSE(lu.symbolic_reused());
    x = lu.solve(b);
    sign = lu.determinant_sign();
  });
  worker.join();
  return x;
}

TEST_P(LuBackends, SamePatternReusedBitIdenticalDifferentPatternNot) {
  const LuReuse reuse = backend(GetParam());
  const SparseMatrix a = grid_matrix(12, 1u, 4.0, false);
  const SparseMatrix b = grid_matrix(12, 2u, 4.0, false);  // same pattern, other values
  const SparseMatrix c = grid_matrix(12, 3u, 4.0, true);   // one more entry
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  LuFactor lu(reuse);
  ASSERT_TRUE(lu.factorize(a));
  ASSERT_TRUE(lu.factorize(b));
  EXPECT_TRUE(lu.symbolic_reused());
  const Eigen::VectorXd x = lu.solve(rhs);
  EXPECT_LT((b * x - rhs).norm(), 1e-12 * rhs.norm());
  int sign = 0;
  const Eigen::VectorXd x_fresh = fresh_solve(b, rhs, sign, reuse);
  EXPECT_EQ(sign, lu.determinant_sign());
  for (Eigen::Index i = 0; i < x.size(); ++i) EXPECT_EQ(x[i], x_fresh[i]) << "entry " << i;
  LuFactor other(reuse);
  ASSERT_TRUE(other.factorize(c));
  EXPECT_FALSE(other.symbolic_reused());
  EXPECT_LT((c * other.solve(rhs) - rhs).norm(), 1e-12 * rhs.norm());
}

TEST_P(LuBackends, DeterminantSignWithReusedAnalysis) {
  // Same pattern, diagonal shifted through the spectrum: the sign must follow the dense value.
  LuFactor lu(backend(GetParam()));
  int negative = 0;
  for (double diagonal : {4.0, 0.3, -0.2, -4.0}) {
    const SparseMatrix k = grid_matrix(8, 7u, diagonal, false);
    ASSERT_TRUE(lu.factorize(k));
    const double det = dense_reference::determinant(Eigen::MatrixXd(k));
    EXPECT_EQ(lu.determinant_sign(), det > 0.0 ? 1 : -1) << "diagonal " << diagonal;
    EXPECT_NEAR(lu.log10_abs_determinant(), std::log10(std::abs(det)), 1e-8);
    if (diagonal != 4.0) {
      EXPECT_TRUE(lu.symbolic_reused());
    }
    negative += det < 0.0;
  }
  EXPECT_GT(negative, 0);  // both signs are exercised
}

// KLU against UMFPACK on the same matrices (every sign of det among them): solves of K and K^T,
// refined and not, agree to round-off; the determinant's sign exactly, its magnitude to
// round-off; a singular matrix fails in both.
TEST(LuBackendsAgree, SolutionsAndDeterminants) {
  int negative = 0;
  for (const double diagonal : {4.0, 0.3, -0.2, -4.0}) {
    for (const unsigned seed : {1u, 7u, 11u}) {
      const SparseMatrix k = grid_matrix(9, seed, diagonal, seed == 11u);
      const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0);
      const Eigen::MatrixXd dense(k);
      const double det = dense_reference::determinant(dense);
      negative += det < 0.0;
      for (const bool refine : {false, true}) {
        LuReuse umfpack_reuse = backend(false), klu_reuse = backend(true);
        umfpack_reuse.refine = klu_reuse.refine = refine;
        LuFactor umfpack(umfpack_reuse), klu(klu_reuse);
        ASSERT_TRUE(umfpack.factorize(k));
        ASSERT_TRUE(klu.factorize(k));
        const std::string where = "diagonal " + std::to_string(diagonal) + " seed " +
                                  std::to_string(seed) + " refine " + std::to_string(refine);
        EXPECT_EQ(klu.determinant_sign(), det > 0.0 ? 1 : -1) << where;
        EXPECT_EQ(klu.determinant_sign(), umfpack.determinant_sign()) << where;
        EXPECT_NEAR(klu.log10_abs_determinant(), std::log10(std::abs(det)), 1e-9) << where;
        const Eigen::VectorXd x = dense_reference::lu_solve(dense, b);
        const Eigen::VectorXd xt = dense_reference::lu_solve(dense.transpose(), b);
        const double scale = 1e-11 * dense.norm() * x.norm();
        EXPECT_LT((klu.solve(b) - x).norm(), 1e-10 * x.norm()) << where;
        EXPECT_LT((klu.solve_transpose(b) - xt).norm(), 1e-10 * xt.norm()) << where;
        EXPECT_LT((klu.solve(b) - umfpack.solve(b)).norm(), 1e-10 * x.norm()) << where;
        EXPECT_LT((k * klu.solve_unrefined(b) - b).norm(), scale + 1e-12 * b.norm()) << where;
      }
    }
  }
  EXPECT_GT(negative, 0);  // both signs are exercised
  // A zero column: singular, no factors.
  SparseMatrix singular = grid_matrix(6, 3u, 4.0, false);
  for (SparseMatrix::InnerIterator it(singular, 5); it; ++it) it.valueRef() = 0.0;
  EXPECT_FALSE(LuFactor(backend(true)).factorize(singular));
  EXPECT_FALSE(LuFactor(backend(false)).factorize(singular));
}

// The componentwise backward error max_i |b - K x|_i / (|K| |x| + |b|)_i.
double backward_error(const SparseMatrix& k, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  const Eigen::MatrixXd a = Eigen::MatrixXd(k).cwiseAbs();
  const Eigen::VectorXd r = (b - k * x).cwiseAbs();
  const Eigen::VectorXd scale = a * x.cwiseAbs() + b.cwiseAbs();
  return (r.array() / scale.array()).maxCoeff();
}

// KLU's refinement (klu_factor.cpp): where the threshold pivoting (diagonal preference down to
// 0.001 of the column) lets the factors grow, the unrefined solve's backward error is well above
// round-off and the refined one's at it.
TEST(LuBackendsAgree, KluRefinementReachesRoundOff) {
  // Diagonal weights 0.005 against off-diagonal ones up to 0.5: 3.5e-14 unrefined, 1.6e-16 refined.
  const SparseMatrix k = grid_matrix(10, 5u, 0.005, false);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0);
  LuReuse refined = backend(true), plain = backend(true);
  plain.refine = false;
  LuFactor with(refined), without(plain);
  ASSERT_TRUE(with.factorize(k));
  ASSERT_TRUE(without.factorize(k));
  const double eps = std::numeric_limits<double>::epsilon();
  EXPECT_GT(backward_error(k, b, without.solve(b)), 10.0 * eps);  // there is something to refine
  EXPECT_LT(backward_error(k, b, with.solve(b)), 2.0 * eps);
  EXPECT_LT(backward_error(k.transpose(), b, with.solve_transpose(b)), 2.0 * eps);
}

// KLU refactorises in the pivot order of a factorisation no longer in use (a spare of the same
// pattern, klu_factor.cpp): the sign and magnitude of det follow the dense values across the
// spectrum, the solves are accurate; a spare whose order puts a tiny pivot on the diagonal is not
// used (KLU pivots afresh); forget_factorisations drops the spares.
TEST(LuBackendsAgree, KluRefactorisesInASparesPivotOrder) {
  std::thread worker([] {  // a new thread: no spares from other tests
    const LuReuse reuse = backend(true);
    LuStatistics& statistics = lu_statistics();
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(64, -1.0, 2.0);
    const auto factorise = [&](const SparseMatrix& k, const std::string& where) {
      // A factor that ends with this scope: its numeric object becomes the next one's spare.
      LuFactor lu(reuse);
      ASSERT_TRUE(lu.factorize(k)) << where;
      const Eigen::MatrixXd dense(k);
      const double det = dense_reference::determinant(dense);
      EXPECT_EQ(lu.determinant_sign(), det > 0.0 ? 1 : -1) << where;
      EXPECT_NEAR(lu.log10_abs_determinant(), std::log10(std::abs(det)), 1e-9) << where;
      const Eigen::VectorXd x = dense_reference::lu_solve(dense, b);
      EXPECT_LT((lu.solve(b) - x).norm(), 1e-10 * x.norm()) << where;
      EXPECT_LT((lu.solve_transpose(b) - dense_reference::lu_solve(dense.transpose(), b)).norm(),
                1e-10 * x.norm())
          << where;
    };
    // Pairs of matrices: the second, of other values (its diagonal 1 % larger, some rows
    // negated: det changes sign with their number), is refactorised in the first one's order.
    int negative = 0;
    for (const double diagonal : {4.0, -4.0})
      for (const int negated : {0, 1, 2}) {
        const std::string where =
            "diagonal " + std::to_string(diagonal) + ", " + std::to_string(negated) + " negated";
        factorise(grid_matrix(8, 9u, diagonal, false), where);
        SparseMatrix k = grid_matrix(8, 9u, diagonal * 1.01, false);
        for (int j = 0; j < k.outerSize(); ++j)
          for (SparseMatrix::InnerIterator it(k, j); it; ++it)
            if (it.row() < negated * 20 && it.row() % 20 == 0) it.valueRef() = -it.value();
        const long before = statistics.refactorisations;
        factorise(k, where + ", refactorised");
        EXPECT_EQ(statistics.refactorisations, before + 1) << where;
        negative += dense_reference::determinant(Eigen::MatrixXd(k)) < 0.0;
      }
    EXPECT_GT(negative, 0);  // both signs are exercised
    // The diagonal at 1e-13 against off-diagonal entries up to 0.5: the spare's diagonal pivots
    // would be tiny, so KLU pivots off the diagonal instead.
    SparseMatrix tiny = grid_matrix(8, 9u, 4.0, false);
    for (int j = 0; j < tiny.outerSize(); ++j) tiny.coeffRef(j, j) = 1e-13;
    long before = statistics.refactorisations;
    factorise(tiny, "tiny diagonal");
    EXPECT_EQ(statistics.refactorisations, before);
    // A spare exists again (the tiny one's), but a run that forgets takes none.
    forget_factorisations();
    before = statistics.refactorisations;
    factorise(grid_matrix(8, 9u, 4.0, false), "after forget_factorisations");
    EXPECT_EQ(statistics.refactorisations, before);
  });
  worker.join();
}

// A K held elsewhere too (the status loop's tangent) is shared by the factor, not copied, and
// factorised as a copy of it would be: the same solution bits and determinant sign.
TEST_P(LuBackends, SharedMatrixIsHeldNotCopiedWithTheBitsOfACopy) {
  const LuReuse reuse = backend(GetParam());
  const auto k = std::make_shared<const SparseMatrix>(grid_matrix(12, 4u, 4.0, false));
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(k->rows(), -1.0, 2.0);
  int copy_sign = 0, shared_sign = 0;
  const Eigen::VectorXd copy = fresh_solve(*k, rhs, copy_sign, reuse);
  Eigen::VectorXd shared;
  std::thread worker([&] {  // a fresh cache, as fresh_solve's
    LuFactor lu(reuse);
    ASSERT_TRUE(lu.factorize(k));
    EXPECT_EQ(k.use_count(), 2);  // this test's and the factor's
    shared = lu.solve(rhs);
    shared_sign = lu.determinant_sign();
  });
  worker.join();
  EXPECT_EQ(shared_sign, copy_sign);
  ASSERT_EQ(shared.size(), copy.size());
  for (Eigen::Index i = 0; i < copy.size(); ++i) EXPECT_EQ(shared[i], copy[i]) << i;
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
      reuse.klu_max_dofs = 0;  // UMFPACK's ordering is the subject
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
  // An unrefined solve: its residual is round-off of the size of |K| |x| (here |x| = 4171 for
  // |rhs| = 30), and the BLAS kernels, which OpenBLAS picks per CPU, set it. A bound of 1e-12 |rhs|
  // held on the Intel VMs and failed on an AMD EPYC one (7.6e-11 against 3.0e-11, a normwise
  // backward error of 8.6e-16); the backward error is the scale-free measure. Its bound is half
  // of n eps (n = 900), the size partial pivoting's a priori bound allows, so no BLAS should
  // reach it, while a wrong permutation gives an error of order 1.
  const double backward = (k * x[1] - rhs).norm() / (k.norm() * x[1].norm() + rhs.norm());
  EXPECT_LT(backward, 1e-13);
  EXPECT_LT((x[1] - x[0]).norm(), 1e-10 * x[0].norm());
  EXPECT_NE(x[1], x[0]) << "the same bits: the METIS ordering did not reach UMFPACK";
  EXPECT_EQ(sign[0], sign[1]);
  EXPECT_NEAR(log10_det[0], log10_det[1], 1e-9 * std::abs(log10_det[0]));
}

}  // namespace
}  // namespace granstab::statics
