// The wide LCP of a status cycle solved by active sets on its sparse system (lcp_by_active_sets,
// static/load_step_parts.hpp), against solve_lcp on the matrix M = K_T I - V S^-1 W formed
// densely: the same unknowns, whichever support the iteration starts from.
#include <gtest/gtest.h>

#include <optional>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include "dense_reference.hpp"
#include "static/complementarity.hpp"
#include "static/load_step_parts.hpp"

namespace granstab::statics {
namespace {

using RowMajor = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

// A system whose M = K_T I + W^T S^-1 W (V = -W^T, S symmetric positive definite) is positive
// definite, so that its LCP has one solution: nk dofs on a chain, n contacts of three dofs each.
struct System {
  SparseMatrix s, w;
  RowMajor v;
  Eigen::VectorXd g, b, q;
  double q_scale = 1.0, k_t = 0.5;
  Eigen::MatrixXd m;  // M / K_T, solve_lcp's matrix

  System(int nk, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> dof(0, nk - 3);
    std::vector<Eigen::Triplet<double>> ts, tw;
    for (int i = 0; i < nk; ++i) {
      ts.emplace_back(i, i, 4.0);
      if (i + 1 < nk) {
        ts.emplace_back(i, i + 1, -1.0);
        ts.emplace_back(i + 1, i, -1.0);
      }
    }
    for (int a = 0; a < n; ++a) {
      const int d = dof(rng);
      for (int l = 0; l < 3; ++l) tw.emplace_back(d + l, a, u(rng));
      // The contact's block w_a w_a^T lies in S's pattern, as a contact's does in the tangent's.
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) ts.emplace_back(d + i, d + j, 0.0);
    }
    s.resize(nk, nk);
    s.setFromTriplets(ts.begin(), ts.end());
    w.resize(nk, n);
    w.setFromTriplets(tw.begin(), tw.end());
    v = RowMajor(-SparseMatrix(w.transpose()));
    g = Eigen::VectorXd::Zero(n);
    for (int a = 0; a < n; a += 2) g[a] = 0.2 * (1.0 + u(rng));  // off the cone: g > 0
    b = Eigen::VectorXd::NullaryExpr(nk, [&] { return u(rng); });
    const Eigen::MatrixXd s_inverse = dense_reference::inverse(Eigen::MatrixXd(s));
    q = g + v * (s_inverse * b);
    q_scale = q.cwiseAbs().maxCoeff();
    m = -dense_reference::product(dense_reference::product(Eigen::MatrixXd(v), s_inverse),
                                  Eigen::MatrixXd(w));
    m.diagonal().array() += k_t;
    m /= k_t;
  }
  LcpSystem view() const { return {s, w, v, g, b, q, q_scale, k_t}; }
};

void expect_same(const LcpResult& a, const LcpResult& b) {
  ASSERT_EQ(a.outcome, LcpResult::Outcome::solved);
  ASSERT_EQ(b.outcome, LcpResult::Outcome::solved);
  EXPECT_LT((a.lambda - b.lambda).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((a.w - b.w).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(LcpByActiveSets, GivesTheMatrixRoutesSolutionFromAnySupport) {
  const double tol = 1e-10;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const System sys(60, 20, seed);
    const LcpResult reference = solve_lcp(sys.m, sys.q / sys.q_scale, tol);
    ASSERT_EQ(reference.outcome, LcpResult::Outcome::solved) << "seed " << seed;
    std::vector<char> right(20, 0);
    int support = 0;
    for (int a = 0; a < 20; ++a) support += right[a] = reference.lambda[a] > tol;
    ASSERT_GT(support, 0) << "seed " << seed << ": not the case under test";
    ASSERT_LT(support, 20) << "seed " << seed << ": not the case under test";
    const LuReuse reuse;
    // The right support at once; every contact sliding; none.
    const std::optional<LcpResult> at_once =
        lcp_by_active_sets(sys.view(), right, tol, 1, reuse, nullptr);
    ASSERT_TRUE(at_once) << "seed " << seed;
    EXPECT_EQ(at_once->how, "support guessed");
    expect_same(*at_once, reference);
    for (const char start : {1, 0}) {
      const std::optional<LcpResult> moved =
          lcp_by_active_sets(sys.view(), std::vector<char>(20, start), tol, 40, reuse, nullptr);
      ASSERT_TRUE(moved) << "seed " << seed << ", start " << int(start);
      expect_same(*moved, reference);
    }
    // A wrong support with no room to move: the caller forms M.
    std::vector<char> wrong = right;
    for (int a = 0; a < 20; ++a)
      if (right[a]) {
        wrong[a] = 0;
        break;
      }
    EXPECT_FALSE(lcp_by_active_sets(sys.view(), wrong, tol, 1, reuse, nullptr)) << seed;
  }
}

TEST(LcpByActiveSets, NothingSlidesWhereQIsNonNegative) {
  System sys(30, 8, 3);
  sys.g = Eigen::VectorXd::Constant(8, 0.5);
  sys.b.setZero();
  sys.q = sys.g;
  sys.q_scale = 0.5;
  const std::optional<LcpResult> r =
      lcp_by_active_sets(sys.view(), std::vector<char>(8, 1), 1e-10, 1, LuReuse(), nullptr);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->how, "trivial");
  EXPECT_EQ(r->lambda, Eigen::VectorXd::Zero(8));
}

}  // namespace
}  // namespace granstab::statics
