#pragma once
// The Hill indicator of STATIC.md §S3.4 (c): the smallest eigenvalue of (K + K^T)/2. A value <= 0
// means the second-order work can vanish; it is reported along the curve, not a failure.
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "static/linear_solvers.hpp"
#include "static/tangent.hpp"

namespace granstab::statics {

struct HillResult {
  bool ok = false;
  double min_eigenvalue = 0.0;
  Eigen::VectorXd mode;  // unit eigenvector
};

// Shift-invert Lanczos (Spectra) with a shift below the spectrum, checked by a CHOLMOD LL^T that
// succeeds (every solve positive definite); the dense eigensolver for tiny systems or when that
// fails. `previous` (the result at the state before, along a load path) warm-starts it: the shift
// just below its eigenvalue and its mode as the start vector, so one factorisation and a few
// Lanczos solves usually settle it. The eigenvalue agrees with the cold and the dense solve to the
// Lanczos tolerance (1e-10 relative); it is a logged indicator, no decision depends on it.
HillResult hill_indicator(const SparseMatrix& k, const HillResult* previous = nullptr);

// S = (K + K^T)/2: the matrix every inertia count and the Hill indicator read.
SparseMatrix symmetric_part(const SparseMatrix& k);

// Negative eigenvalues of the symmetric matrix s, exactly: the negative pivots of its LDL^T
// (Sylvester's law of inertia). -1 when the factorisation meets a zero pivot. With a count > 0
// and `witness`, also a vector x with x^T s x < 0 (from the first negative pivot), when its sign
// is beyond round-off. By value: a temporary S (symmetric_part's) is factorised without a copy.
int negative_eigenvalue_count_symmetric(SparseMatrix s, Eigen::VectorXd* witness = nullptr);

// Whether x^T k x < 0 beyond its round-off: then (k + k^T)/2 is indefinite (x^T k x is x^T S x).
bool proves_indefinite(const SparseMatrix& k, const Eigen::VectorXd& x);

// The §S3.4 (b) criterion made robust to an even number of eigenvalues crossing zero at once
// (det K keeps its sign then): the real negative eigenvalues of K.
inline constexpr int indefinite_uncounted = -2;
struct NegativeEigenvalues {
  bool ok = false;
  // Negative eigenvalues of S = (K + K^T)/2 (LDL^T inertia); indefinite_uncounted when a witness
  // showed S indefinite and the inertia was not computed.
  int symmetric = -1;
  Eigen::VectorXd witness;             // x with x^T S x < 0 where one is known (S indefinite)
  int real = -1;                       // real negative eigenvalues of K
  std::vector<Eigen::VectorXd> modes;  // their (real) eigenvectors, unit length
  // Smallest |eigenvalue| among those computed (NaN when none were: the symmetric part positive
  // definite). The step control grows steps only while it stays away from 0 (stable_span,
  // stability_check.cpp).
  double nearest_zero = std::numeric_limits<double>::quiet_NaN();
  // The Arnoldi's Ritz vectors folded into one real vector (empty when none ran): the start of the
  // next state's Arnoldi, whose eigenvalues nearest 0 moved little since.
  Eigen::VectorXd arnoldi_start;
};
// If (K + K^T)/2 has no negative eigenvalue, neither has K (x^T K x = x^T S x > 0 for every real
// eigenvector x): real = 0 at the cost of one LDL^T. Otherwise the eigenvalues of K nearest 0
// (shift-invert Arnoldi, Spectra, with lu = the LU of K, or dense when lu is null or Arnoldi
// fails and K is small) are counted: an eigenvalue that crossed 0 since the last state is near 0.
// A `witness` (say the last state's) that proves S indefinite spares the LDL^T: the Arnoldi runs
// as it would on an inertia > 0, and the caller counts the inertia where it needs it. A `start`
// (the last state's arnoldi_start) starts the Arnoldi instead of Spectra's fixed vector: any
// start finds the same eigenvalues, a near one in fewer solves.
NegativeEigenvalues negative_eigenvalues(const SparseMatrix& k, const LuFactor* lu,
                                         const Eigen::VectorXd* witness = nullptr,
                                         const Eigen::VectorXd* start = nullptr);

// Counters of this thread's negative_eigenvalues work (bench/static).
struct NegativeEigenvalueStatistics {
  long calls = 0;
  long witnessed = 0;          // calls whose witness spared the LDL^T
  long arnoldi = 0;            // calls that ran the Arnoldi iteration (indefinite symmetric part)
  long arnoldi_solves = 0;     // solves with the LU of K in those
  long arnoldi_confirmed = 0;  // calls whose screening found a value that may count (rerun)
  long dense = 0;              // calls that ended in the dense eigensolver
  double symmetric_seconds = 0.0;  // the symmetric part's inertia (thread CPU)
  double arnoldi_seconds = 0.0;    // Arnoldi incl. its solves (thread CPU)
};
NegativeEigenvalueStatistics& negative_eigenvalue_statistics();

}  // namespace granstab::statics
