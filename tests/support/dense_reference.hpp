#pragma once
// Dense reference answers for the tests of the sparse solvers: Eigen's dense decompositions,
// compiled once here. Each test that instantiated them itself spent 10-25 s of CPU compiling them
// (twice that under ASan), the heaviest test sources of CI (docs/reliability.md, "CI time").
#include <Eigen/Core>

namespace granstab::dense_reference {

// x with a x = b, by LU with partial pivoting.
Eigen::VectorXd lu_solve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);
// x with a x = b, by LU with full pivoting; *invertible (when given) says whether a has full
// rank (for a singular a, x solves a x = b only where b is in its range).
Eigen::VectorXd full_pivot_solve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                                 bool* invertible = nullptr);
double determinant(const Eigen::MatrixXd& a);
Eigen::MatrixXd inverse(const Eigen::MatrixXd& a);
// a b (a general matrix product).
Eigen::MatrixXd product(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);
// The eigenvalues of a symmetric a, ascending.
Eigen::VectorXd symmetric_eigenvalues(const Eigen::MatrixXd& a);

}  // namespace granstab::dense_reference
