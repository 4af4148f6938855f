// The exact LCP behind the existence criterion (static/complementarity,
// docs/static.md "Existence of a consistent status set"): small constructed
// problems with a known answer, on which the status iteration of the predictor
// (block principal pivoting: flip every inconsistent status at once) cycles.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

#include <Eigen/Core>

#include "dense_reference.hpp"
#include "static/complementarity.hpp"

namespace granstab::statics {
namespace {

// The predictor's rule on an LCP: contacts in alpha slide (lambda free, w = 0);
// then a sliding one with lambda < 0 sticks and a sticking one with w < 0
// slides, all at once. Starts with every contact sliding (as the predictor
// starts critical contacts). True if it settles.
bool block_pivoting_settles(const Eigen::MatrixXd& m, const Eigen::VectorXd& q) {
  const int n = static_cast<int>(q.size());
  std::vector<char> alpha(n, 1);
  std::set<std::vector<char>> seen;
  while (seen.insert(alpha).second) {
    std::vector<int> a;
    for (int i = 0; i < n; ++i)
      if (alpha[i]) a.push_back(i);
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(n);
    if (!a.empty()) {
      Eigen::MatrixXd maa(a.size(), a.size());
      Eigen::VectorXd qa(a.size());
      for (std::size_t i = 0; i < a.size(); ++i) {
        qa[i] = -q[a[i]];
        for (std::size_t j = 0; j < a.size(); ++j) maa(i, j) = m(a[i], a[j]);
      }
      const Eigen::VectorXd la = dense_reference::full_pivot_solve(maa, qa);
      for (std::size_t i = 0; i < a.size(); ++i) lambda[a[i]] = la[i];
    }
    const Eigen::VectorXd w = q + m * lambda;
    std::vector<char> next(n);
    for (int i = 0; i < n; ++i) next[i] = alpha[i] ? lambda[i] >= 0.0 : w[i] < 0.0;
    if (next == alpha) return true;
    alpha = next;
  }
  return false;
}

void expect_solution(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, const LcpResult& r) {
  ASSERT_EQ(r.outcome, LcpResult::Outcome::solved) << r.how;
  const Eigen::VectorXd w = q + m * r.lambda;
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    EXPECT_GE(r.lambda[i], 0.0);
    EXPECT_GE(w[i], -1e-12);
    EXPECT_LE(std::min(r.lambda[i], w[i]), 1e-12);
  }
}

TEST(Complementarity, CyclingIterationButASolutionExists) {
  // Found by a search over small integer LCPs; the unique solution is lambda =
  // (1, 1, 0), w = (0, 0, 2).
  Eigen::MatrixXd m(3, 3);
  m << 1, 0, 3, 0, 3, -2, 3, 1, 4;
  const Eigen::VectorXd q = (Eigen::VectorXd(3) << -1, -3, -2).finished();
  EXPECT_FALSE(block_pivoting_settles(m, q));
  const LcpResult r = solve_lcp(m, q);
  expect_solution(m, q, r);
  EXPECT_NEAR(r.lambda[0], 1.0, 1e-12);
  EXPECT_NEAR(r.lambda[1], 1.0, 1e-12);
  EXPECT_NEAR(r.lambda[2], 0.0, 1e-12);
}

TEST(Complementarity, CyclingIterationAndNoSolution) {
  Eigen::MatrixXd m(3, 3);
  m << 1, 2, 4, -3, 1, -1, -1, -2, 1;
  const Eigen::VectorXd q = (Eigen::VectorXd(3) << -3, 0, -3).finished();
  EXPECT_FALSE(block_pivoting_settles(m, q));
  const LcpResult r = solve_lcp(m, q);
  EXPECT_EQ(r.outcome, LcpResult::Outcome::no_solution) << r.how;
  // Without enumeration Lemke's ray proves nothing: undecided.
  EXPECT_EQ(solve_lcp(m, q, 1e-10, 0).outcome, LcpResult::Outcome::undecided);
}

TEST(Complementarity, OneContactLimitPoint) {
  // A contact whose sticking increment leaves the cone (q < 0) and whose
  // sliding branch has a negative stiffness (M < 0): no consistent status
  // (docs/static.md, contact (17, 78)).
  const Eigen::MatrixXd m = Eigen::MatrixXd::Constant(1, 1, -0.5);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, -1.0);
  EXPECT_EQ(solve_lcp(m, q).outcome, LcpResult::Outcome::no_solution);
  // With a positive sliding stiffness it slides: lambda = 2.
  const LcpResult r = solve_lcp(-m, q);
  expect_solution(-m, q, r);
  EXPECT_NEAR(r.lambda[0], 2.0, 1e-12);
}

TEST(Complementarity, PMatrixAlwaysSolvedByLemke) {
  // Positive definite (unsymmetric) M: a P-matrix, unique solution for every q.
  Eigen::MatrixXd m(4, 4);
  m << 4, 1, -1, 0.5, 0, 3, 1, -1, 1, -1, 5, 0, 0.5, 1, 0, 2;
  for (int k = 0; k < 16; ++k) {
    Eigen::VectorXd q(4);
    for (int i = 0; i < 4; ++i) q[i] = (k >> i) & 1 ? -1.0 - i : 0.5 * i;
    const LcpResult r = solve_lcp(m, q);
    expect_solution(m, q, r);
  }
}

TEST(Complementarity, WarmStartFromTheRightSupportSkipsLemke) {
  // A P-matrix (diagonally dominant) LCP of 60 unknowns: one solution, whose support is the
  // right guess; a wrong guess (one index dropped) must fall back to Lemke.
  const int n = 60;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m(n, n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) m(r, c) = r == c ? n : u(rng);
  Eigen::VectorXd q(n);
  for (int i = 0; i < n; ++i) q[i] = u(rng);
  const LcpResult cold = solve_lcp(m, q);
  ASSERT_EQ(cold.outcome, LcpResult::Outcome::solved);
  EXPECT_EQ(cold.how, "lemke");
  std::vector<int> support;
  for (int i = 0; i < n; ++i)
    if (cold.lambda[i] > 1e-10) support.push_back(i);
  ASSERT_GT(support.size(), 5u);
  ASSERT_LT(support.size(), static_cast<std::size_t>(n - 5));
  const LcpResult warm = solve_lcp(m, q, 1e-10, 16, &support);
  expect_solution(m, q, warm);
  EXPECT_EQ(warm.how, "warm start");
  EXPECT_LT((warm.lambda - cold.lambda).cwiseAbs().maxCoeff(), 1e-12);
  const std::vector<int> wrong(support.begin() + 1, support.end());
  const LcpResult fallback = solve_lcp(m, q, 1e-10, 16, &wrong);
  expect_solution(m, q, fallback);
  EXPECT_EQ(fallback.how, "lemke");
}

TEST(Complementarity, WarmStartOnASingularSupportFallsBackToLemke) {
  // M_aa singular on the guess {0, 1}: the solve on it fails, so Lemke decides.
  Eigen::MatrixXd m(2, 2);
  m << 1, 1, 1, 1;
  const Eigen::VectorXd q = Eigen::Vector2d(-1.0, -1.0);
  const std::vector<int> guess{0, 1};
  const LcpResult r = solve_lcp(m, q, 1e-10, 16, &guess);
  expect_solution(m, q, r);
  EXPECT_EQ(r.how, "lemke");
}

// Lemke one pivot at a time over the whole tableau (the form before the batched updates), the
// reference of the next test: lambda, or an empty vector on a ray.
Eigen::VectorXd lemke_one_pivot_at_a_time(const Eigen::MatrixXd& m, const Eigen::VectorXd& q) {
  const int n = static_cast<int>(q.size());
  const int z0 = 2 * n, rhs = 2 * n + 1;
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(n, 2 * n + 2);
  t.leftCols(n).setIdentity();
  t.block(0, n, n, n) = -m;
  t.col(z0).setConstant(-1.0);
  t.col(rhs) = q;
  std::vector<int> basis(n);
  for (int i = 0; i < n; ++i) basis[i] = i;
  const auto pivot = [&](int r, int c) {
    t.row(r) /= t(r, c);
    for (int i = 0; i < n; ++i)
      if (i != r && t(i, c) != 0.0) t.row(i) -= t(i, c) * t.row(r);
    const int left = basis[r];
    basis[r] = c;
    return left;
  };
  int r0 = 0;
  for (int i = 1; i < n; ++i)
    if (q[i] < q[r0]) r0 = i;
  int entering = n + r0;
  pivot(r0, z0);
  const double tiny = 1e-12 * std::max(1.0, t.leftCols(2 * n + 1).cwiseAbs().maxCoeff());
  for (int it = 0; it < 50 * n + 100; ++it) {
    int r = -1;
    double best = 0.0;
    for (int i = 0; i < n; ++i) {
      if (t(i, entering) <= tiny) continue;
      const double ratio = t(i, rhs) / t(i, entering);
      const bool tie = r >= 0 && std::abs(ratio - best) <= 1e-12 * std::max(1.0, std::abs(best));
      if (r < 0 || (!tie && ratio < best) || (tie && basis[i] == z0)) {
        r = i;
        best = ratio;
      }
    }
    if (r < 0) return {};
    const int left = pivot(r, entering);
    if (left == z0) {
      Eigen::VectorXd lambda = Eigen::VectorXd::Zero(n);
      for (int i = 0; i < n; ++i)
        if (basis[i] >= n && basis[i] < 2 * n) lambda[basis[i] - n] = std::max(0.0, t(i, rhs));
      return lambda;
    }
    entering = left < n ? left + n : left - n;
  }
  return {};
}

TEST(Complementarity, BatchedLemkeHasTheBitsOfOnePivotAtATime) {
  // P-matrices (diagonally dominant, unsymmetric) with q mostly negative: about n pivots, so
  // several batches of pending pivots and the ratio tests between them.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const int n : {3, 40, 150}) {
    Eigen::MatrixXd m(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) m(i, j) = u(rng);
    m.diagonal().array() += n;
    Eigen::VectorXd q(n);
    for (int i = 0; i < n; ++i) q[i] = u(rng) - 0.7;
    const Eigen::VectorXd reference = lemke_one_pivot_at_a_time(m, q);
    ASSERT_EQ(reference.size(), n);
    const LcpResult r = solve_lcp(m, q);
    ASSERT_EQ(r.how, "lemke");
    expect_solution(m, q, r);
    for (int i = 0; i < n; ++i) EXPECT_EQ(r.lambda[i], reference[i]) << "n " << n << ", " << i;
  }
}

// The enumeration's reference: every support with a full-pivot LU, singular blocks that admit a
// continuum of candidates leave the answer open.
LcpResult::Outcome enumerated_outcome(const Eigen::MatrixXd& m, const Eigen::VectorXd& q,
                                      double tol) {
  const int n = static_cast<int>(q.size());
  bool singular = false;
  for (unsigned mask = 0; mask < (1u << n); ++mask) {
    std::vector<int> a;
    for (int i = 0; i < n; ++i)
      if (mask & (1u << i)) a.push_back(i);
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(n);
    if (!a.empty()) {
      const int k = static_cast<int>(a.size());
      Eigen::MatrixXd maa(k, k);
      Eigen::VectorXd qa(k);
      for (int i = 0; i < k; ++i) {
        qa[i] = -q[a[i]];
        for (int j = 0; j < k; ++j) maa(i, j) = m(a[i], a[j]);
      }
      bool invertible = false;
      const Eigen::VectorXd la = dense_reference::full_pivot_solve(maa, qa, &invertible);
      if (!invertible) {
        singular = singular || (maa * la - qa).norm() <= 1e-9 * std::max(1.0, qa.norm());
        continue;
      }
      for (int i = 0; i < k; ++i) lambda[a[i]] = la[i];
    }
    const Eigen::VectorXd w = q + m * lambda;
    bool ok = true;
    for (int i = 0; i < n; ++i)
      ok = ok && lambda[i] >= -tol && w[i] >= -tol && !(lambda[i] > tol && w[i] > tol);
    if (ok) return LcpResult::Outcome::solved;
  }
  return singular ? LcpResult::Outcome::undecided : LcpResult::Outcome::no_solution;
}

TEST(Complementarity, EnumerationAgreesWithAFullPivotReference) {
  // Small integer LCPs: many principal blocks exactly singular, which the enumeration's partial-
  // pivot LU must hand to the full-pivot one. Every outcome as the reference's.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> entry(-3, 3);
  int counted[3] = {0, 0, 0};
  for (int trial = 0; trial < 3000; ++trial) {
    const int n = 2 + trial % 4;
    Eigen::MatrixXd m(n, n);
    Eigen::VectorXd q(n);
    for (int i = 0; i < n; ++i) {
      q[i] = entry(rng);
      for (int j = 0; j < n; ++j) m(i, j) = entry(rng);
    }
    const LcpResult r = solve_lcp(m, q);
    const LcpResult::Outcome expected = enumerated_outcome(m, q, 1e-10);
    ASSERT_EQ(r.outcome, expected) << "trial " << trial << " (" << r.how << ")\n"
                                   << m << "\nq " << q.transpose();
    if (r.outcome == LcpResult::Outcome::solved) expect_solution(m, q, r);
    ++counted[static_cast<int>(r.outcome)];
  }
  // All three outcomes occur (the singular case: "lemke ray, singular principal blocks").
  for (int c : counted) EXPECT_GT(c, 0);
}

}  // namespace
}  // namespace granstab::statics
