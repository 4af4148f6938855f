// The LU factorisations of the tangent (UMFPACK): symbolic analyses reused per sparsity pattern,
// low-rank (Woodbury) updates of a recent factorisation, solves deferred to GMRES (gmres.cpp).
#include "static/linear_solvers.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <mutex>
#include <stdexcept>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <Eigen/Dense>
#include <umfpack.h>

#include "static/numeric_lu.hpp"

namespace granstab::statics {
namespace {

// Symbolic analyses (orderings) of the last few sparsity patterns factorised in this thread: a load
// step refactorises the same pattern many times (status iterations, Newton, the stability check).
class SymbolicCache {
 public:
  ~SymbolicCache() {
    for (Entry& e : entries_)
      if (e.symbolic) umfpack_di_free_symbolic(&e.symbolic);
  }
  // The analysis of k's pattern, computed on a miss; nullptr if UMFPACK fails.
  void* get(const SparseMatrix& k, const double* control, bool& reused) {
    const int n = static_cast<int>(k.rows());
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      if (!entries_[e].pattern.same_as(k)) continue;
      std::rotate(entries_.begin(), entries_.begin() + e,
                  entries_.begin() + e + 1);  // most recent first
      reused = true;
      return entries_.front().symbolic;
    }
    reused = false;
    double info[UMFPACK_INFO];
    void* symbolic = nullptr;
    // With the values, as a fresh analysis would be made (UMFPACK reads them for statistics and
    // the strategy choice only; the analysis holds for any values on the pattern).
    if (umfpack_di_symbolic(n, n, k.outerIndexPtr(), k.innerIndexPtr(), k.valuePtr(), &symbolic,
                            control, info) != UMFPACK_OK) {
      if (symbolic) umfpack_di_free_symbolic(&symbolic);
      return nullptr;
    }
    if (entries_.size() == capacity) {
      umfpack_di_free_symbolic(&entries_.back().symbolic);
      entries_.pop_back();
    }
    Entry x;
    x.pattern.assign(k);
    x.symbolic = symbolic;
    entries_.insert(entries_.begin(), std::move(x));
    return symbolic;
  }

 private:
  static constexpr std::size_t capacity = 4;
  struct Entry {
    SparsityPattern pattern;
    void* symbolic = nullptr;
  };
  std::vector<Entry> entries_;
};

SymbolicCache& symbolic_cache() {
  thread_local SymbolicCache cache;
  return cache;
}

// Factorises k (compressed) with UMFPACK; false when singular or failed. reused: the symbolic
// analysis came from the cache.
bool factorize_numeric(NumericLu& lu, bool& reused) {
  double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
  umfpack_control(control);
  LuStatistics& statistics = lu_statistics();
  ++statistics.numeric;
  ++statistics.phase_numeric[static_cast<int>(statistics.phase)];
  const double t0 = thread_seconds();
  void* symbolic = symbolic_cache().get(lu.k, control, reused);
  const double t1 = thread_seconds();
  statistics.symbolic_seconds += t1 - t0;
  if (!reused) ++statistics.symbolic;
  if (!symbolic) return false;
  const int status = umfpack_di_numeric(lu.k.outerIndexPtr(), lu.k.innerIndexPtr(), lu.k.valuePtr(),
                                        symbolic, &lu.numeric, control, info);
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
  lu.log10_det = std::log10(std::abs(mantissa)) + exponent;
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

// The columns in which k and k0 (same size, compressed) differ in value; false when more than
// limit. An entry stored in one and absent from the other counts as a difference unless it is 0.
bool changed_columns(const SparseMatrix& k, const SparseMatrix& k0, int limit,
                     std::vector<int>& cols) {
  cols.clear();
  const int* p = k.outerIndexPtr();
  const int* p0 = k0.outerIndexPtr();
  const int* i = k.innerIndexPtr();
  const int* i0 = k0.innerIndexPtr();
  const double* x = k.valuePtr();
  const double* x0 = k0.valuePtr();
  for (int j = 0; j < k.outerSize(); ++j) {
    int a = p[j], a0 = p0[j];
    const int end = p[j + 1], end0 = p0[j + 1];
    bool differs = false;
    while ((a < end || a0 < end0) && !differs) {
      if (a < end && a0 < end0 && i[a] == i0[a0]) {
        differs = x[a++] != x0[a0++];
      } else if (a0 >= end0 || (a < end && i[a] < i0[a0])) {
        differs = x[a++] != 0.0;
      } else {
        differs = x0[a0++] != 0.0;
      }
    }
    if (!differs) continue;
    if (static_cast<int>(cols.size()) == limit) return false;
    cols.push_back(j);
  }
  return true;
}

}  // namespace

LuReuse& default_lu_reuse() {
  thread_local LuReuse reuse;
  return reuse;
}

void forget_factorisations() { base_factors().clear(); }

LuStatistics& lu_statistics() {
  thread_local LuStatistics statistics;
  return statistics;
}

// K = K0 + U V^T with U, V supported on a few rows and columns: Woodbury with K0's factor.
struct LowRankUpdate {
  std::shared_ptr<const NumericLu> base;
  std::vector<int> rows, cols;                       // supports of U and V
  Eigen::MatrixXd u, v;                              // |rows| x r, |cols| x r
  Eigen::MatrixXd z;                                 // K0^-1 U (n x r)
  Eigen::PartialPivLU<Eigen::MatrixXd> capacitance;  // I + V^T K0^-1 U
  mutable Eigen::MatrixXd zt;  // K0^-T V (n x r), made on the first transposed solve

  // K^-1 b (transposed: K^-T b) without refinement.
  Eigen::VectorXd apply(const Eigen::VectorXd& b, bool transposed) const {
    const Eigen::Index r = u.cols();
    // K^T = K0^T + V U^T: the roles of U and V swap.
    const std::vector<int>& right_support = transposed ? rows : cols;
    const Eigen::MatrixXd& right = transposed ? u : v;
    if (transposed && zt.cols() != r) {
      zt.resize(b.size(), r);
      for (Eigen::Index c = 0; c < r; ++c) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(b.size());
        for (std::size_t a = 0; a < cols.size(); ++a) e[cols[a]] = v(a, c);
        zt.col(c) = base->solve(UMFPACK_At, e, false);
      }
    }
    const Eigen::VectorXd y = base->solve(transposed ? UMFPACK_At : UMFPACK_A, b, false);
    Eigen::VectorXd t(r);
    for (Eigen::Index c = 0; c < r; ++c) {
      double sum = 0.0;
      for (std::size_t a = 0; a < right_support.size(); ++a)
        sum += right(a, c) * y[right_support[a]];
      t[c] = sum;
    }
    const Eigen::VectorXd s =
        transposed ? Eigen::VectorXd(capacitance.transpose().solve(t)) : capacitance.solve(t);
    return y - (transposed ? zt : z) * s;
  }
};

struct LuFactor::Impl {
  LuReuse reuse;
  std::shared_ptr<const NumericLu> full;  // the factorisation of k itself
  std::unique_ptr<LowRankUpdate> update;  // or a low-rank update of a base factorisation
  SparseMatrix k;                         // k, for the refinement of updated solves and for GMRES
  // Deferred factorisation (LuReuse::krylov): GMRES on k preconditioned by this factorisation.
  std::shared_ptr<const NumericLu> preconditioner;
  bool deferred = false;
  bool singular = false;  // the deferred factorisation found k singular
};

namespace {

// K = K0 + (K - K0) with the change confined to cols: a rank-revealing QR of the changed block
// gives U V^T. Null when the change is too large for an update to pay.
std::unique_ptr<LowRankUpdate> low_rank_update(const SparseMatrix& k,
                                               std::shared_ptr<const NumericLu> base,
                                               const std::vector<int>& cols, int max_rank) {
  const int n = static_cast<int>(k.rows());
  std::vector<int> row_slot(n, -1);
  std::vector<int> rows;
  std::vector<Eigen::Triplet<double>> change;  // (row, column slot, K - K0)
  const SparseMatrix& k0 = base->k;
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const int j = cols[c];
    const auto add = [&](int row, double value) {
      if (value == 0.0) return;
      if (row_slot[row] < 0) {
        row_slot[row] = static_cast<int>(rows.size());
        rows.push_back(row);
      }
      change.emplace_back(row_slot[row], static_cast<int>(c), value);
    };
    SparseMatrix::InnerIterator a(k, j), a0(k0, j);
    while (a || a0) {
      if (a && a0 && a.row() == a0.row()) {
        add(a.row(), a.value() - a0.value());
        ++a;
        ++a0;
      } else if (!a0 || (a && a.row() < a0.row())) {
        add(a.row(), a.value());
        ++a;
      } else {
        add(a0.row(), -a0.value());
        ++a0;
      }
    }
  }
  Eigen::MatrixXd block = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()),
                                                static_cast<Eigen::Index>(cols.size()));
  for (const auto& t : change) block(t.row(), t.col()) += t.value();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(block);
  // Pivots below 1e-13 of the largest change are round-off of the assembly's sums.
  qr.setThreshold(1e-13);
  const Eigen::Index r = qr.rank();
  if (r > max_rank) return nullptr;
  auto up = std::make_unique<LowRankUpdate>();
  up->base = std::move(base);
  up->rows = std::move(rows);
  up->cols = cols;
  up->u = qr.householderQ() * Eigen::MatrixXd::Identity(block.rows(), r);
  const Eigen::MatrixXd r_top = qr.matrixR().topRows(r).triangularView<Eigen::Upper>();
  up->v = (r_top * qr.colsPermutation().transpose()).transpose();
  up->z.resize(n, r);
  for (Eigen::Index c = 0; c < r; ++c) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    for (std::size_t a = 0; a < up->rows.size(); ++a) e[up->rows[a]] = up->u(a, c);
    up->z.col(c) = up->base->solve(UMFPACK_A, e, false);
  }
  Eigen::MatrixXd cap = Eigen::MatrixXd::Identity(r, r);
  for (std::size_t a = 0; a < up->cols.size(); ++a)
    cap += up->v.row(a).transpose() * up->z.row(up->cols[a]);
  up->capacitance.compute(cap);
  return up;
}

}  // namespace

namespace {
// glibc serves UMFPACK's large blocks by mmap and unmaps them on free, so every factorisation
// page-faults its memory in afresh: 9 s of system and ~10 s of user CPU of 56 s for q1 at
// N = 1400 (bench/README.md, "Static solver"). Keep freed memory in the heap instead
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

bool LuFactor::factorize(const SparseMatrix& k) {
  Impl& m = *impl_;
  m.full.reset();
  m.update.reset();
  m.preconditioner.reset();
  m.deferred = false;
  m.singular = false;
  det_sign_ = 0;
  log10_det_ = -INFINITY;
  symbolic_reused_ = false;
  if (k.rows() == 0) {
    det_sign_ = 1;
    log10_det_ = 0.0;
    return true;
  }
  if (m.reuse.krylov) {
    for (const auto& base : base_factors())
      if (base->k.rows() == k.rows()) {
        m.preconditioner = base;  // the most recent one of this size
        break;
      }
    if (m.preconditioner) {
      m.k = k;
      m.k.makeCompressed();
      m.deferred = true;
      symbolic_reused_ = true;
      ++lu_statistics().deferred;
      return true;
    }
  } else if (m.reuse.low_rank) {
    SparseMatrix kc = k;
    kc.makeCompressed();
    // The recent factorisation from which k differs in the fewest columns.
    std::shared_ptr<const NumericLu> best;
    std::vector<int> best_cols, cols;
    for (const auto& base : base_factors()) {
      if (base->k.rows() != kc.rows()) continue;
      const int limit = best ? static_cast<int>(best_cols.size()) : m.reuse.max_columns;
      if (!changed_columns(kc, base->k, limit, cols)) continue;
      if (!best || cols.size() < best_cols.size()) {
        best = base;
        best_cols = cols;
      }
    }
    if (best && best_cols.empty()) {  // the same matrix
      m.full = best;
    } else if (best) {
      m.update = low_rank_update(kc, best, best_cols, m.reuse.max_rank);
      if (!m.update) ++lu_statistics().too_many;
    } else if (!base_factors().empty()) {
      ++lu_statistics().too_many;
    }
    if (m.full || m.update) {
      symbolic_reused_ = true;
      if (m.full) {
        det_sign_ = m.full->sign;
        log10_det_ = m.full->log10_det;
        return true;
      }
      ++lu_statistics().low_rank;
      lu_statistics().rank_sum += m.update->u.cols();
      const Eigen::MatrixXd& lu = m.update->capacitance.matrixLU();
      int sign = m.update->base->sign *
                 static_cast<int>(m.update->capacitance.permutationP().determinant());
      double log10_det = m.update->base->log10_det;
      for (Eigen::Index i = 0; i < lu.rows(); ++i) {
        if (lu(i, i) == 0.0 || !std::isfinite(lu(i, i))) return false;
        if (lu(i, i) < 0.0) sign = -sign;
        log10_det += std::log10(std::abs(lu(i, i)));
      }
      m.k = std::move(kc);
      det_sign_ = sign;
      log10_det_ = log10_det;
      return true;
    }
  }
  auto lu = std::make_shared<NumericLu>();
  lu->k = k;
  lu->k.makeCompressed();
  if (!factorize_numeric(*lu, symbolic_reused_)) return false;
  det_sign_ = lu->sign;
  log10_det_ = lu->log10_det;
  m.full = lu;
  if (m.reuse.low_rank || m.reuse.krylov) remember_base(std::move(lu));
  return true;
}

bool LuFactor::factorise_deferred() const {
  Impl& m = *impl_;
  if (!m.deferred) return !m.singular;
  m.deferred = false;
  m.preconditioner.reset();
  ++lu_statistics().deferred_factorised;
  auto lu = std::make_shared<NumericLu>();
  lu->k = std::move(m.k);
  bool reused = false;
  if (!factorize_numeric(*lu, reused)) {
    m.singular = true;
    det_sign_ = 0;
    log10_det_ = -INFINITY;
    return false;
  }
  det_sign_ = lu->sign;
  log10_det_ = lu->log10_det;
  m.full = lu;
  remember_base(std::move(lu));
  return true;
}

int LuFactor::determinant_sign() const {
  factorise_deferred();
  return det_sign_;
}

double LuFactor::log10_abs_determinant() const {
  factorise_deferred();
  return log10_det_;
}

bool LuFactor::factorised() const { return !impl_->deferred; }

namespace {
// x = K^-1 b with one step of iterative refinement against K itself.
Eigen::VectorXd refined(const LowRankUpdate& up, const SparseMatrix& k, const Eigen::VectorXd& b,
                        bool transposed) {
  Eigen::VectorXd x = up.apply(b, transposed);
  const Eigen::VectorXd r =
      transposed ? Eigen::VectorXd(b - k.transpose() * x) : Eigen::VectorXd(b - k * x);
  return x + up.apply(r, transposed);
}
}  // namespace

namespace {
// GMRES with the deferred factorisation's preconditioner; false when over the bound.
bool krylov_solve(const SparseMatrix& k, const NumericLu& preconditioner, const LuReuse& reuse,
                  const Eigen::VectorXd& b, bool transposed, Eigen::VectorXd& x) {
  LuStatistics& statistics = lu_statistics();
  const double t0 = thread_seconds();
  int iterations = 0;
  const bool converged = gmres(k, preconditioner, b, transposed, reuse.krylov_tolerance,
                               reuse.max_krylov_iterations, x, iterations);
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
    if (krylov_solve(m.k, *m.preconditioner, m.reuse, b, transposed, x)) return x;
    if (!factorise_deferred()) return not_a_solution(b.size());
  }
  if (m.update) return refined(*m.update, m.k, b, transposed);
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
