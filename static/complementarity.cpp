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

// row -= f * b, entry by entry: a multiply, then a subtraction (this file is compiled with
// -ffp-contract=off, so no clone fuses them), hence the same bits at every vector width.
[[gnu::target_clones("avx512f", "avx2", "default")]] void subtract_multiple(
    double* __restrict row, double f, const double* __restrict b, int width) {
  for (int j = 0; j < width; ++j) row[j] -= f * b[j];
}

// Lemke's tableau [I | -M | -e | q] with its pivots applied in batches, and kept over the
// nonbasic variables only. Variables: w_i = i, z_j = n + j, z0 = 2n, and q as 2n + 1. A pivot on
// (r, c) divides row r by t(r, c) and subtracts t(i, c) times that row from every other row i
// with t(i, c) != 0. A basic variable's column is a unit vector that nothing reads, so the
// tableau holds the n + 1 nonbasic columns and q (half the width of the whole one): after a
// pivot, column c is the leaving variable's, computed as the whole tableau computes its unit
// column (1 / t(r, c) in row r, 0 - t(i, c) (1 / t(r, c)) elsewhere). Applied at once, each pivot
// swept the whole tableau (62 MB at 1964 contacts, N = 5600); here a pivot records its
// normalised row and its column of factors, and the rows take the pending pivots `batch` at a
// time, each row held in L1 meanwhile (series B's LCPs 2.7 -> 1.3 s with the AVX clones, N =
// 5600's 49 -> 27 s). Every entry undergoes the same operations in the same order as with one
// pivot at a time over the whole tableau, so the same bits; entries read between two batches
// (the ratio test's columns, the pivot row) take the pending pivots on the fly.
class LemkeTableau {
 public:
  static constexpr int batch = 16;
  LemkeTableau(const Eigen::MatrixXd& m, const Eigen::VectorXd& q)
      : n_(static_cast<int>(q.size())),
        width_(n_ + 2),
        t_(n_, width_),
        b_(batch, width_),
        a_(n_, batch),
        rows_(batch),
        cols_(batch),
        where_(2 * n_ + 2, -1) {
    t_.leftCols(n_) = -m;
    t_.col(n_).setConstant(-1.0);
    t_.col(n_ + 1) = q;
    for (int j = 0; j <= n_ + 1; ++j) where_[n_ + j] = j;  // z_j, z0, q
  }
  // Entry (i, variable v's column) with the pending pivots applied; v nonbasic or q.
  double at(int i, int v) const {
    const int j = where_[v];
    double x = t_(i, j);
    for (int k = 0; k < count_; ++k) {
      if (i == rows_[k]) {
        x = b_(k, j);
      } else if (a_(i, k) != 0.0) {
        x = (j == cols_[k] ? 0.0 : x) - a_(i, k) * b_(k, j);
      }
    }
    return x;
  }
  void column(int v, Eigen::VectorXd& out) const {
    out.resize(n_);
    for (int i = 0; i < n_; ++i) out[i] = at(i, v);
  }
  // Pivot on (r, entering): `leaving` (basic in row r) leaves; column_c: the entering
  // variable's column as at() gives it.
  void pivot(int r, int entering, int leaving, const Eigen::VectorXd& column_c) {
    if (count_ == batch) flush();
    const int c = where_[entering];
    double* row = &b_(count_, 0);
    for (int j = 0; j < width_; ++j) row[j] = t_(r, j);
    apply_pending(r, row);
    const double p = row[c];
    for (int j = 0; j < width_; ++j) row[j] /= p;
    row[c] = 1.0 / p;  // the leaving variable's unit column, divided as the row is
    for (int i = 0; i < n_; ++i) a_(i, count_) = i == r ? 0.0 : column_c[i];
    rows_[count_] = r;
    cols_[count_++] = c;
    where_[leaving] = c;
    where_[entering] = -1;
  }
  void flush() {
    for (int i = 0; i < n_; ++i) apply_pending(i, &t_(i, 0));
    count_ = 0;
  }
  // The largest |entry| of the whole tableau but q (its unit columns give 1).
  double max_abs_except_rhs() {
    flush();
    return std::max(1.0, t_.leftCols(width_ - 1).cwiseAbs().maxCoeff());
  }

 private:
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  void apply_pending(int i, double* __restrict row) const {
    for (int k = 0; k < count_; ++k) {
      const double* __restrict bk = &b_(k, 0);
      if (i == rows_[k]) {
        for (int j = 0; j < width_; ++j) row[j] = bk[j];
      } else if (const double f = a_(i, k); f != 0.0) {
        row[cols_[k]] = 0.0;  // the leaving variable's unit column: 0 off row r
        subtract_multiple(row, f, bk, width_);
      }
    }
  }
  int n_, width_;
  Rows t_;
  Rows b_;             // the pending pivots' normalised rows
  Eigen::MatrixXd a_;  // and their factors t(i, c) (0 in the pivot row)
  std::vector<int> rows_, cols_;
  std::vector<int> where_;  // a variable's column, -1 while basic
  int count_ = 0;
};

// M_aa and -q_a of the support a (maa, qa sized |a|).
void principal_block(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, const std::vector<int>& a,
                     Eigen::MatrixXd& maa, Eigen::VectorXd& qa) {
  const int k = static_cast<int>(a.size());
  for (int c = 0; c < k; ++c) {
    qa[c] = -q[a[c]];
    for (int r = 0; r < k; ++r) maa(r, c) = m(a[r], a[c]);
  }
}

// lambda with M_aa lambda_a = -q_a on the support a and 0 elsewhere; false where M_aa is
// singular to the partial-pivot LU's eye.
bool on_support(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, const std::vector<int>& a,
                Eigen::VectorXd& lambda) {
  const int k = static_cast<int>(a.size());
  lambda.setZero();
  if (k == 0) return true;
  Eigen::MatrixXd maa(k, k);
  Eigen::VectorXd qa(k);
  principal_block(m, q, a, maa, qa);
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(maa);
  const auto pivots = lu.matrixLU().diagonal().cwiseAbs();
  if (!(pivots.minCoeff() > 1e-12 * pivots.maxCoeff())) return false;
  const Eigen::VectorXd la = lu.solve(qa);
  for (int c = 0; c < k; ++c) lambda[a[c]] = la[c];
  return true;
}

// Lemke's method on the tableau [I | -M | -e | q] (variables w, z, z0). Returns
// true with lambda when z0 leaves the basis; false on a secondary ray or the
// iteration cap.
bool lemke(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, Eigen::VectorXd& lambda) {
  const int n = static_cast<int>(q.size());
  const int z0 = 2 * n, rhs = 2 * n + 1;
  LemkeTableau t(m, q);
  std::vector<int> basis(n);
  for (int i = 0; i < n; ++i) basis[i] = i;
  Eigen::VectorXd entering_column, rhs_column;
  const auto pivot = [&](int r, int c) {
    const int left = basis[r];
    t.pivot(r, c, left, entering_column);
    basis[r] = c;
    return left;
  };
  int r0 = 0;
  for (int i = 1; i < n; ++i)
    if (q[i] < q[r0]) r0 = i;
  int entering = n + r0;  // complement of w_r0, which z0 replaces
  t.column(z0, entering_column);
  pivot(r0, z0);
  const double tiny = 1e-12 * t.max_abs_except_rhs();
  for (int it = 0; it < 50 * n + 100; ++it) {
    t.column(entering, entering_column);
    t.column(rhs, rhs_column);
    int r = -1;
    double best = 0.0;
    for (int i = 0; i < n; ++i) {
      if (entering_column[i] <= tiny) continue;
      const double ratio = rhs_column[i] / entering_column[i];
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
        if (basis[i] >= n && basis[i] < 2 * n) lambda[basis[i] - n] = std::max(0.0, t.at(i, rhs));
      return true;
    }
    entering = left < n ? left + n : left - n;
  }
  return false;
}

}  // namespace

LcpResult solve_lcp(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, double tol,
                    int max_enumerated, const std::vector<int>* support_guess) {
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
  if (support_guess && on_support(m, q, *support_guess, lambda) &&
      satisfies(m, q, lambda, tol, w)) {
    result.outcome = LcpResult::Outcome::solved;
    result.lambda = lambda.cwiseMax(0.0);
    result.w = w;
    result.how = "warm start";
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
    principal_block(m, q, alpha, maa, qa);
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
