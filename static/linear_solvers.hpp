#pragma once
// The two factorisations of the static solver, behind one small interface each so that no
// SuiteSparse header leaks out of static/ (DEPS.md #9):
// - CHOLMOD supernodal LL^T for symmetric positive definite systems (a failed factorisation
//   is the test of positive definiteness; DEPS.md #1-#3);
// - UMFPACK LU for the full unsymmetric operator with sliding contacts, with the sign of its
//   determinant (STATIC.md §S3.1 first route, §S3.4 (b)).
#include <memory>

#include <Eigen/Core>

#include "static/tangent.hpp"

namespace granstab::statics {

class SymmetricFactor {
 public:
  SymmetricFactor();
  ~SymmetricFactor();
  SymmetricFactor(const SymmetricFactor&) = delete;
  SymmetricFactor& operator=(const SymmetricFactor&) = delete;

  // Factorises the symmetric matrix (its lower triangle is read). Returns false when it is not
  // positive definite (CHOLMOD_NOT_POSDEF, checked right after the factorisation).
  bool factorize(const SparseMatrix& k);
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class LuFactor {
 public:
  LuFactor();
  ~LuFactor();
  LuFactor(const LuFactor&) = delete;
  LuFactor& operator=(const LuFactor&) = delete;

  // Returns false when UMFPACK finds the matrix singular (or fails). The symbolic analysis
  // (ordering) of a recent factorisation in this thread is reused when k has exactly the same
  // sparsity pattern; only the numeric factorisation is then redone.
  bool factorize(const SparseMatrix& k);
  // Whether the last factorize reused a cached symbolic analysis.
  bool symbolic_reused() const { return symbolic_reused_; }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  Eigen::VectorXd solve_transpose(const Eigen::VectorXd& b) const;
  // Sign of det K (+1, -1; 0 when singular) and log10 |det K|.
  int determinant_sign() const { return det_sign_; }
  double log10_abs_determinant() const { return log10_det_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int det_sign_ = 0;
  double log10_det_ = 0.0;
  bool symbolic_reused_ = false;
};

// The submatrix on the kept indices (keep[i] != 0), in order, and the maps between the two.
struct Reduction {
  std::vector<int> full_to_reduced;  // -1 for an eliminated index
  std::vector<int> reduced_to_full;
};
Reduction make_reduction(const std::vector<char>& keep);
SparseMatrix reduce(const SparseMatrix& k, const Reduction& r);
Eigen::VectorXd reduce(const Eigen::VectorXd& v, const Reduction& r);
Eigen::VectorXd expand(const Eigen::VectorXd& v, const Reduction& r, int full_size);

}  // namespace granstab::statics
