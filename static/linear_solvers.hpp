#pragma once
// The two factorisations of the static solver, behind one small interface each so that no
// SuiteSparse header leaks out of static/ (DEPS.md #9):
// - CHOLMOD simplicial LL^T for symmetric positive definite systems (a failed factorisation
//   is the test of positive definiteness; DEPS.md #1-#3);
// - UMFPACK LU (KLU for small systems) for the full unsymmetric operator with sliding contacts,
//   with the sign of its determinant (STATIC.md §S3.1 first route, §S3.4 (b)).
#include <algorithm>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "static/tangent.hpp"

namespace granstab::statics {

// The sparsity pattern of a compressed matrix, kept to recognise it again: an ordering or
// symbolic analysis depends on the pattern only, and a q1 run factorises many matrices of one
// contact list's pattern.
struct SparsityPattern {
  std::vector<int> col, row;  // outer starts, inner indices (empty: none kept)
  bool same_as(const SparseMatrix& compressed) const {
    return static_cast<Eigen::Index>(col.size()) == compressed.outerSize() + 1 &&
           static_cast<Eigen::Index>(row.size()) == compressed.nonZeros() &&
           std::equal(col.begin(), col.end(), compressed.outerIndexPtr()) &&
           std::equal(row.begin(), row.end(), compressed.innerIndexPtr());
  }
  void assign(const SparseMatrix& compressed) {
    col.assign(compressed.outerIndexPtr(), compressed.outerIndexPtr() + compressed.outerSize() + 1);
    row.assign(compressed.innerIndexPtr(), compressed.innerIndexPtr() + compressed.nonZeros());
  }
  void clear() {
    col.clear();
    row.clear();
  }
};

class SymmetricFactor {
 public:
  SymmetricFactor();
  ~SymmetricFactor();
  SymmetricFactor(const SymmetricFactor&) = delete;
  SymmetricFactor& operator=(const SymmetricFactor&) = delete;

  // Factorises the symmetric matrix (its lower triangle is read). Returns false when it is not
  // positive definite (CHOLMOD_NOT_POSDEF, checked right after the factorisation). The symbolic
  // analysis of the previous call is reused when k has exactly the same sparsity pattern (the
  // same ordering, hence the same factor).
  bool factorize(const SparseMatrix& k);
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  // S^-1 B for several right-hand sides at once (bench/static/bench_schur).
  Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& b) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// How LuFactor may avoid a numeric factorisation (off by default: the results then differ from a
// fresh LU in round-off; docs/static.md "Performance"), and whether its solves are refined.
struct LuReuse {
  // A matrix that differs from a recent full factorisation K0 of this thread in a few columns
  // (status changes of a few contacts inside a complementarity loop) is written K = K0 + U V^T
  // (rank-revealing QR of the changed block) and solved by the Woodbury formula with K0's factor,
  // plus one step of iterative refinement against K; det K = det K0 det(I + V^T K0^-1 U), so the
  // determinant sign stays exact. Tried before deferral (krylov) when both are on.
  bool low_rank = false;
  int low_rank_min_dofs = 0;  // updates only for matrices of at least this many rows
  int max_columns = 96;       // changed columns beyond which K is not updated
  int max_rank = 40;          // rank of U V^T beyond which K is not updated (r solves with K0)
  // Deferred factorisation: a matrix of the size of a recent full factorisation or update K0 of
  // this thread (the check's later status iterates change a few contact blocks, the corrector
  // O(dq) of the geometry; a step's status iterates are factorised, complementarity_loop.cpp) is
  // not factorised; its solves run GMRES on K itself, right-preconditioned by K0's
  // exact operator (the latest one of the size). K is factorised when GMRES does not reach the
  // tolerance in max_krylov_iterations, and whenever an exact operator is asked for: the
  // determinant (sign and magnitude) and solve_unrefined (the eigensolvers' operator).
  bool krylov = false;
  // Deferral only for matrices of at least this many rows, those UMFPACK factorises (see
  // klu_max_dofs): below, KLU refactorises into a spare's pivot order in about the time of a
  // GMRES solve, and factorising every matrix took 10-12 % off three of the main job's six static
  // halves, 1-3 % off the others (docs/notes/2026-12-05-static-main-job.md). At 2538 rows (UMFPACK)
  // deferral still saves 3 %.
  int krylov_min_dofs = 2000;
  int max_krylov_iterations = 24;  // about the cost of one numeric factorisation at N = 5600
  // A matrix is factorised at once, not deferred, when the latest GMRES solve preconditioned by
  // the operator it would take needed more iterations than this (or failed): the matrices of a
  // corrector drift away from their preconditioner, and the next solve would cost more still or
  // run over the bound. On the N = 5600 tiling's q1, 177 -> 79 solves over the bound and 16102 ->
  // 11662 GMRES iterations, 5 % less time (docs/notes/2026-12-07-stale-preconditioner.md).
  int krylov_stale_iterations = 12;
  // An UMFPACK factor's unrefined solves read a copy of its L by rows (UmfpackCopy: the same
  // bits, a third less time per solve) from the first one after this many (negative: never). The
  // copy costs about two solves; most factors are solved with at most twice (a status iterate) or
  // over 16 times (a GMRES preconditioner, the Arnoldi operator; series B: 232 and 558 of 886).
  int copy_after_solves = 4;
  // |b - K x| <= krylov_tolerance | |K| |x| + |b| |: at 1e-14 a third of the GMRES solves at
  // N = 5600 did not get there in 24 iterations (the residual's round-off floor); the path and
  // q1 are the same at 1e-12 and 1e-14 (docs/notes/2026-12-02-static-speed-measurements.md).
  double krylov_tolerance = 1e-12;
  // UMFPACK's fill-reducing ordering: METIS (nested dissection, through CHOLMOD) for matrices of
  // at least this many rows, AMD/COLAMD (UMFPACK's default) below. At 61248 dofs (the N = 22400
  // tiling of series B) METIS takes 34 % off the numeric factorisations and 17 % off q1's first
  // 20 states; at 15312 dofs 12 % and 1 %; at 3828 nothing (commit 0d8bbc1).
  // The threshold keeps the shipped samples (N <= 1400) on their path to the bit.
  int metis_min_dofs = 40000;
  // KLU instead of UMFPACK for matrices of fewer rows: UMFPACK's numeric factorisation has a fixed
  // cost of a few hundred microseconds (its frontal matrices, pivot search and memory) that KLU's
  // left-looking one does not have. Per numeric factorisation in q1 runs (bench_static, one
  // thread): 282 dofs (periodic-n100) 0.48 -> 0.30 ms, 1128 dofs (2 x 2 tiling) 3.9 -> 2.6 ms,
  // 2538 (3 x 3) 9.6 -> 7.4. Whole q1 runs, side by side: series A (N = 1024, 2888 dofs) 9-11 %
  // faster with KLU (its path moves by round-off, q1 the same bits), series B (3819 dofs) 8-12 %
  // slower, so the threshold lies between them (docs/notes/2026-12-05-static-main-job.md).
  int klu_max_dofs = 3300;
  // Iterative refinement in solve and solve_transpose (UMFPACK's, or klu_factor.cpp's for KLU: up
  // to 2 steps against K, 5-8 unrefined solves' worth). Off, a solve is the exact inverse of the
  // computed factors (backward stable). The load step turns it off (SolverOptions::refine_solves).
  bool refine = true;
};
// The reuse of a default-constructed LuFactor in this thread.
LuReuse& default_lu_reuse();

// Drops this thread's recent full factorisations (the bases of low-rank updates, the
// preconditioners of deferred factorisations): what a run computes after it does not depend on
// what the thread factorised before (the same bits run after run).
void forget_factorisations();

// The part of a q1 run that this thread's LuFactor work belongs to (bench/static splits the
// counters by it; set by the load step and the stability check).
enum class SolvePhase {
  other,
  step_loop,
  chord,
  corrector,
  check_first,
  check_later,
  check_sign,
  count
};

// Counters of this thread's LuFactor work (bench/static).
struct LuStatistics {
  long numeric = 0;           // full numeric factorisations
  long symbolic = 0;          // symbolic analyses among them
  long refactorisations = 0;  // KLU: numeric ones in a spare's pivot order (klu_refactor)
  long low_rank = 0;          // factorisations replaced by a low-rank update
  long rank_sum = 0;          // sum of the ranks of those updates
  long too_many = 0;          // updates refused (too many changed columns or too high a rank)
  long solves = 0;            // solves with iterative refinement (solve, solve_transpose)
  long unrefined_solves = 0;  // solves without it (solve_unrefined, low-rank updates' inner ones)
  long deferred = 0;          // factorisations deferred (LuReuse::krylov)
  long deferred_factorised = 0;   // ... and made later for an exact operator (determinant etc.)
  long krylov_solves = 0;         // GMRES solves, converged
  long krylov_iterations = 0;     // their iterations (one preconditioner solve each)
  long krylov_failed = 0;         // GMRES solves over the bound: K factorised instead
  double krylov_seconds = 0.0;    // thread CPU seconds of the GMRES solves (failed ones included)
  double solve_seconds = 0.0;     // thread CPU seconds of the refined UMFPACK solves
  double symbolic_seconds = 0.0;  // thread CPU seconds of the symbolic analyses
  double numeric_seconds = 0.0;   // thread CPU seconds of the numeric factorisations
  long copies = 0;                // UMFPACK factors whose L was copied (UmfpackCopy)
  double copy_seconds = 0.0;      // thread CPU seconds of those copies
  // The same split by SolvePhase: numeric factorisations, GMRES solves (converged), over the
  // bound, iterations, CPU seconds.
  SolvePhase phase = SolvePhase::other;
  static constexpr int phases = static_cast<int>(SolvePhase::count);
  long phase_numeric[phases] = {};
  long phase_krylov_solves[phases] = {};
  long phase_krylov_failed[phases] = {};
  long phase_krylov_iterations[phases] = {};
  double phase_krylov_seconds[phases] = {};
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
  // low-rank update of a recent factorisation may replace the numeric factorisation. k is kept
  // (for the refinement, GMRES and the updates): a temporary passed here is swapped in, not
  // copied (Eigen 3.4's SparseMatrix has no move operations).
  bool factorize(SparseMatrix k);
  // The same for a K held elsewhere too, shared instead of copied (it must not change).
  bool factorize(std::shared_ptr<const SparseMatrix> k);
  // Whether the last factorize reused a cached symbolic analysis (or made none: low-rank update,
  // deferred factorisation).
  bool symbolic_reused() const { return symbolic_reused_; }
  // K^-1 b, refined by UMFPACK unless LuReuse::refine is off. With a deferred factorisation
  // (LuReuse::krylov) K may turn out singular only here: try_solve then returns false, solve a
  // vector of NaN.
  bool try_solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  Eigen::VectorXd solve_transpose(const Eigen::VectorXd& b) const;
  // K^-1 b without iterative refinement (UMFPACK's, KLU's or the low-rank update's): the exact
  // inverse of the computed factors, a fixed linear operator for eigensolvers; about a third of the
  // cost. Factorises a deferred K first.
  Eigen::VectorXd solve_unrefined(const Eigen::VectorXd& b) const;
  // Sign of det K (+1, -1; 0 when singular) and log10 |det K|, always from a factorisation of K
  // or the exact determinant identity of a low-rank update (a deferred K is factorised now).
  int determinant_sign() const;
  double log10_abs_determinant() const;
  // Whether K is factorised (or updated) already, i.e. the determinant costs nothing.
  bool factorised() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  // Factorises a deferred K; false when singular.
  bool factorise_deferred() const;
  Eigen::VectorXd solve_system(const Eigen::VectorXd& b, bool transposed) const;
  mutable int det_sign_ = 0;
  bool symbolic_reused_ = false;
};

// The submatrix on the kept indices (keep[i] != 0), in order, and the maps between the two.
struct Reduction {
  std::vector<int> full_to_reduced;  // -1 for an eliminated index
  std::vector<int> reduced_to_full;
  bool keeps_all() const { return reduced_to_full.size() == full_to_reduced.size(); }
};
Reduction make_reduction(const std::vector<char>& keep);
SparseMatrix reduce(const SparseMatrix& k, const Reduction& r);
// The same, taking k's storage instead of copying it when every index is kept (k is then left
// empty; otherwise it is left as it was): Eigen 3.4's SparseMatrix has no move constructor.
SparseMatrix reduce(SparseMatrix&& k, const Reduction& r);
// k on the kept indices without a copy when every index is kept: k itself, else `reduced`, set.
const SparseMatrix& kept_part(const SparseMatrix& k, const Reduction& r, SparseMatrix& reduced);
Eigen::VectorXd reduce(const Eigen::VectorXd& v, const Reduction& r);
Eigen::VectorXd expand(const Eigen::VectorXd& v, const Reduction& r, int full_size);

}  // namespace granstab::statics
