#pragma once
// The Hill indicator of STATIC.md §S3.4 (c): the smallest eigenvalue of (K + K^T)/2. A value <= 0
// means the second-order work can vanish; it is reported along the curve, not a failure.
#include <Eigen/Core>

#include "static/tangent.hpp"

namespace granstab::statics {

struct HillResult {
  bool ok = false;
  double min_eigenvalue = 0.0;
  Eigen::VectorXd mode;  // unit eigenvector
};

// Dense eigensolver for small systems; otherwise shift-invert Lanczos (Spectra) with a shift below
// the spectrum found by CHOLMOD LL^T trials, so every solve is positive definite.
HillResult hill_indicator(const SparseMatrix& k);

}  // namespace granstab::statics
