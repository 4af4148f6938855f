#pragma once
// The two factorisations of the static solver, behind one small interface each so that no
// SuiteSparse header leaks out of static/ (DEPS.md #9):
// - CHOLMOD supernodal LL^T for symmetric positive definite systems (a failed factorisation
//   is the test of positive definiteness; DEPS.md #1-#3);
// - UMFPACK LU for the full unsymmetric operator with sliding contacts, with the sign of its
//   determinant (STATIC.md §S3.1 first route, §S3.4 (b)).
#include <memory>
#include <vector>

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
  // positive definite (CHOLMOD_NOT_POSDEF, checked right after the factorisation). The symbolic
  // analysis of the previous call is reused when k has exactly the same sparsity pattern (the
  // same ordering and supernodes, hence the same factor).
  bool factorize(const SparseMatrix& k);
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  // S^-1 B for several right-hand sides at once (blocked triangular solves).
  Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& b) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// How LuFactor may avoid a numeric factorisation (off by default: the results then differ from a
// fresh LU in round-off, which moves q1 today, docs/static.md "Performance").
struct LuReuse {
  // A matrix that differs from a recent full factorisation K0 of this thread in a few columns
  // (status changes of a few contacts inside a complementarity loop) is written K = K0 + U V^T
  // (rank-revealing QR of the changed block) and solved by the Woodbury formula with K0's factor,
  // plus one step of iterative refinement against K; det K = det K0 det(I + V^T K0^-1 U), so the
  // determinant sign stays exact.
  bool low_rank = false;
  int max_columns = 96;  // changed columns beyond which K is factorised afresh
  int max_rank = 40;     // rank of U V^T beyond which K is factorised afresh (r solves with K0)
};
// The reuse of a default-constructed LuFactor in this thread.
LuReuse& default_lu_reuse();

// Counters of this thread's LuFactor work (bench/static).
struct LuStatistics {
  long numeric = 0;           // full numeric factorisations
  long symbolic = 0;          // symbolic analyses among them
  long low_rank = 0;          // factorisations replaced by a low-rank update
  long rank_sum = 0;          // sum of the ranks of those updates
  long too_many = 0;          // updates refused (too many changed columns or too high a rank)
  long solves = 0;            // solves with UMFPACK's iterative refinement (solve, solve_transpose)
  long unrefined_solves = 0;  // solves without it (solve_unrefined, low-rank updates' inner ones)
  double solve_seconds = 0.0;     // thread CPU seconds of the refined UMFPACK solves
  double symbolic_seconds = 0.0;  // thread CPU seconds of the symbolic analyses
  double numeric_seconds = 0.0;   // thread CPU seconds of the numeric factorisations
};
LuStatistics& lu_statistics();

class LuFactor {
 public:
  LuFactor();
  explicit LuFactor(const LuReuse& reuse);
  ~LuFactor();
  LuFactor(const LuFactor&) = delete;
  LuFactor& operator=(const LuFactor&) = delete;

  // Returns false when UMFPACK finds the matrix singular (or fails). The symbolic analysis
  // (ordering) of a recent factorisation in this thread is reused when k has exactly the same
  // sparsity pattern; only the numeric factorisation is then redone. With LuReuse::low_rank, a
  // low-rank update of a recent factorisation may replace the numeric factorisation.
  bool factorize(const SparseMatrix& k);
  // Whether the last factorize reused a cached symbolic analysis (or made none: low-rank update).
  bool symbolic_reused() const { return symbolic_reused_; }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  Eigen::VectorXd solve_transpose(const Eigen::VectorXd& b) const;
  // K^-1 b without UMFPACK's iterative refinement (nor the low-rank update's): the exact inverse
  // of the computed factors, a fixed linear operator for eigensolvers; about a third of the cost.
  Eigen::VectorXd solve_unrefined(const Eigen::VectorXd& b) const;
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
