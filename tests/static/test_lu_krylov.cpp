// LuReuse::krylov (static/linear_solvers): a factorisation is deferred and its solves run GMRES
// preconditioned with a recent LU of the thread. The solutions must match a fresh LU's to the
// tolerance, the determinant sign must be the exact one (a deferred K is factorised for it), and
// a GMRES solve over its bound must fall back to a factorisation. On the shipped samples, the
// complementarity loops with SolverOptions::krylov_solves (a load step's: low-rank updates or
// deferred factorisations; a check's: low-rank updates) must end on the statuses, increment and
// determinant sign of the loop with an LU per iteration.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <thread>
#include <utility>

#include <Eigen/Dense>

#include "dense_reference.hpp"
#include "common/io/configuration_file.hpp"
#include "lu_test_matrices.hpp"
#include "static/backbone.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "static/tangent.hpp"

namespace granstab::statics {
namespace {

// Runs f in a new thread: an empty cache of factorisations, deferral switched on there only.
void in_fresh_thread(const std::function<void()>& f, int max_iterations = 24) {
  std::thread worker([&f, max_iterations] {
    default_lu_reuse().krylov = true;
    default_lu_reuse().krylov_min_dofs = 0;  // these test matrices are small
    default_lu_reuse().max_krylov_iterations = max_iterations;
    f();
  });
  worker.join();
}

struct Fresh {
  Eigen::VectorXd x, xt;
  int sign = 0;
};

Fresh fresh_lu(const SparseMatrix& k, const Eigen::VectorXd& b) {
  LuFactor lu(LuReuse{});  // no reuse: a new factorisation
  EXPECT_TRUE(lu.factorize(k));
  return {lu.solve(b), lu.solve_transpose(b), lu.determinant_sign()};
}

SparseMatrix changed(const SparseMatrix& k, int row, const std::vector<int>& cols, double value) {
  SparseMatrix out = k;
  for (int c : cols) out.coeffRef(row, c) += value;
  out.makeCompressed();
  return out;
}

// k0 factorised, k deferred: its solves (plain, transposed) by GMRES without a factorisation,
// within tolerance of a fresh LU's, then its exact determinant sign by one factorisation.
void expect_deferred_matches_fresh_lu(const SparseMatrix& k0, const SparseMatrix& k,
                                      double tolerance) {
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0);
  const Fresh fresh = fresh_lu(k, b);
  in_fresh_thread([&] {
    LuFactor base;
    ASSERT_TRUE(base.factorize(k0));
    const LuStatistics before = lu_statistics();
    LuFactor lu;
    ASSERT_TRUE(lu.factorize(k));
    EXPECT_FALSE(lu.factorised());
    EXPECT_EQ(lu_statistics().deferred, before.deferred + 1);
    const Eigen::VectorXd x = lu.solve(b), xt = lu.solve_transpose(b);
    EXPECT_EQ(lu_statistics().numeric, before.numeric);  // GMRES converged, nothing factorised
    EXPECT_EQ(lu_statistics().krylov_solves, before.krylov_solves + 2);
    EXPECT_LE((x - fresh.x).norm(), tolerance * fresh.x.norm());
    EXPECT_LE((xt - fresh.xt).norm(), tolerance * fresh.xt.norm());
    EXPECT_EQ(lu.determinant_sign(), fresh.sign);
    EXPECT_TRUE(lu.factorised());
    EXPECT_EQ(lu_statistics().numeric, before.numeric + 1);
    EXPECT_LE((lu.solve_unrefined(b) - fresh.x).norm(), tolerance * fresh.x.norm());
  });
}

using testing::grid_matrix;

// GMRES stops at a normwise backward error of 1e-12 (LuReuse::krylov_tolerance); these matrices
// are diagonally dominant (condition ~10), so the solutions are within ~1e-11 of the LU's.
constexpr double solution_tolerance = 1e-10;

TEST(LuKrylov, LowRankChangesMatchAFreshLu) {
  const SparseMatrix k0 = grid_matrix(15, 3u, 4.0);
  SparseMatrix k = changed(k0, 7, {7, 40, 100}, 0.8);
  k = changed(k, 150, {3, 150}, -1.3);
  expect_deferred_matches_fresh_lu(k0, k, solution_tolerance);
}

TEST(LuKrylov, DeterminantSignOfTheDeferredMatrixNotOfThePreconditioner) {
  // A diagonal entry driven through zero flips det K: the sign must be K's, not K0's.
  const SparseMatrix k0 = grid_matrix(10, 5u, 4.0);
  const double d = k0.coeff(33, 33);
  const SparseMatrix k = changed(k0, 33, {33}, -d - 2.0);
  ASSERT_LT(dense_reference::determinant(Eigen::MatrixXd(k)) *
                dense_reference::determinant(Eigen::MatrixXd(k0)),
            0.0);
  expect_deferred_matches_fresh_lu(k0, k, solution_tolerance);
}

TEST(LuKrylov, SmallChangesEverywhereMatchAFreshLu) {
  // Every entry moves by ~1 %, as the geometry does over a load step.
  const SparseMatrix k0 = grid_matrix(15, 3u, 4.0);
  SparseMatrix k = k0;
  const SparseMatrix other = grid_matrix(15, 4u, 4.0);
  k += 0.01 * other;
  k.makeCompressed();
  expect_deferred_matches_fresh_lu(k0, k, solution_tolerance);
}

TEST(LuKrylov, OverTheBoundItFactorises) {
  const SparseMatrix k0 = grid_matrix(15, 3u, 4.0);
  const SparseMatrix k = grid_matrix(15, 4u, 4.0);  // another matrix: GMRES needs many steps
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(k.rows());
  in_fresh_thread(
      [&] {
        LuFactor base;
        ASSERT_TRUE(base.factorize(k0));
        const LuStatistics before = lu_statistics();
        LuFactor lu;
        ASSERT_TRUE(lu.factorize(k));
        const Eigen::VectorXd x = lu.solve(b);
        EXPECT_EQ(lu_statistics().krylov_failed, before.krylov_failed + 1);
        EXPECT_EQ(lu_statistics().numeric, before.numeric + 1);
        EXPECT_TRUE(lu.factorised());
        EXPECT_LT((k * x - b).norm(), 1e-12 * b.norm());
      },
      3);
}

TEST(LuKrylov, AfterASlowSolveTheNextMatrixIsFactorised) {
  // K1 is deferred against K0's LU and its solve takes some GMRES iterations. The next matrix is
  // deferred against K0 too while they are at most krylov_stale_iterations, and factorised at
  // once when they were more.
  const SparseMatrix k0 = grid_matrix(15, 3u, 4.0);
  SparseMatrix k1 = k0;
  k1 += 0.05 * grid_matrix(15, 4u, 4.0);
  k1.makeCompressed();
  const SparseMatrix k2 = changed(k1, 7, {7, 40}, 0.1);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(k0.rows());
  // K0 factorised, K1 deferred and solved, then K2: K1's GMRES iterations, whether K2 was
  // factorised at once.
  const auto run = [&](int stale) {
    std::pair<long, bool> out{0, false};
    in_fresh_thread([&] {
      default_lu_reuse().krylov_stale_iterations = stale;
      LuFactor base, first, next;
      ASSERT_TRUE(base.factorize(k0));
      const long before = lu_statistics().krylov_iterations;
      ASSERT_TRUE(first.factorize(k1));
      ASSERT_FALSE(first.factorised());
      EXPECT_LT((k1 * first.solve(b) - b).norm(), 1e-10 * b.norm());
      out.first = lu_statistics().krylov_iterations - before;
      ASSERT_TRUE(next.factorize(k2));
      out.second = next.factorised();
    });
    return out;
  };
  const auto [iterations, never] = run(1000);
  ASSERT_GE(iterations, 3) << "not the case under test";
  EXPECT_FALSE(never);
  EXPECT_FALSE(run(static_cast<int>(iterations)).second);
  EXPECT_TRUE(run(static_cast<int>(iterations) - 1).second);
}

TEST(LuKrylov, SingularDeferredMatrixIsReported) {
  const SparseMatrix k0 = grid_matrix(8, 2u, 4.0);
  SparseMatrix k = k0;
  for (int j = 0; j < k.cols(); ++j) k.coeffRef(5, j) = 0.0;  // a zero row
  k.makeCompressed();
  in_fresh_thread(
      [&] {
        LuFactor base;
        ASSERT_TRUE(base.factorize(k0));
        LuFactor lu;
        ASSERT_TRUE(lu.factorize(k));  // deferred: not known yet
        Eigen::VectorXd x;
        EXPECT_FALSE(lu.try_solve(Eigen::VectorXd::Ones(k.rows()), x));
        EXPECT_EQ(lu.determinant_sign(), 0);
      },
      3);
}

TEST(LuKrylov, BelowTheMinimumSizeItFactorises) {
  // krylov_min_dofs: a matrix with fewer rows is factorised at once, even with a base at hand.
  const SparseMatrix k0 = grid_matrix(15, 3u, 4.0);
  const SparseMatrix k = changed(k0, 7, {7, 40}, 0.8);
  in_fresh_thread([&] {
    default_lu_reuse().krylov_min_dofs = static_cast<int>(k.rows());
    LuFactor base;
    ASSERT_TRUE(base.factorize(k0));  // a base of that size at hand
    default_lu_reuse().krylov_min_dofs = static_cast<int>(k.rows()) + 1;
    const LuStatistics before = lu_statistics();
    LuFactor lu;
    ASSERT_TRUE(lu.factorize(k));
    EXPECT_TRUE(lu.factorised());
    EXPECT_EQ(lu_statistics().deferred, before.deferred);
    EXPECT_EQ(lu_statistics().numeric, before.numeric + 1);
    default_lu_reuse().krylov_min_dofs = static_cast<int>(k.rows());  // at the minimum: deferred
    LuFactor at_minimum;
    ASSERT_TRUE(at_minimum.factorize(k));
    EXPECT_FALSE(at_minimum.factorised());
    EXPECT_EQ(lu_statistics().deferred, before.deferred + 1);
  });
}

// LuReuse::refine off: a solve is the unrefined one (the inverse of the computed factors), counted
// as such; the load step's reuse has it off unless SolverOptions::refine_solves.
TEST(LuRefine, OffSolvesAreTheUnrefinedOnes) {
  const SparseMatrix k = grid_matrix(12, 3u, 4.0);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0);
  LuReuse reuse;
  reuse.refine = false;
  LuFactor lu(reuse);
  ASSERT_TRUE(lu.factorize(k));
  const LuStatistics before = lu_statistics();
  const Eigen::VectorXd x = lu.solve(b);
  EXPECT_EQ(lu_statistics().solves, before.solves);
  EXPECT_EQ(lu_statistics().unrefined_solves, before.unrefined_solves + 1);
  EXPECT_EQ(x, lu.solve_unrefined(b));
  EXPECT_LT((k * x - b).norm(), 1e-12 * b.norm());
  LuFactor refined;  // the default refines
  ASSERT_TRUE(refined.factorize(k));
  const LuStatistics before_refined = lu_statistics();
  refined.solve(b);
  EXPECT_EQ(lu_statistics().solves, before_refined.solves + 1);
  EXPECT_FALSE(lu_reuse(SolverOptions{}).refine);
  SolverOptions refining;
  refining.refine_solves = true;
  EXPECT_TRUE(lu_reuse(refining).refine);
}

// The stability check's loop (the predictor with a pure load increment) on a prepared shipped
// sample, at its start and after a load step, with and without deferred factorisations.
void expect_same_predictor(const std::string& name) {
  const Configuration config =
      read_configuration(std::filesystem::path(GRANSTAB_SAMPLES_DIR) / name);
  Network net = network_from_configuration(config);
  net.constraints.cell_free = {true, true};
  net.constraints.remove_rattlers = true;
  SolverOptions exact;
  exact.krylov_solves = false;
  SolverOptions krylov = exact;
  krylov.krylov_solves = true;
  prepare(net, exact);
  const double sigma1 = net.loading.sigma[0];
  for (int step = 0; step < 3; ++step) {
    Network probe = net;
    probe.loading.sigma[1] *= 1.0 + 1e-6;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
    const Eigen::VectorXd increment = residual(probe, zero, evaluate_contacts(probe, zero)) -
                                      residual(net, zero, evaluate_contacts(net, zero));
    // a, b: the check's loop (determinant wanted); c, d: a load step's (no determinant).
    PredictorResult a, b, c, d;
    std::thread([&] {
      a = predict(probe, exact, nullptr, &increment);
      c = predict(probe, exact, nullptr, &increment, nullptr, false);
    }).join();
    std::thread([&] {
      // The preconditioner: an LU of the all-stick tangent of this state.
      const std::vector<ContactState> states = evaluate_contacts(net, zero);
      std::vector<ContactStatus> stick = classify_contacts(states);
      for (std::size_t c = 0; c < states.size(); ++c)
        if (states[c].frictional && stick[c] != ContactStatus::open)
          stick[c] = ContactStatus::stick;
      // Deferred at any size here (periodic-n100 is below the default krylov_min_dofs).
      default_lu_reuse().krylov_min_dofs = 0;
      LuReuse reuse = default_lu_reuse();
      reuse.krylov = true;
      LuFactor base(reuse);
      ASSERT_TRUE(base.factorize(reduce(assemble_tangent(net, states, stick),
                                        make_reduction(kept_dofs(net, states, stick)))));
      // The check factorises or updates a recent LU (its determinant is exact), never defers.
      LuStatistics before = lu_statistics();
      b = predict(probe, krylov, nullptr, &increment);
      EXPECT_EQ(lu_statistics().deferred, before.deferred) << name;
      EXPECT_GT(lu_statistics().low_rank + lu_statistics().numeric,
                before.low_rank + before.numeric)
          << name;
      // A step's loop updates the check's LU where few columns changed, defers otherwise.
      before = lu_statistics();
      d = predict(probe, krylov, nullptr, &increment, nullptr, false);
      EXPECT_GT(lu_statistics().low_rank + lu_statistics().deferred,
                before.low_rank + before.deferred)
          << name;
    }).join();
    for (const auto& [lu, reused] : {std::pair{&a, &b}, std::pair{&c, &d}}) {
      ASSERT_TRUE(lu->ok) << name << ": " << lu->failure;
      ASSERT_TRUE(reused->ok) << name << ": " << reused->failure;
      EXPECT_EQ(lu->statuses, reused->statuses) << name << " step " << step;
      // (A deferred factorisation at the end of a step's loop leaves the sign unknown: 0.)
      if (reused == &b || reused->determinant_sign != 0) {
        EXPECT_EQ(lu->determinant_sign, reused->determinant_sign) << name << " step " << step;
      }
      // The tolerance of the loop's solves (backward error 1e-12) times the conditioning of K.
      EXPECT_LE((lu->dq - reused->dq).norm(), 1e-9 * lu->dq.norm()) << name << " step " << step;
    }
    net.loading.sigma[1] = sigma1 * (1.0 + 1e-3 * (step + 1));
    ASSERT_TRUE(load_step(net, exact).ok) << name;
    rebuild_degrees_of_freedom(net);
  }
}

TEST(LuKrylov, ShippedSamplesCheckLoopMatchesTheLuLoop) {
  expect_same_predictor("periodic-n100-k1e4.granstab");
  expect_same_predictor("series-b-n1400-k1e4-s1.granstab");
}

}  // namespace
}  // namespace granstab::statics
