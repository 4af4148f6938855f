// GMRES preconditioned by a nearby matrix's exact operator (LuReuse::krylov): the solves of a
// status iteration whose matrix differs from a recent factorisation or update in a few contacts.
#include <cmath>

#include "static/numeric_lu.hpp"

namespace granstab::statics {

// The contract is in numeric_lu.hpp.
bool gmres(const SparseMatrix& k,
           const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& precondition,
           const Eigen::VectorXd& b, bool transposed, double tolerance, int max_iterations,
           Eigen::VectorXd& x, int& iterations) {
  const auto apply = [&](const SparseMatrix& a, const Eigen::VectorXd& v) {
    return transposed ? Eigen::VectorXd(a.transpose() * v) : Eigen::VectorXd(a * v);
  };
  const Eigen::Index n = b.size();
  x = precondition(b);
  iterations = 1;
  Eigen::MatrixXd v(n, max_iterations + 1);
  Eigen::MatrixXd h(max_iterations + 1, max_iterations);
  Eigen::VectorXd g(max_iterations + 1), cs(max_iterations), sn(max_iterations);
  while (true) {
    const Eigen::VectorXd r = b - apply(k, x);
    const double target = tolerance * (abs_product(k, x, transposed) + b.cwiseAbs()).norm();
    const double beta = r.norm();
    if (beta <= target) return true;
    const int cycle = max_iterations - iterations;
    if (cycle < 2) return false;
    h.setZero();
    g.setZero();
    v.col(0) = r / beta;
    g[0] = beta;
    int j = 0;
    for (; j < cycle - 1; ++j) {
      Eigen::VectorXd w = apply(k, precondition(v.col(j)));
      ++iterations;
      // Classical Gram-Schmidt, twice: as stable as the modified one, in matrix-vector products.
      for (int pass = 0; pass < 2; ++pass) {
        const Eigen::VectorXd c = v.leftCols(j + 1).transpose() * w;
        w -= v.leftCols(j + 1) * c;
        h.col(j).head(j + 1) += c;
      }
      const double next = w.norm();
      if (next > 0.0) v.col(j + 1) = w / next;
      h(j + 1, j) = next;
      for (int i = 0; i < j; ++i) {  // the earlier Givens rotations
        const double t = cs[i] * h(i, j) + sn[i] * h(i + 1, j);
        h(i + 1, j) = -sn[i] * h(i, j) + cs[i] * h(i + 1, j);
        h(i, j) = t;
      }
      const double rho = std::hypot(h(j, j), h(j + 1, j));
      if (rho == 0.0) return false;  // K M^-1 singular on the Krylov space
      cs[j] = h(j, j) / rho;
      sn[j] = h(j + 1, j) / rho;
      h(j, j) = rho;
      h(j + 1, j) = 0.0;
      g[j + 1] = -sn[j] * g[j];
      g[j] = cs[j] * g[j];
      if (std::abs(g[j + 1]) <= 0.5 * target || next == 0.0) {
        ++j;
        break;
      }
      // Give up early when the mean rate so far would take more than twice the bound: the
      // iterations left would be wasted on a factorisation anyway.
      if (j >= 5) {
        const double rate = std::log(std::abs(g[j + 1]) / beta) / (j + 1);
        if (rate >= 0.0 || std::log(0.5 * target / beta) / rate > 2.0 * max_iterations)
          return false;
      }
    }
    if (j == cycle - 1 && std::abs(g[j]) > 0.5 * target) return false;
    const Eigen::VectorXd y = h.topLeftCorner(j, j).triangularView<Eigen::Upper>().solve(g.head(j));
    x += precondition(v.leftCols(j) * y);
    ++iterations;
  }
}

}  // namespace granstab::statics
