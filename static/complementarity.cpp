#include "static/complementarity.hpp"

#include <Eigen/LU>
#include <cmath>
#include <vector>

namespace granstab::statics {
namespace {

bool satisfies(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, const Eigen::VectorXd& lambda,
               double tol, Eigen::VectorXd& w) {
  w.noalias() = m * lambda;  // then + q: the same sums as q + M lambda, without a temporary
  w += q;
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    if (lambda[i] < -tol || w[i] < -tol) return false;
    if (lambda[i] > tol && w[i] > tol) return false;
  }
  return true;
}

// Lemke's method on the tableau [I | -M | -e | q] (variables w, z, z0). Returns
// true with lambda when z0 leaves the basis; false on a secondary ray or the
// iteration cap.
bool lemke(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, Eigen::VectorXd& lambda) {
  const int n = static_cast<int>(q.size());
  const int z0 = 2 * n, rhs = 2 * n + 1;
  // Row-major: a pivot subtracts multiples of one row from the others, each row then a contiguous
  // stream (column-major, every term was a strided load: Lemke over 579 contacts of series B took
  // 0.66-0.86 s, now 0.15 s). The same operations on every entry, so the same bits.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> t =
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>::Zero(n, 2 * n + 2);
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
  int entering = n + r0;  // complement of w_r0, which z0 replaces
  pivot(r0, z0);
  const double tiny = 1e-12 * std::max(1.0, t.leftCols(2 * n + 1).cwiseAbs().maxCoeff());
  for (int it = 0; it < 50 * n + 100; ++it) {
    int r = -1;
    double best = 0.0;
    for (int i = 0; i < n; ++i) {
      if (t(i, entering) <= tiny) continue;
      const double ratio = t(i, rhs) / t(i, entering);
      // Ties (degenerate bases): z0 leaves first (termination), else the
      // smallest index.
      const bool tie = r >= 0 && std::abs(ratio - best) <= 1e-12 * std::max(1.0, std::abs(best));
      if (r < 0 || (!tie && ratio < best) || (tie && basis[i] == z0)) {
        r = i;
        best = ratio;
      }
    }
    if (r < 0) return false;  // secondary ray
    const int left = pivot(r, entering);
    if (left == z0) {
      lambda = Eigen::VectorXd::Zero(n);
      for (int i = 0; i < n; ++i)
        if (basis[i] >= n && basis[i] < 2 * n) lambda[basis[i] - n] = std::max(0.0, t(i, rhs));
      return true;
    }
    entering = left < n ? left + n : left - n;
  }
  return false;
}

}  // namespace

LcpResult solve_lcp(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, double tol,
                    int max_enumerated) {
  LcpResult result;
  const int n = static_cast<int>(q.size());
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(n), w;
  if (satisfies(m, q, lambda, tol, w)) {
    result.outcome = LcpResult::Outcome::solved;
    result.lambda = lambda;
    result.w = w;
    result.how = "trivial";
    return result;
  }
  if (lemke(m, q, lambda) && satisfies(m, q, lambda, tol, w)) {
    result.outcome = LcpResult::Outcome::solved;
    result.lambda = lambda;
    result.w = w;
    result.how = "lemke";
    return result;
  }
  if (n > max_enumerated) {
    result.how = "lemke ray, too many unknowns to enumerate (" + std::to_string(n) + ")";
    return result;
  }
  // Every solution has a support alpha with M_aa lambda_a = -q_a: enumerate them all. The blocks
  // and decompositions of each size are kept from one support to the next (allocated per support,
  // an enumeration of 2^15 supports took 0.67 instead of 0.48 us per support).
  std::vector<Eigen::MatrixXd> blocks(n + 1);
  std::vector<Eigen::VectorXd> rhs(n + 1), solution(n + 1);
  std::vector<Eigen::PartialPivLU<Eigen::MatrixXd>> quick(n + 1);
  std::vector<Eigen::FullPivLU<Eigen::MatrixXd>> lus(n + 1);
  for (int k = 1; k <= n; ++k) {
    blocks[k].resize(k, k);
    rhs[k].resize(k);
    solution[k].resize(k);
    quick[k] = Eigen::PartialPivLU<Eigen::MatrixXd>(k);
    lus[k] = Eigen::FullPivLU<Eigen::MatrixXd>(k, k);
  }
  std::vector<int> alpha;
  alpha.reserve(n);
  bool singular = false;
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    alpha.clear();
    for (int i = 0; i < n; ++i)
      if (mask & (1u << i)) alpha.push_back(i);
    const int k = static_cast<int>(alpha.size());
    Eigen::MatrixXd& maa = blocks[k];
    Eigen::VectorXd& qa = rhs[k];
    Eigen::VectorXd& la = solution[k];
    for (int a = 0; a < k; ++a) {
      qa[a] = -q[alpha[a]];
      for (int b = 0; b < k; ++b) maa(a, b) = m(alpha[a], alpha[b]);
    }
    // Partial pivoting first (2^15 supports: 18 -> 12 ms): with its pivots within 1e-6 of each
    // other the block is far from singular and both LUs give lambda to round-off, well inside tol.
    // Near a singular block only the full-pivot LU tells its rank (test EnumerationAgrees...).
    Eigen::PartialPivLU<Eigen::MatrixXd>& pp = quick[k];
    pp.compute(maa);
    const auto pivots = pp.matrixLU().diagonal().cwiseAbs();
    if (pivots.minCoeff() > 1e-6 * pivots.maxCoeff()) {
      la = pp.solve(qa);
    } else {
      Eigen::FullPivLU<Eigen::MatrixXd>& lu = lus[k];
      lu.compute(maa);
      la = lu.solve(qa);
      if (!lu.isInvertible()) {
        // A continuum of candidates on this support: a particular one failing
        // proves nothing.
        if ((maa * la - qa).norm() <= 1e-9 * std::max(1.0, qa.norm())) singular = true;
        continue;
      }
    }
    // A negative component fails satisfies() below: skip its product with M.
    if ((la.array() < -tol).any()) continue;
    lambda.setZero();
    for (int a = 0; a < k; ++a) lambda[alpha[a]] = la[a];
    if (satisfies(m, q, lambda, tol, w)) {
      result.outcome = LcpResult::Outcome::solved;
      result.lambda = lambda.cwiseMax(0.0);
      result.w = w;
      result.how = "enumeration";
      return result;
    }
  }
  if (singular) {
    result.how = "lemke ray, singular principal blocks";
    return result;
  }
  result.outcome = LcpResult::Outcome::no_solution;
  result.how = "enumeration of " + std::to_string((1u << n)) + " bases";
  return result;
}

}  // namespace granstab::statics
