#pragma once
// Small dense linear complementarity problems (STATIC.md §S3.1, second route):
// find lambda with
//   w = q + M lambda >= 0,  lambda >= 0,  lambda^T w = 0,
// or prove that none exists. Used when the status iteration of the predictor
// cycles: the rate problem over the contacts whose status it could not settle
// is such an LCP on the Schur complement of the tangent (docs/static.md,
// "Existence of a consistent status set").
#include <string>
#include <vector>

#include <Eigen/Core>

namespace granstab::statics {

struct LcpResult {
  enum class Outcome {
    solved,       // lambda, w satisfy the conditions to the tolerance
    no_solution,  // proved: no principal basis gives a solution (complete
                  // enumeration)
    undecided,    // neither (too many unknowns to enumerate, or singular principal
                  // blocks)
  };
  Outcome outcome = Outcome::undecided;
  Eigen::VectorXd lambda, w;
  std::string how;  // "lemke", "enumeration", or why it is undecided
};

// Lemke's complementary pivoting (covering vector 1, lexicographic-free
// minimum-ratio test with ties broken by the smallest index); on a secondary
// ray, which proves nothing for a general M, every principal basis is
// enumerated when n <= max_enumerated (2^n small dense solves). tol is the
// absolute tolerance on lambda and w (the caller scales the problem to O(1)
// entries). support_guess (optional): the indices of a likely support of lambda; where
// M_aa lambda_a = -q_a on it gives a solution, that is the answer ("warm start": one dense LU
// instead of Lemke's pivots), else Lemke runs as without it.
LcpResult solve_lcp(const Eigen::MatrixXd& m, const Eigen::VectorXd& q, double tol = 1e-10,
                    int max_enumerated = 16, const std::vector<int>* support_guess = nullptr);

}  // namespace granstab::statics
