#include "static/hill.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Spectra/SymEigsShiftSolver.h>

#include "static/linear_solvers.hpp"

// The negative-eigenvalue count of §S3.4 (b) is in negative_eigenvalues.cpp (its own translation
// unit: the two Spectra solvers compile in parallel).

namespace granstab::statics {
namespace {

// Spectra's shift-solve operator: y = (S - sigma I)^-1 x with the CHOLMOD factor.
class ShiftSolve {
 public:
  using Scalar = double;
  explicit ShiftSolve(const SparseMatrix& s) : s_(s) {}
  Eigen::Index rows() const { return s_.rows(); }
  Eigen::Index cols() const { return s_.cols(); }
  void set_shift(const Scalar& sigma) { ok_ = factorize(sigma); }
  void perform_op(const Scalar* x_in, Scalar* y_out) const {
    Eigen::Map<const Eigen::VectorXd> x(x_in, s_.rows());
    Eigen::Map<Eigen::VectorXd>(y_out, s_.rows()) = factor_.solve(x);
  }
  bool factorize(double sigma) {
    SparseMatrix shifted = s_;
    for (int i = 0; i < shifted.rows(); ++i) shifted.coeffRef(i, i) -= sigma;
    return factor_.factorize(shifted);
  }
  bool ok() const { return ok_; }

 private:
  const SparseMatrix& s_;
  SymmetricFactor factor_;
  bool ok_ = false;
};

}  // namespace

HillResult hill_indicator(const SparseMatrix& k) {
  HillResult h;
  const int n = static_cast<int>(k.rows());
  if (n == 0) return h;
  SparseMatrix s = 0.5 * (k + SparseMatrix(k.transpose()));
  if (n <= 400) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig{Eigen::MatrixXd(s)};
    if (eig.info() != Eigen::Success) return h;
    h.ok = true;
    h.min_eigenvalue = eig.eigenvalues()[0];
    h.mode = eig.eigenvectors().col(0);
    return h;
  }
  double scale = 0.0;
  for (int i = 0; i < n; ++i) scale = std::max(scale, std::abs(s.coeff(i, i)));
  ShiftSolve op(s);
  double sigma = 0.0;
  bool below = false;
  for (double f = 1e-10; f <= 10.0 && !below; f *= 100.0) {
    sigma = -f * scale;
    below = op.factorize(sigma);
  }
  if (!below) return h;
  Spectra::SymEigsShiftSolver<ShiftSolve> eigs(op, 1, std::min(n, 20), sigma);
  if (!op.ok()) return h;
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10);
  if (eigs.info() != Spectra::CompInfo::Successful) return h;
  h.ok = true;
  h.min_eigenvalue = eigs.eigenvalues()[0];
  h.mode = eigs.eigenvectors().col(0);
  return h;
}

}  // namespace granstab::statics
