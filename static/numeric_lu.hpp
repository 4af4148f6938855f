#pragma once
// UMFPACK's numeric LU as linear_solvers.cpp, low_rank_update.cpp and gmres.cpp use it. Internal
// to static/.
#include <cmath>
#include <ctime>
#include <stdexcept>

#include <Eigen/Dense>
#include <umfpack.h>

#include "static/linear_solvers.hpp"

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
  // arithmetic is the same, hence the same bits (bench/README.md, "Static solver").
  control[UMFPACK_ALLOC_INIT] = 1.0;
}

// One UMFPACK numeric factorisation with the matrix it factorised (its solves refine against it).
struct NumericLu {
  SparseMatrix k;  // compressed: UMFPACK keeps pointers to it between calls
  void* numeric = nullptr;
  int sign = 0;
  double log10_det = -INFINITY;
  NumericLu() = default;
  NumericLu(const NumericLu&) = delete;
  NumericLu& operator=(const NumericLu&) = delete;
  ~NumericLu() {
    if (numeric) umfpack_di_free_numeric(&numeric);
  }
  // sys: UMFPACK_A or UMFPACK_At. refine: UMFPACK's own iterative refinement (up to 2 steps);
  // the low-rank updates refine against their own matrix instead.
  Eigen::VectorXd solve(int sys, const Eigen::VectorXd& b, bool refine = true) const {
    if (!numeric) throw std::logic_error("LuFactor::solve without a successful factorisation");
    Eigen::VectorXd x(b.size());
    double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
    umfpack_control(control);
    if (!refine) control[UMFPACK_IRSTEP] = 0;
    LuStatistics& statistics = lu_statistics();
    const double t0 = refine ? thread_seconds() : 0.0;
    const int status = umfpack_di_solve(sys, k.outerIndexPtr(), k.innerIndexPtr(), k.valuePtr(),
                                        x.data(), b.data(), numeric, control, info);
    if (refine) {
      ++statistics.solves;
      statistics.solve_seconds += thread_seconds() - t0;
    } else {
      ++statistics.unrefined_solves;
    }
    if (status != UMFPACK_OK) throw std::runtime_error("UMFPACK solve failed");
    return x;
  }
};

// Right-preconditioned GMRES on K x = b (transposed: K^T x = b), M^-1 the unrefined solve with
// the factors of another matrix, restarted when the recurrence's residual drifts from the true
// one. Converged: |b - K x| <= tolerance | |K| |x| + |b| | (a normwise backward error, as
// UMFPACK's refinement judges its solves componentwise), checked on the true residual. False
// after max_iterations preconditioner solves; iterations counts them.
bool gmres(const SparseMatrix& k, const NumericLu& m, const Eigen::VectorXd& b, bool transposed,
           double tolerance, int max_iterations, Eigen::VectorXd& x, int& iterations);

}  // namespace granstab::statics
