#include "dense_reference.hpp"

#include <Eigen/Dense>

namespace granstab::dense_reference {

Eigen::VectorXd lu_solve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b) {
  return a.partialPivLu().solve(b);
}

Eigen::VectorXd full_pivot_solve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                 bool* invertible) {
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  if (invertible) *invertible = lu.isInvertible();
  return lu.solve(b);
}

double determinant(const Eigen::MatrixXd& a) { return a.partialPivLu().determinant(); }

Eigen::MatrixXd inverse(const Eigen::MatrixXd& a) { return a.partialPivLu().inverse(); }

Eigen::MatrixXd product(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return a * b; }

Eigen::VectorXd symmetric_eigenvalues(const Eigen::MatrixXd& a) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(a, Eigen::EigenvaluesOnly).eigenvalues();
}

}  // namespace granstab::dense_reference
