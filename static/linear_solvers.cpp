#include "static/linear_solvers.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/CholmodSupport>
#include <umfpack.h>

namespace granstab::statics {

struct SymmetricFactor::Impl {
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt;
};

SymmetricFactor::SymmetricFactor() : impl_(std::make_unique<Impl>()) {
  impl_->llt.cholmod().print = 0;  // CHOLMOD writes warnings to stdout otherwise (DEPS.md #3)
}
SymmetricFactor::~SymmetricFactor() = default;

bool SymmetricFactor::factorize(const SparseMatrix& k) {
  impl_->llt.compute(k);
  // NumericalIssue is CHOLMOD_NOT_POSDEF: the factor is unusable (DEPS.md #2).
  return impl_->llt.info() == Eigen::Success;
}

Eigen::VectorXd SymmetricFactor::solve(const Eigen::VectorXd& b) const {
  return impl_->llt.solve(b);
}

struct LuFactor::Impl {
  SparseMatrix k;  // compressed copy: UMFPACK keeps pointers to it between calls
  void* numeric = nullptr;
  ~Impl() {
    if (numeric) umfpack_di_free_numeric(&numeric);
  }
};

namespace {

void umfpack_control(double* control) {
  umfpack_di_defaults(control);
  control[UMFPACK_PRL] = 0;
}

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
    const Eigen::Index nnz = k.nonZeros();
    for (std::size_t e = 0; e < entries_.size(); ++e) {
      Entry& x = entries_[e];
      if (x.n != n || static_cast<Eigen::Index>(x.row.size()) != nnz) continue;
      if (!std::equal(x.col.begin(), x.col.end(), k.outerIndexPtr()) ||
          !std::equal(x.row.begin(), x.row.end(), k.innerIndexPtr()))
        continue;
      std::rotate(entries_.begin(), entries_.begin() + e, entries_.begin() + e + 1);  // most recent first
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
    x.n = n;
    x.col.assign(k.outerIndexPtr(), k.outerIndexPtr() + n + 1);
    x.row.assign(k.innerIndexPtr(), k.innerIndexPtr() + nnz);
    x.symbolic = symbolic;
    entries_.insert(entries_.begin(), std::move(x));
    return symbolic;
  }

 private:
  static constexpr std::size_t capacity = 4;
  struct Entry {
    int n = 0;
    std::vector<int> col, row;
    void* symbolic = nullptr;
  };
  std::vector<Entry> entries_;
};

SymbolicCache& symbolic_cache() {
  thread_local SymbolicCache cache;
  return cache;
}

}  // namespace

LuFactor::LuFactor() : impl_(std::make_unique<Impl>()) {}
LuFactor::~LuFactor() = default;

bool LuFactor::factorize(const SparseMatrix& k) {
  Impl& m = *impl_;
  if (m.numeric) umfpack_di_free_numeric(&m.numeric);
  det_sign_ = 0;
  log10_det_ = -INFINITY;
  symbolic_reused_ = false;
  m.k = k;
  m.k.makeCompressed();
  const int n = static_cast<int>(m.k.rows());
  if (n == 0) {
    det_sign_ = 1;
    log10_det_ = 0.0;
    return true;
  }
  double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
  umfpack_control(control);
  void* symbolic = symbolic_cache().get(m.k, control, symbolic_reused_);
  if (!symbolic) return false;
  const int status = umfpack_di_numeric(m.k.outerIndexPtr(), m.k.innerIndexPtr(),
                                        m.k.valuePtr(), symbolic, &m.numeric, control, info);
  if (status != UMFPACK_OK) {  // includes UMFPACK_WARNING_singular_matrix
    if (m.numeric) umfpack_di_free_numeric(&m.numeric);
    return false;
  }
  // Mantissa and base-10 exponent: det K overflows a double for any realistic network.
  double mantissa = 0.0, exponent = 0.0;
  if (umfpack_di_get_determinant(&mantissa, &exponent, m.numeric, info) != UMFPACK_OK)
    return false;
  det_sign_ = mantissa > 0.0 ? 1 : (mantissa < 0.0 ? -1 : 0);
  log10_det_ = std::log10(std::abs(mantissa)) + exponent;
  return det_sign_ != 0;
}

namespace {
Eigen::VectorXd umfpack_solve(int sys, const SparseMatrix& k, void* numeric,
                              const Eigen::VectorXd& b) {
  if (!numeric) throw std::logic_error("LuFactor::solve without a successful factorisation");
  Eigen::VectorXd x(b.size());
  double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
  umfpack_control(control);
  const int status = umfpack_di_solve(sys, k.outerIndexPtr(), k.innerIndexPtr(), k.valuePtr(),
                                      x.data(), b.data(), numeric, control, info);
  if (status != UMFPACK_OK) throw std::runtime_error("UMFPACK solve failed");
  return x;
}
}  // namespace

Eigen::VectorXd LuFactor::solve(const Eigen::VectorXd& b) const {
  if (b.size() == 0) return b;
  return umfpack_solve(UMFPACK_A, impl_->k, impl_->numeric, b);
}

Eigen::VectorXd LuFactor::solve_transpose(const Eigen::VectorXd& b) const {
  if (b.size() == 0) return b;
  return umfpack_solve(UMFPACK_At, impl_->k, impl_->numeric, b);
}

Reduction make_reduction(const std::vector<char>& keep) {
  Reduction r;
  r.full_to_reduced.assign(keep.size(), -1);
  for (std::size_t i = 0; i < keep.size(); ++i) {
    if (!keep[i]) continue;
    r.full_to_reduced[i] = static_cast<int>(r.reduced_to_full.size());
    r.reduced_to_full.push_back(static_cast<int>(i));
  }
  return r;
}

SparseMatrix reduce(const SparseMatrix& k, const Reduction& r) {
  const int n = static_cast<int>(r.reduced_to_full.size());
  if (n == k.rows()) return k;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(k.nonZeros());
  for (int col = 0; col < k.outerSize(); ++col) {
    const int rc = r.full_to_reduced[col];
    if (rc < 0) continue;
    for (SparseMatrix::InnerIterator it(k, col); it; ++it) {
      const int rr = r.full_to_reduced[it.row()];
      if (rr >= 0) t.emplace_back(rr, rc, it.value());
    }
  }
  SparseMatrix out(n, n);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

Eigen::VectorXd reduce(const Eigen::VectorXd& v, const Reduction& r) {
  Eigen::VectorXd out(r.reduced_to_full.size());
  for (std::size_t i = 0; i < r.reduced_to_full.size(); ++i) out[i] = v[r.reduced_to_full[i]];
  return out;
}

Eigen::VectorXd expand(const Eigen::VectorXd& v, const Reduction& r, int full_size) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(full_size);
  for (std::size_t i = 0; i < r.reduced_to_full.size(); ++i) out[r.reduced_to_full[i]] = v[i];
  return out;
}

}  // namespace granstab::statics
