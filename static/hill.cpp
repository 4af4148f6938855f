#include "static/hill.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

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

namespace {

HillResult dense_hill(const SparseMatrix& s) {
  HillResult h;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig{Eigen::MatrixXd(s)};
  if (eig.info() != Eigen::Success) return h;
  h.ok = true;
  h.min_eigenvalue = eig.eigenvalues()[0];
  h.mode = eig.eigenvectors().col(0);
  return h;
}

}  // namespace

HillResult hill_indicator(const SparseMatrix& k, const HillResult* previous) {
  HillResult h;
  const int n = static_cast<int>(k.rows());
  if (n == 0) return h;
  SparseMatrix s = symmetric_part(k);
  if (n <= 40) return dense_hill(s);  // a Lanczos basis would be the whole space
  double scale = 0.0;
  for (int i = 0; i < n; ++i) scale = std::max(scale, std::abs(s.coeff(i, i)));
  ShiftSolve op(s);
  double sigma = 0.0;
  bool below = false;
  const bool warm = previous && previous->ok && previous->mode.size() == n;
  if (warm) {
    // Just below the previous eigenvalue: the nearest eigenvalue to the shift is then the
    // smallest, and close to it, so shift-invert converges in a few iterations.
    const double lambda = previous->min_eigenvalue;
    for (double f = 1e-3; f <= 10.0 && !below; f *= 10.0) {
      sigma = lambda - f * std::max(std::abs(lambda), 1e-8 * scale);
      below = op.factorize(sigma);
    }
  }
  for (double f = 1e-10; f <= 10.0 && !below; f *= 100.0) {
    sigma = -f * scale;
    below = op.factorize(sigma);
  }
  if (!below) return n <= 2000 ? dense_hill(s) : h;
  // A warm start vector is nearly the eigenvector: a short basis suffices.
  Spectra::SymEigsShiftSolver<ShiftSolve> eigs(op, 1, std::min(n, warm ? 6 : 20), sigma);
  if (!op.ok()) return h;
  if (warm) {
    // The previous mode plus a fixed spread over every dof: started from an exact eigenvector
    // the Krylov space would be invariant (a Lanczos breakdown).
    Eigen::VectorXd start = previous->mode;
    for (int i = 0; i < n; ++i) start[i] += 1e-2 * std::sin(1.0 + 7.0 * i) / std::sqrt(double(n));
    eigs.init(start.data());
  } else {
    eigs.init();
  }
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10);
  if (eigs.info() != Spectra::CompInfo::Successful) return n <= 2000 ? dense_hill(s) : h;
  h.ok = true;
  h.min_eigenvalue = eigs.eigenvalues()[0];
  h.mode = eigs.eigenvectors().col(0);
  return h;
}

}  // namespace granstab::statics
