// The LU factorisations of the tangent (UMFPACK; KLU below LuReuse::klu_max_dofs, klu_factor.cpp):
// symbolic analyses reused per sparsity pattern,
// low-rank (Woodbury) updates of a recent factorisation (low_rank_update.cpp), solves deferred to
// GMRES (gmres.cpp).
#include "static/linear_solvers.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <Eigen/Dense>
#include <umfpack.h>

#include "static/low_rank_update.hpp"
#include "static/numeric_lu.hpp"

namespace granstab::statics {
namespace {

// A UMFPACK symbolic analysis (ordering) of one sparsity pattern.
struct UmfpackAnalysis {
  void* symbolic = nullptr;
  UmfpackAnalysis() = default;
  UmfpackAnalysis(const UmfpackAnalysis&) = delete;
  UmfpackAnalysis& operator=(const UmfpackAnalysis&) = delete;
  ~UmfpackAnalysis() {
    if (symbolic) umfpack_di_free_symbolic(&symbolic);
  }
};

// The analysis of k's pattern with control's ordering, from this thread's cache; nullptr if
// UMFPACK fails.
std::shared_ptr<const UmfpackAnalysis> umfpack_analysis(const SparseMatrix& k, double* control,
                                                        bool& reused) {
  thread_local AnalysisCache<UmfpackAnalysis> cache;
  return cache.get(k, control[UMFPACK_ORDERING], reused, [control](const SparseMatrix& m) {
    auto analysis = std::make_shared<UmfpackAnalysis>();
    double info[UMFPACK_INFO];
    const int n = static_cast<int>(m.rows());
    // With the values, as a fresh analysis would be made (UMFPACK reads them for statistics and
    // the strategy choice only; the analysis holds for any values on the pattern).
    if (umfpack_di_symbolic(n, n, m.outerIndexPtr(), m.innerIndexPtr(), m.valuePtr(),
                            &analysis->symbolic, control, info) != UMFPACK_OK) {
      return std::shared_ptr<UmfpackAnalysis>();
    }
    return analysis;
  });
}

// Factorises k (compressed) with UMFPACK, or KLU below klu_max_dofs rows; false when singular or
// failed. reused: the symbolic analysis came from the cache.
bool factorize_numeric(NumericLu& lu, bool& reused, const LuReuse& reuse) {
  LuStatistics& statistics = lu_statistics();
  ++statistics.numeric;
  ++statistics.phase_numeric[static_cast<int>(statistics.phase)];
  const double t0 = thread_seconds();
  if (lu.k().rows() < reuse.klu_max_dofs) {
    const bool ok = factorize_klu(lu, reused);
    if (!reused) ++statistics.symbolic;
    statistics.numeric_seconds += thread_seconds() - t0;
    return ok;
  }
  double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
  umfpack_control(control);
  if (lu.k().rows() >= reuse.metis_min_dofs) control[UMFPACK_ORDERING] = UMFPACK_ORDERING_METIS;
  const std::shared_ptr<const UmfpackAnalysis> analysis = umfpack_analysis(lu.k(), control, reused);
  const double t1 = thread_seconds();
  statistics.symbolic_seconds += t1 - t0;
  if (!reused) ++statistics.symbolic;
  if (!analysis) return false;
  const int status =
      umfpack_di_numeric(lu.k().outerIndexPtr(), lu.k().innerIndexPtr(), lu.k().valuePtr(),
                         analysis->symbolic, &lu.numeric, control, info);
  statistics.numeric_seconds += thread_seconds() - t1;
  if (status != UMFPACK_OK) {  // includes UMFPACK_WARNING_singular_matrix
    if (lu.numeric) umfpack_di_free_numeric(&lu.numeric);
    return false;
  }
  // Mantissa and base-10 exponent: det K overflows a double for any realistic network.
  double mantissa = 0.0, exponent = 0.0;
  if (umfpack_di_get_determinant(&mantissa, &exponent, lu.numeric, info) != UMFPACK_OK)
    return false;
  lu.sign = mantissa > 0.0 ? 1 : (mantissa < 0.0 ? -1 : 0);
  lu.umfpack_log10_det = std::log10(std::abs(mantissa)) + exponent;
  lu.copy_after_solves = reuse.copy_after_solves;
  return lu.sign != 0;
}

// Recent full factorisations of this thread that low-rank updates start from.
std::vector<std::shared_ptr<const NumericLu>>& base_factors() {
  thread_local std::vector<std::shared_ptr<const NumericLu>> bases;
  return bases;
}

void remember_base(std::shared_ptr<const NumericLu> lu) {
  constexpr std::size_t capacity = 3;
  auto& bases = base_factors();
  bases.insert(bases.begin(), std::move(lu));
  if (bases.size() > capacity) bases.pop_back();
}

// The exact operator of a recent factorisation or low-rank update: the preconditioner of a
// deferred factorisation.
struct RecentOperator {
  std::shared_ptr<const NumericLu> full;
  std::shared_ptr<const LowRankUpdate> update;
  // The GMRES iterations of the latest solve it preconditioned (max_krylov_iterations + 1: over
  // the bound), shared by the copies of this operator.
  std::shared_ptr<int> last_iterations = std::make_shared<int>(0);
  Eigen::Index rows() const { return update ? update->base->k().rows() : full->k().rows(); }
  Eigen::VectorXd apply(const Eigen::VectorXd& v, bool transposed) const {
    return update ? update->apply(v, transposed)
                  : full->solve(transposed ? UMFPACK_At : UMFPACK_A, v, false);
  }
};

// This thread's recent operators, the latest first: a deferred factorisation is preconditioned by
// the latest of its size (after a stability check, its last iterate's update: the statuses the
// next load step starts from).
std::vector<RecentOperator>& recent_operators() {
  thread_local std::vector<RecentOperator> recent;
  return recent;
}

void remember_operator(RecentOperator op) {
  constexpr std::size_t capacity = 3;
  auto& recent = recent_operators();
  recent.insert(recent.begin(), std::move(op));
  if (recent.size() > capacity) recent.pop_back();
}

// A full factorisation: a base of updates and a preconditioner both.
void remember_factorisation(const std::shared_ptr<const NumericLu>& lu) {
  remember_operator({lu, nullptr});
  remember_base(lu);
}

}  // namespace

LuReuse& default_lu_reuse() {
  thread_local LuReuse reuse;
  return reuse;
}

void forget_factorisations() {
  base_factors().clear();
  recent_operators().clear();
  forget_klu_analyses();
}

LuStatistics& lu_statistics() {
  thread_local LuStatistics statistics;
  return statistics;
}

const UmfpackCopy* NumericLu::umfpack_copied() const {
  const std::lock_guard<std::mutex> lock(copy_mutex);
  if (copy_tried || copy_after_solves < 0 || ++unrefined_before_copy <= copy_after_solves)
    return umfpack_copy.get();
  copy_tried = true;
  const double t0 = thread_seconds();
  auto copy = std::make_unique<UmfpackCopy>();
  LuStatistics& statistics = lu_statistics();
  if (copy->assign(numeric, static_cast<int>(k().rows()))) {
    umfpack_copy = std::move(copy);
    ++statistics.copies;
  }
  statistics.copy_seconds += thread_seconds() - t0;
  return umfpack_copy.get();
}

struct LuFactor::Impl {
  LuReuse reuse;
  std::shared_ptr<const NumericLu> full;        // the factorisation of k itself
  std::shared_ptr<const LowRankUpdate> update;  // or a low-rank update of a base factorisation
  std::shared_ptr<const SparseMatrix> k;        // k, for the refinement of updated solves and GMRES
  // Deferred factorisation (LuReuse::krylov): GMRES on k preconditioned by this operator.
  std::optional<RecentOperator> preconditioner;
  bool deferred = false;
  bool singular = false;  // the deferred factorisation found k singular
};

namespace {
// glibc serves UMFPACK's large blocks by mmap and unmaps them on free, so every factorisation
// page-faults its memory in afresh: 19 % of q1 at N = 1400, with 10 s of system time of 62 s
// (docs/notes/2026-12-02-static-performance-log.md). Keep freed memory in the heap instead
// (process-wide, once; the peak footprint is unchanged). Allocation only: the same bits.
void keep_freed_memory() {
#ifdef __GLIBC__
  static std::once_flag once;
  std::call_once(once, [] {
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
  });
#endif
}
}  // namespace

LuFactor::LuFactor() : LuFactor(default_lu_reuse()) {}
LuFactor::LuFactor(const LuReuse& reuse) : impl_(std::make_unique<Impl>()) {
  keep_freed_memory();
  impl_->reuse = reuse;
}
LuFactor::~LuFactor() = default;

bool LuFactor::factorize(SparseMatrix k) {
  k.makeCompressed();
  auto own = std::make_shared<SparseMatrix>();
  own->swap(k);
  return factorize(std::shared_ptr<const SparseMatrix>(std::move(own)));
}

bool LuFactor::factorize(std::shared_ptr<const SparseMatrix> shared) {
  if (!shared->isCompressed()) {
    auto compressed = std::make_shared<SparseMatrix>(*shared);
    compressed->makeCompressed();
    shared = std::move(compressed);
  }
  const SparseMatrix& k = *shared;
  Impl& m = *impl_;
  m.full.reset();
  m.update.reset();
  m.preconditioner.reset();
  m.deferred = false;
  m.singular = false;
  det_sign_ = 0;
  symbolic_reused_ = false;
  if (k.rows() == 0) {
    det_sign_ = 1;
    return true;
  }
  const bool deferrable = m.reuse.krylov && k.rows() >= m.reuse.krylov_min_dofs;
  const bool updatable = m.reuse.low_rank && k.rows() >= m.reuse.low_rank_min_dofs;
  if (updatable) {
    // The recent factorisation from which k differs in the fewest columns.
    std::shared_ptr<const NumericLu> best;
    std::vector<int> best_cols, cols;
    for (const auto& base : base_factors()) {
      if (base->k().rows() != k.rows()) continue;
      const int limit = best ? static_cast<int>(best_cols.size()) : m.reuse.max_columns;
      if (!changed_columns(k, base->k(), limit, cols)) continue;
      if (!best || cols.size() < best_cols.size()) {
        best = base;
        best_cols = cols;
      }
    }
    if (best && best_cols.empty()) {  // the same matrix
      m.full = best;
    } else if (best) {
      m.update = low_rank_update(k, best, best_cols, m.reuse.max_rank);
      if (!m.update) ++lu_statistics().too_many;
    } else if (!base_factors().empty()) {
      ++lu_statistics().too_many;
    }
    if (m.full || m.update) {
      symbolic_reused_ = true;
      if (m.full) {
        det_sign_ = m.full->sign;
        return true;
      }
      ++lu_statistics().low_rank;
      lu_statistics().rank_sum += m.update->u.cols();
      const Eigen::MatrixXd& lu = m.update->capacitance.matrixLU();
      int sign = m.update->base->sign *
                 static_cast<int>(m.update->capacitance.permutationP().determinant());
      for (Eigen::Index i = 0; i < lu.rows(); ++i) {
        if (lu(i, i) == 0.0 || !std::isfinite(lu(i, i))) return false;
        if (lu(i, i) < 0.0) sign = -sign;
      }
      m.k = std::move(shared);
      det_sign_ = sign;
      remember_operator({nullptr, m.update});
      return true;
    }
  }
  if (deferrable) {
    for (const RecentOperator& op : recent_operators())
      if (op.rows() == k.rows()) {
        // The most recent one of this size, unless its latest GMRES solve took more than
        // krylov_stale_iterations: the matrices have moved away from it.
        if (*op.last_iterations <= m.reuse.krylov_stale_iterations) m.preconditioner = op;
        break;
      }
    if (m.preconditioner) {
      m.k = std::move(shared);
      m.deferred = true;
      symbolic_reused_ = true;
      ++lu_statistics().deferred;
      return true;
    }
  }
  auto lu = std::make_shared<NumericLu>();
  lu->matrix = std::move(shared);
  if (!factorize_numeric(*lu, symbolic_reused_, m.reuse)) return false;
  det_sign_ = lu->sign;
  m.full = lu;
  // Kept as a base only where one can serve: held here, a KLU factor would not become a spare.
  if (updatable || deferrable) remember_factorisation(lu);
  return true;
}

bool LuFactor::factorise_deferred() const {
  Impl& m = *impl_;
  if (!m.deferred) return !m.singular;
  m.deferred = false;
  m.preconditioner.reset();
  ++lu_statistics().deferred_factorised;
  auto lu = std::make_shared<NumericLu>();
  lu->matrix = std::move(m.k);
  bool reused = false;
  if (!factorize_numeric(*lu, reused, m.reuse)) {
    m.singular = true;
    det_sign_ = 0;
    return false;
  }
  det_sign_ = lu->sign;
  m.full = lu;
  remember_factorisation(lu);
  return true;
}

int LuFactor::determinant_sign() const {
  factorise_deferred();
  return det_sign_;
}

double LuFactor::log10_abs_determinant() const {
  factorise_deferred();
  const Impl& m = *impl_;
  if (det_sign_ == 0) return -INFINITY;
  if (m.update) {
    // det(K0 + U V^T) = det K0 det(C), C the capacitance matrix.
    const Eigen::MatrixXd& lu = m.update->capacitance.matrixLU();
    double log10_det = m.update->base->log10_abs_det();
    for (Eigen::Index i = 0; i < lu.rows(); ++i) log10_det += std::log10(std::abs(lu(i, i)));
    return log10_det;
  }
  return m.full ? m.full->log10_abs_det() : 0.0;  // no factor: the empty matrix
}

bool LuFactor::factorised() const { return !impl_->deferred; }

namespace {
// GMRES with the deferred factorisation's preconditioner; false when over the bound.
bool krylov_solve(const SparseMatrix& k, const RecentOperator& preconditioner, const LuReuse& reuse,
                  const Eigen::VectorXd& b, bool transposed, Eigen::VectorXd& x) {
  LuStatistics& statistics = lu_statistics();
  const double t0 = thread_seconds();
  int iterations = 0;
  const auto precondition = [&](const Eigen::VectorXd& v) {
    return preconditioner.apply(v, transposed);
  };
  const bool converged = gmres(k, precondition, b, transposed, reuse.krylov_tolerance,
                               reuse.max_krylov_iterations, x, iterations);
  *preconditioner.last_iterations = converged ? iterations : reuse.max_krylov_iterations + 1;
  const double seconds = thread_seconds() - t0;
  statistics.krylov_seconds += seconds;
  statistics.krylov_iterations += iterations;
  ++(converged ? statistics.krylov_solves : statistics.krylov_failed);
  const int phase = static_cast<int>(statistics.phase);
  statistics.phase_krylov_seconds[phase] += seconds;
  statistics.phase_krylov_iterations[phase] += iterations;
  ++(converged ? statistics.phase_krylov_solves : statistics.phase_krylov_failed)[phase];
  return converged;
}

Eigen::VectorXd not_a_solution(Eigen::Index n) {
  return Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
}
}  // namespace

bool LuFactor::try_solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  x = solve(b);
  return !impl_->singular;
}

Eigen::VectorXd LuFactor::solve(const Eigen::VectorXd& b) const { return solve_system(b, false); }

Eigen::VectorXd LuFactor::solve_transpose(const Eigen::VectorXd& b) const {
  return solve_system(b, true);
}

Eigen::VectorXd LuFactor::solve_system(const Eigen::VectorXd& b, bool transposed) const {
  if (b.size() == 0) return b;
  const Impl& m = *impl_;
  if (m.deferred) {
    Eigen::VectorXd x;
    if (krylov_solve(*m.k, *m.preconditioner, m.reuse, b, transposed, x)) return x;
    if (!factorise_deferred()) return not_a_solution(b.size());
  }
  if (m.update) return refined(*m.update, *m.k, b, transposed);
  if (!m.full) throw std::logic_error("LuFactor::solve without a successful factorisation");
  return m.full->solve(transposed ? UMFPACK_At : UMFPACK_A, b, m.reuse.refine);
}

Eigen::VectorXd LuFactor::solve_unrefined(const Eigen::VectorXd& b) const {
  if (b.size() == 0) return b;
  if (!factorise_deferred()) return not_a_solution(b.size());
  if (impl_->update) return impl_->update->apply(b, false);
  if (!impl_->full) throw std::logic_error("LuFactor::solve without a successful factorisation");
  return impl_->full->solve(UMFPACK_A, b, false);
}

}  // namespace granstab::statics
