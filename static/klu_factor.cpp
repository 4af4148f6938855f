// KLU for the small systems (LuReuse::klu_max_dofs): its symbolic analyses reused per sparsity
// pattern, numeric factorisations refilled into spare factors of the pattern (klu_refactor), the
// determinant's sign and magnitude from its factors, and the iterative refinement that KLU leaves
// to its caller. UMFPACK's numeric factorisation carries a fixed cost of a few hundred
// microseconds that dominates below ~1000 dofs (docs/static.md, "Performance").
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "static/numeric_lu.hpp"

namespace granstab::statics {
namespace {

// +1 for an even permutation, -1 for an odd one (the parity of its even-length cycles).
int permutation_sign(const int* p, int n, std::vector<char>& seen) {
  seen.assign(static_cast<std::size_t>(n), 0);
  int sign = 1;
  for (int i = 0; i < n; ++i) {
    int length = 0;
    for (int j = i; !seen[j]; j = p[j]) {
      seen[j] = 1;
      ++length;
    }
    if (length > 0 && length % 2 == 0) sign = -sign;
  }
  return sign;
}

// max_i |r_i| / (|K| |x| + |b|)_i over the rows where the denominator is not zero (transposed:
// |K|^T): the componentwise backward error of x (UMFPACK's omega1).
double backward_error(const SparseMatrix& k, bool transposed, const Eigen::VectorXd& b,
                      const Eigen::VectorXd& x, Eigen::VectorXd& r) {
  r = transposed ? Eigen::VectorXd(b - k.transpose() * x) : Eigen::VectorXd(b - k * x);
  const Eigen::VectorXd scale = abs_product(k, x, transposed) + b.cwiseAbs();
  double omega = 0.0;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    if (scale[i] > 0.0) omega = std::max(omega, std::abs(r[i]) / scale[i]);
  }
  return omega;
}

}  // namespace

klu_common& klu_settings() {
  thread_local klu_common common = [] {
    klu_common c;
    klu_defaults(&c);  // AMD ordering, BTF, partial pivoting with diagonal preference (0.001)
    return c;
  }();
  return common;
}

AnalysisCache<KluAnalysis>& klu_analyses() {
  // The settings first: thread_locals are destroyed in the reverse order of their construction,
  // and the analyses (with their spare factors) are freed through them.
  klu_settings();
  thread_local AnalysisCache<KluAnalysis> cache;
  return cache;
}

void forget_klu_analyses() { klu_analyses().clear(); }

// KLU factorises L U = P (R \ A) Q, L unit lower triangular, R the (positive) row scales, so
// det A = sign(P) sign(Q) prod(R) prod(diag U).
bool factorize_klu(NumericLu& lu, bool& reused) {
  klu_common& common = klu_settings();
  lu.analysis = klu_analyses().get(lu.k(), 0.0, reused, [&common](const SparseMatrix& k) {
    auto analysis = std::make_shared<KluAnalysis>();
    // KLU reads its inputs only; its interface is not const-qualified.
    analysis->symbolic =
        klu_analyze(static_cast<int>(k.rows()), const_cast<int*>(k.outerIndexPtr()),
                    const_cast<int*>(k.innerIndexPtr()), &common);
    return analysis->symbolic ? analysis : std::shared_ptr<KluAnalysis>();
  });
  if (!lu.analysis) return false;
  klu_symbolic* symbolic = lu.analysis->symbolic;
  int* const ap = const_cast<int*>(lu.k().outerIndexPtr());
  int* const ai = const_cast<int*>(lu.k().innerIndexPtr());
  double* const ax = const_cast<double*>(lu.k().valuePtr());
  // A spare's pivot order first. It is kept while the smallest pivot stays as large against the
  // largest (KLU's rcond, the cheap one) as when partial pivoting chose the order, within a factor
  // refactor_rcond: a pivot that shrank makes its column's multipliers grow. Otherwise (or on a
  // zero pivot) KLU pivots afresh.
  constexpr double refactor_rcond = 0.01;
  KluAnalysis::Spare spare;
  if (lu.analysis->take_spare(spare)) {
    if (klu_refactor(ap, ai, ax, symbolic, spare.numeric, &common) && common.status == KLU_OK &&
        klu_rcond(symbolic, spare.numeric, &common) &&
        common.rcond >= refactor_rcond * spare.rcond) {
      lu.klu = spare.numeric;
      lu.klu_rcond = spare.rcond;
      ++lu_statistics().refactorisations;
    } else {
      klu_free_numeric(&spare.numeric, &common);
    }
  }
  if (!lu.klu) {
    lu.klu = klu_factor(ap, ai, ax, symbolic, &common);
    // A zero pivot: KLU frees the partial factors and returns none (halt_if_singular).
    if (!lu.klu || common.status != KLU_OK) return false;
    if (!klu_rcond(symbolic, lu.klu, &common)) return false;
    lu.klu_rcond = common.rcond;
  }
  const int n = static_cast<int>(lu.k().rows());
  const double* u = static_cast<const double*>(lu.klu->Udiag);
  thread_local std::vector<char> seen;
  int sign = permutation_sign(lu.klu->Pnum, n, seen) * permutation_sign(symbolic->Q, n, seen);
  for (int i = 0; i < n; ++i) {
    if (u[i] == 0.0 || !std::isfinite(u[i])) return false;
    if (u[i] < 0.0) sign = -sign;
  }
  lu.sign = sign;
  return true;
}

double NumericLu::log10_abs_det() const {
  if (!klu) return umfpack_log10_det;
  const int n = static_cast<int>(k().rows());
  const double* u = static_cast<const double*>(klu->Udiag);
  double log10_det = 0.0;
  for (int i = 0; i < n; ++i) {
    log10_det += std::log10(std::abs(u[i]));
    if (klu->Rs) log10_det += std::log10(klu->Rs[i]);
  }
  return log10_det;
}

void NumericLu::solve_columns(int sys, Eigen::MatrixXd& x) const {
  const int n = static_cast<int>(x.rows()), nrhs = static_cast<int>(x.cols());
  if (nrhs == 0) return;
  if (!klu) {
    for (int c = 0; c < nrhs; ++c) x.col(c) = solve(sys, Eigen::VectorXd(x.col(c)), false);
    return;
  }
  // KLU works in chunks of up to four columns, with every column's operations those of a
  // one-column solve in the same order: the same bits (test
  // LuLowRank.SolvesOfSeveralColumnsAreTheBitsOfOneColumnSolves).
  klu_symbolic* symbolic = analysis->symbolic;
  const int ok = sys == UMFPACK_At ? klu_tsolve(symbolic, klu, n, nrhs, x.data(), &klu_settings())
                                   : klu_solve(symbolic, klu, n, nrhs, x.data(), &klu_settings());
  if (!ok) throw std::runtime_error("KLU solve failed");
  lu_statistics().unrefined_solves += nrhs;
}

// With refine, up to 2 steps of iterative refinement against k, as UMFPACK's solve does: stop
// when the componentwise backward error is at round-off, or when a step does not halve it (then
// the better of the last two solutions is kept).
Eigen::VectorXd NumericLu::solve_klu(bool transposed, const Eigen::VectorXd& b, bool refine) const {
  klu_symbolic* symbolic = analysis->symbolic;
  const int n = static_cast<int>(b.size());
  const auto apply_inverse = [&](Eigen::VectorXd& v) {
    const int ok = transposed ? klu_tsolve(symbolic, klu, n, 1, v.data(), &klu_settings())
                              : klu_solve(symbolic, klu, n, 1, v.data(), &klu_settings());
    if (!ok) throw std::runtime_error("KLU solve failed");
  };
  LuStatistics& statistics = lu_statistics();
  Eigen::VectorXd x = b;
  if (!refine) {
    apply_inverse(x);
    ++statistics.unrefined_solves;
    return x;
  }
  const double t0 = thread_seconds();
  apply_inverse(x);
  Eigen::VectorXd r;
  double omega = backward_error(k(), transposed, b, x, r);
  for (int step = 0; step < 2 && omega > std::numeric_limits<double>::epsilon(); ++step) {
    apply_inverse(r);
    Eigen::VectorXd next = x + r;
    const double next_omega = backward_error(k(), transposed, b, next, r);
    const bool halved = next_omega <= 0.5 * omega;
    if (next_omega < omega) {
      x = std::move(next);
      omega = next_omega;
    }
    if (!halved) break;
  }
  ++statistics.solves;
  statistics.solve_seconds += thread_seconds() - t0;
  return x;
}

}  // namespace granstab::statics
