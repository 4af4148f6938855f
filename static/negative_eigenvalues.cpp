// The negative-eigenvalue count of STATIC.md §S3.4 (b), declared in hill.hpp (apart from the Hill
// indicator in hill.cpp so that the two Spectra solvers compile in separate translation units).
#include <algorithm>
#include <cmath>
#include <complex>
#include <ctime>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
// GCC 12 reports a false use-after-free inside Spectra's UpperHessenbergEigen (Eigen temporaries).
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuse-after-free"
#endif
#include <Spectra/GenEigsRealShiftSolver.h>
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12
#pragma GCC diagnostic pop
#endif

#include "static/hill.hpp"
#include "static/linear_solvers.hpp"

namespace granstab::statics {
namespace {

double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Spectra's real-shift operator for K with the shift 0 only: y = K^-1 x with the LU of K.
class InverseOperator {
 public:
  using Scalar = double;
  InverseOperator(const LuFactor& lu, Eigen::Index n) : lu_(lu), n_(n) {}
  Eigen::Index rows() const { return n_; }
  Eigen::Index cols() const { return n_; }
  void set_shift(const Scalar&) {}
  void perform_op(const Scalar* x_in, Scalar* y_out) const {
    ++negative_eigenvalue_statistics().arnoldi_solves;
    // Unrefined: Arnoldi converges on the inverse of the computed factors as well (a backward-
    // stable perturbation of K) in as many solves and with the same counts on the shipped samples;
    // UMFPACK's refinement made each solve 5-8 times as expensive (2.9 against 0.39 ms per solve
    // at N = 1400; docs/notes/2026-12-02-static-speed-measurements.md).
    Eigen::Map<Eigen::VectorXd>(y_out, n_) =
        lu_.solve_unrefined(Eigen::Map<const Eigen::VectorXd>(x_in, n_));
  }

 private:
  const LuFactor& lu_;
  Eigen::Index n_;
};

bool real_negative(const std::complex<double>& z) {
  return z.real() < 0.0 && std::abs(z.imag()) <= 1e-10 * std::abs(z);
}

bool dense_real_negative(const SparseMatrix& k, NegativeEigenvalues& out) {
  Eigen::EigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(k), true);
  if (eig.info() != Eigen::Success) return false;
  out.real = 0;
  out.nearest_zero = eig.eigenvalues().cwiseAbs().minCoeff();
  for (Eigen::Index i = 0; i < eig.eigenvalues().size(); ++i)
    if (real_negative(eig.eigenvalues()[i])) {
      ++out.real;
      out.modes.push_back(eig.eigenvectors().col(i).real().normalized());
    }
  return true;
}

// Dense solves stay cheap up to this size (a few tenths of a second).
constexpr int dense_limit = 1500;

// The Arnoldi's two tolerances (Spectra's: each Ritz pair's residual against its value of K^-1).
// A state is first screened at 1e-4. A real negative eigenvalue among those found keeps the sign
// of its Ritz value's real part at any tolerance well below 1, so the screening sees it. If no
// value found has a negative real part, nothing can count, and nearest_zero only feeds the step
// control, where steps are limited by changes of at least 1/64 of it per dq (stable_span,
// max_step_factor): an error of 1e-4 of it is immaterial. Otherwise the run at 1e-10 decides,
// from the same start: the count, and the modes whose signs the branch test reads. On series A
// at mu = 0.25 no state needed it; the screening at 1e-6 took the Arnoldi from 31157 to 22262
// solves, at 1e-4 to 19140, with the same curve (docs/notes/2026-12-06-bench-static-history.md,
// docs/notes/2026-12-06-arnoldi-screening.md).
constexpr double screening_tolerance = 1e-4;
constexpr double counting_tolerance = 1e-10;

struct ArnoldiRun {
  bool ok = false;
  Eigen::VectorXcd values;   // eigenvalues of K nearest 0
  Eigen::MatrixXcd vectors;  // their eigenvectors
};

// Shift-invert Arnoldi for the nev eigenvalues of K nearest 0, from start (Spectra's fixed vector
// when null).
ArnoldiRun arnoldi(InverseOperator& op, int nev, int ncv, const Eigen::VectorXd* start,
                   double tolerance) {
  Spectra::GenEigsRealShiftSolver<InverseOperator> eigs(op, nev, ncv, 0.0);
  if (start)
    eigs.init(start->data());
  else
    eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, tolerance);
  ArnoldiRun run;
  run.ok = eigs.info() == Spectra::CompInfo::Successful;
  if (run.ok) {
    run.values = eigs.eigenvalues();
    run.vectors = eigs.eigenvectors();
  }
  return run;
}

}  // namespace

NegativeEigenvalueStatistics& negative_eigenvalue_statistics() {
  thread_local NegativeEigenvalueStatistics statistics;
  return statistics;
}

namespace {

// S = (K + K^T)/2 on K's pattern, from the value index of each entry's mirror. Its own function:
// a named matrix returned next to another return statement would be copied (no move constructor).
SparseMatrix mirrored_mean(const SparseMatrix& k, const std::vector<int>& mirror) {
  SparseMatrix s = with_structure_of(k);
  const double* a = k.valuePtr();
  double* v = s.valuePtr();
  for (std::size_t p = 0; p < mirror.size(); ++p) v[p] = 0.5 * (a[p] + a[mirror[p]]);
  return s;
}

}  // namespace

SparseMatrix symmetric_part(const SparseMatrix& k) {
  // A structurally symmetric K (the fixed pattern's, reduced or not) gives S on its own pattern:
  // each value 0.5 (K_ij + K_ji), the sum's values in the sum's order, from the position of each
  // entry's mirror, kept per pattern. Otherwise the general sum (its pattern is the union).
  struct Mirrors {
    SparsityPattern pattern;
    std::vector<int> mirror;  // value index of (j, i) for the entry (i, j); empty: not symmetric
  };
  thread_local Mirrors cache;
  if (k.isCompressed() && k.rows() == k.cols()) {
    if (!cache.pattern.same_as(k)) {
      cache.pattern.assign(k);
      cache.mirror.assign(static_cast<std::size_t>(k.nonZeros()), -1);
      // Column j's entries in row order: the mirrors of row i's entries, visited column by column,
      // are row i's entries in column order, so one cursor per column finds them all.
      std::vector<int> cursor(k.outerIndexPtr(), k.outerIndexPtr() + k.outerSize());
      bool symmetric = true;
      for (int j = 0; j < k.outerSize() && symmetric; ++j)
        for (int p = k.outerIndexPtr()[j]; p < k.outerIndexPtr()[j + 1]; ++p) {
          const int i = k.innerIndexPtr()[p];
          const int q = cursor[i]++;
          if (q >= k.outerIndexPtr()[i + 1] || k.innerIndexPtr()[q] != j) {
            symmetric = false;
            break;
          }
          cache.mirror[p] = q;
        }
      for (int i = 0; i < k.outerSize() && symmetric; ++i)
        symmetric = cursor[i] == k.outerIndexPtr()[i + 1];  // no entry of column i left unpaired
      if (!symmetric) cache.mirror.clear();
    }
    if (!cache.mirror.empty()) return mirrored_mean(k, cache.mirror);
  }
  return 0.5 * (k + SparseMatrix(k.transpose()));
}

bool proves_indefinite(const SparseMatrix& k, const Eigen::VectorXd& x) {
  if (x.size() != k.cols() || x.size() == 0) return false;
  // x^T k x summed term by term, and the sum of the terms' sizes, which bounds its round-off.
  double value = 0.0, size = 0.0;
  for (Eigen::Index j = 0; j < k.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(k, j); it; ++it) {
      const double term = x[it.index()] * it.value() * x[j];
      value += term;
      size += std::abs(term);
    }
  return value < -1e-8 * size;
}

int negative_eigenvalue_count_symmetric(SparseMatrix sc, Eigen::VectorXd* witness) {
  // The ordering and the elimination tree of the last pattern, kept: a q1 run counts the inertia
  // of many matrices with the pattern of one contact list (the fixed pattern of the tangent). The
  // analysis reads the pattern only, so the factor is the same as a fresh one's.
  struct Cache {
    Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> ldlt;
    SparsityPattern analysed;
  };
  thread_local Cache cache;
  sc.makeCompressed();
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower>& ldlt = cache.ldlt;
  if (!cache.analysed.same_as(sc)) {
    cache.analysed.clear();
    ldlt.analyzePattern(sc);
    if (ldlt.info() != Eigen::Success) return -1;
    cache.analysed.assign(sc);
  }
  ldlt.factorize(sc);
  if (ldlt.info() != Eigen::Success) return -1;
  const Eigen::VectorXd d = ldlt.vectorD();
  int count = 0;
  Eigen::Index first_negative = -1;
  for (Eigen::Index i = 0; i < d.size(); ++i) {
    if (d[i] == 0.0 || !std::isfinite(d[i])) return -1;
    if (d[i] < 0.0 && first_negative < 0) first_negative = i;
    count += d[i] < 0.0;
  }
  if (witness && first_negative >= 0) {
    // S = P^T L D L^T P: x = P^-1 L^-T e_i gives x^T S x = D_i < 0.
    Eigen::VectorXd e = Eigen::VectorXd::Zero(d.size());
    e[first_negative] = 1.0;
    const Eigen::VectorXd y = ldlt.matrixU().solve(e);
    Eigen::VectorXd x = ldlt.permutationPinv() * y;
    if (proves_indefinite(sc, x)) *witness = std::move(x);
  }
  return count;
}

NegativeEigenvalues negative_eigenvalues(const SparseMatrix& k, const LuFactor* lu,
                                         const Eigen::VectorXd* witness,
                                         const Eigen::VectorXd* start) {
  NegativeEigenvalues out;
  NegativeEigenvalueStatistics& statistics = negative_eigenvalue_statistics();
  ++statistics.calls;
  const int n = static_cast<int>(k.rows());
  if (n == 0) {
    out.ok = true;
    out.symmetric = out.real = 0;
    return out;
  }
  const double t0 = thread_seconds();
  // Not gated by a CHOLMOD LL^T: the symmetric part is indefinite in 70 % of the calls of a q1 run
  // (the LDL^T then runs anyway), and the gate doubled this part's cost at N = 1400.
  if (witness && proves_indefinite(k, *witness)) {
    ++statistics.witnessed;
    out.symmetric = indefinite_uncounted;
    out.witness = *witness;
  } else {
    out.symmetric = negative_eigenvalue_count_symmetric(symmetric_part(k), &out.witness);
  }
  const double t1 = thread_seconds();
  statistics.symmetric_seconds += t1 - t0;
  if (out.symmetric == 0) {
    out.ok = true;
    out.real = 0;
    return out;
  }
  if (lu && n > 8) {
    ++statistics.arnoldi;
    InverseOperator op(*lu, n);
    const int nev = std::min(6, n - 3);
    // From the last state's Ritz vectors a smaller Krylov space does: 14 vectors instead of 20
    // took a quarter off the solves of the main job's q1 runs
    // (docs/notes/2026-12-04-static-main-job.md).
    const bool warm = start && start->size() == n && start->norm() > 0.0;
    const int ncv = std::min(n, warm ? 2 * nev + 2 : 2 * nev + 8);
    ArnoldiRun run = arnoldi(op, nev, ncv, warm ? start : nullptr, screening_tolerance);
    if (run.ok && (run.values.real().array() < 0.0).any()) {
      // A value that may count: decided by the run of counting_tolerance from the same start.
      ++statistics.arnoldi_confirmed;
      run = arnoldi(op, nev, ncv, warm ? start : nullptr, counting_tolerance);
    }
    statistics.arnoldi_seconds += thread_seconds() - t1;
    if (run.ok) {
      out.ok = true;
      out.real = 0;
      out.nearest_zero = run.values.cwiseAbs().minCoeff();
      out.arnoldi_start = Eigen::VectorXd::Zero(n);
      for (Eigen::Index i = 0; i < run.values.size(); ++i) {
        if (real_negative(run.values[i])) {
          ++out.real;
          out.modes.push_back(run.vectors.col(i).real().normalized());
        }
        // Unequal weights, real and imaginary parts: a conjugate pair keeps both directions.
        out.arnoldi_start +=
            (run.vectors.col(i).real() + run.vectors.col(i).imag()) / double(i + 1);
      }
      return out;
    }
  }
  if (n <= dense_limit) {
    ++statistics.dense;
    out.ok = dense_real_negative(k, out);
  }
  return out;
}

}  // namespace granstab::statics
