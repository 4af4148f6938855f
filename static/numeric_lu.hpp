#pragma once
// The numeric LU as linear_solvers.cpp, low_rank_update.cpp and gmres.cpp use it: UMFPACK, or
// KLU for small systems (LuReuse::klu_max_dofs; klu_factor.cpp). Internal to static/.
#include <algorithm>
#include <cmath>
#include <ctime>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>
#include <klu.h>
#include <umfpack.h>

#include "static/linear_solvers.hpp"
#include "static/umfpack_copy.hpp"

namespace granstab::statics {

inline double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

inline void umfpack_control(double* control) {
  umfpack_di_defaults(control);
  control[UMFPACK_PRL] = 0;
  // Allocate the estimated peak of the numeric factorisation at once (default: 70 % of it): the
  // reallocations and copies as the factors grow took ~19 % of a q1 run at N = 1400 (perf). The
  // arithmetic is the same, hence the same bits (docs/notes/2026-12-02-static-performance-log.md).
  control[UMFPACK_ALLOC_INIT] = 1.0;
}

// |K| |x| (transposed: |K|^T |x|) without a copy of |K| (a copy per GMRES solve cost ~1 % of a q1
// run at N = 1400, perf): the sums of Eigen's sparse products, in their order. The scale of the
// backward errors of GMRES (gmres.cpp) and of KLU's refinement (klu_factor.cpp).
inline Eigen::VectorXd abs_product(const SparseMatrix& k, const Eigen::VectorXd& x,
                                   bool transposed) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(transposed ? k.cols() : k.rows());
  for (Eigen::Index j = 0; j < k.outerSize(); ++j) {
    if (transposed) {
      double sum = 0.0;
      for (SparseMatrix::InnerIterator it(k, j); it; ++it)
        sum += std::abs(it.value()) * std::abs(x[it.index()]);
      y[j] += sum;
    } else {
      const double xj = std::abs(x[j]);
      for (SparseMatrix::InnerIterator it(k, j); it; ++it)
        y[it.index()] += std::abs(it.value()) * xj;
    }
  }
  return y;
}

// Symbolic analyses of the last few sparsity patterns factorised in a thread (one cache per
// thread and solver): a load step refactorises the same pattern many times (status iterations,
// Newton, the stability check). `key` tells analyses of one pattern apart (UMFPACK's ordering).
template <class Analysis>
class AnalysisCache {
 public:
  // The analysis of k's pattern under key, made by make(k) on a miss (nullptr: failed).
  template <class Make>
  std::shared_ptr<const Analysis> get(const SparseMatrix& k, double key, bool& reused, Make make) {
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      if (entries_[e].key != key || !entries_[e].pattern.same_as(k)) continue;
      std::rotate(entries_.begin(), entries_.begin() + e,
                  entries_.begin() + e + 1);  // most recent first
      reused = true;
      return entries_.front().analysis;
    }
    reused = false;
    std::shared_ptr<const Analysis> analysis = make(k);
    if (!analysis) return nullptr;
    if (entries_.size() == capacity) entries_.pop_back();
    entries_.insert(entries_.begin(), Entry{SparsityPattern{}, key, analysis});
    entries_.front().pattern.assign(k);
    return analysis;
  }
  void clear() { entries_.clear(); }

 private:
  static constexpr std::size_t capacity = 4;
  struct Entry {
    SparsityPattern pattern;
    double key = 0.0;
    std::shared_ptr<const Analysis> analysis;
  };
  std::vector<Entry> entries_;
};

// This thread's KLU settings and status (every KLU call takes them).
klu_common& klu_settings();

// A KLU symbolic analysis (fill-reducing ordering, block triangular form) of one sparsity
// pattern, shared by the factorisations of that pattern, and the factors of that pattern no
// longer in use: klu_refactor refills them in their pivot order, without the pivot search and
// the symbolic work of each column (half of a factorisation's time on periodic-n100).
struct KluAnalysis {
  klu_symbolic* symbolic = nullptr;
  // Spare factors with KLU's rcond (smallest over largest |pivot|) of the pivoting factorisation
  // that chose their pivot order (klu_factor.cpp judges a refactorisation by it).
  struct Spare {
    klu_numeric* numeric = nullptr;
    double rcond = 0.0;
  };
  KluAnalysis() = default;
  KluAnalysis(const KluAnalysis&) = delete;
  KluAnalysis& operator=(const KluAnalysis&) = delete;
  ~KluAnalysis() {
    for (Spare& s : spares_) klu_free_numeric(&s.numeric, &klu_settings());
    if (symbolic) klu_free_symbolic(&symbolic, &klu_settings());
  }
  // Takes the spare given back last (false: none). Factors are given back and taken in the
  // order of the run, so the pivot orders, and the bits, are those of a fixed sequence of calls.
  bool take_spare(Spare& s) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (spares_.empty()) return false;
    s = spares_.back();
    spares_.pop_back();
    return true;
  }
  void give_back(Spare s) const {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (spares_.size() < max_spares) {
      spares_.push_back(s);
    } else {
      klu_free_numeric(&s.numeric, &klu_settings());
    }
  }

 private:
  static constexpr std::size_t max_spares = 4;
  mutable std::mutex mutex_;  // a factorisation may end in another thread than its analysis'
  mutable std::vector<Spare> spares_;
};

// One numeric factorisation, UMFPACK's or KLU's, with the matrix it factorised (its solves
// refine against it).
struct NumericLu {
  // Compressed: UMFPACK and KLU keep pointers to it between calls. Shared, never changed: the
  // caller's own K where no dof is dropped (the status loop's tangent), without a copy.
  std::shared_ptr<const SparseMatrix> matrix;
  const SparseMatrix& k() const { return *matrix; }
  void* numeric = nullptr;                      // UMFPACK
  std::shared_ptr<const KluAnalysis> analysis;  // KLU: the pattern's analysis and
  klu_numeric* klu = nullptr;                   // the factors
  double klu_rcond = 0.0;  // KLU: the rcond of the pivoting factorisation that chose their pivots
  int sign = 0;
  // log10 |det K|: UMFPACK's, kept at the factorisation; KLU's, summed from its factors when
  // asked (only tests ask: a log10 per pivot and row scale was ~1 % of a q1 run's instructions).
  double log10_abs_det() const;
  double umfpack_log10_det = -INFINITY;
  // UMFPACK: a copy of L by rows (umfpack_copy.hpp), made at the first unrefined solve after
  // copy_after_solves of them (LuReuse::copy_after_solves; negative: never); later unrefined
  // solves read it, with the same bits.
  int copy_after_solves = -1;
  mutable int unrefined_before_copy = 0;
  mutable bool copy_tried = false;
  mutable std::unique_ptr<UmfpackCopy> umfpack_copy;
  mutable std::mutex copy_mutex;
  // The copy for this unrefined solve (null: UMFPACK solves it alone).
  const UmfpackCopy* umfpack_copied() const;
  NumericLu() = default;
  NumericLu(const NumericLu&) = delete;
  NumericLu& operator=(const NumericLu&) = delete;
  ~NumericLu() {
    if (numeric) umfpack_di_free_numeric(&numeric);
    if (klu) analysis->give_back({klu, klu_rcond});
  }
  // sys: UMFPACK_A or UMFPACK_At. refine: UMFPACK's own iterative refinement (up to 2 steps);
  // the low-rank updates refine against their own matrix instead.
  Eigen::VectorXd solve(int sys, const Eigen::VectorXd& b, bool refine = true) const {
    if (klu) return solve_klu(sys == UMFPACK_At, b, refine);
    if (!numeric) throw std::logic_error("LuFactor::solve without a successful factorisation");
    Eigen::VectorXd x(b.size());
    if (!refine && sys == UMFPACK_A) {
      if (const UmfpackCopy* c = umfpack_copied()) {
        ++lu_statistics().unrefined_solves;
        c->solve(numeric, b.data(), x.data());
        return x;
      }
    }
    double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
    umfpack_control(control);
    if (!refine) control[UMFPACK_IRSTEP] = 0;
    LuStatistics& statistics = lu_statistics();
    const double t0 = refine ? thread_seconds() : 0.0;
    const int status = umfpack_di_solve(sys, k().outerIndexPtr(), k().innerIndexPtr(),
                                        k().valuePtr(), x.data(), b.data(), numeric, control, info);
    if (refine) {
      ++statistics.solves;
      statistics.solve_seconds += thread_seconds() - t0;
    } else {
      ++statistics.unrefined_solves;
    }
    if (status != UMFPACK_OK) throw std::runtime_error("UMFPACK solve failed");
    return x;
  }
  // The same with KLU's factors (klu_factor.cpp).
  Eigen::VectorXd solve_klu(bool transposed, const Eigen::VectorXd& b, bool refine) const;
  // Each column of x replaced by its unrefined solve (the same bits as solve(sys, column,
  // false)). KLU solves up to four columns in one sweep of its factors, which a solve reads from
  // memory once instead of once per column (klu_factor.cpp); UMFPACK one column at a time.
  void solve_columns(int sys, Eigen::MatrixXd& x) const;
};

// Factorises lu.k (compressed) with KLU, the analysis of its pattern taken from this thread's
// cache (reused: found there); sets sign. False when singular or failed.
bool factorize_klu(NumericLu& lu, bool& reused);
// Drops this thread's KLU analyses and with them their spare factors: a run that starts here
// takes no pivot order from an earlier one (forget_factorisations).
void forget_klu_analyses();

// Right-preconditioned GMRES on K x = b (transposed: K^T x = b), precondition(v) = M^-1 v
// (transposed: M^-T v) the unrefined solve with another matrix (a recent LU, or a low-rank update
// of one), restarted when the recurrence's residual drifts from the true one. Converged:
// |b - K x| <= tolerance (|K| |x| + |b|) (a normwise backward error, as UMFPACK's refinement
// judges its solves componentwise), checked on the true residual. False after max_iterations
// preconditioner solves; iterations counts them.
bool gmres(const SparseMatrix& k,
           const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& precondition,
           const Eigen::VectorXd& b, bool transposed, double tolerance, int max_iterations,
           Eigen::VectorXd& x, int& iterations);

}  // namespace granstab::statics
