// CHOLMOD's LL^T for the symmetric positive definite systems (SymmetricFactor,
// linear_solvers.hpp): the Hill indicator's shift-invert solves. Simplicial, not supernodal: the
// supernodes of these 2D contact networks are small, and with Debian's reference BLAS the
// supernodal factorisation took 2-7x longer (600 against 85 us at 282 dofs, 12.4 against 4.3 ms
// at 3819, 71 against 35 ms at 15276; bench/README.md). A simplicial LL^T still stops at the
// first non-positive pivot with CHOLMOD_NOT_POSDEF (DEPS.md #1 is about the LDL^T of auto mode).
#include <Eigen/CholmodSupport>

#include "static/linear_solvers.hpp"

namespace granstab::statics {

struct SymmetricFactor::Impl {
  Eigen::CholmodSimplicialLLT<SparseMatrix, Eigen::Lower> llt;
  SparsityPattern analysed;  // the pattern analysed last
};

SymmetricFactor::SymmetricFactor() : impl_(std::make_unique<Impl>()) {
  impl_->llt.cholmod().print = 0;  // CHOLMOD writes warnings to stdout otherwise (DEPS.md #3)
}
SymmetricFactor::~SymmetricFactor() = default;

bool SymmetricFactor::factorize(const SparseMatrix& k) {
  Impl& m = *impl_;
  SparseMatrix kc = k;
  kc.makeCompressed();
  if (!m.analysed.same_as(kc)) {
    m.llt.analyzePattern(kc);
    m.analysed.assign(kc);
  }
  m.llt.factorize(kc);
  // NumericalIssue is CHOLMOD_NOT_POSDEF: the factor is unusable (DEPS.md #2).
  return impl_->llt.info() == Eigen::Success;
}

Eigen::VectorXd SymmetricFactor::solve(const Eigen::VectorXd& b) const {
  return impl_->llt.solve(b);
}

Eigen::MatrixXd SymmetricFactor::solve_columns(const Eigen::MatrixXd& b) const {
  return impl_->llt.solve(b);
}

}  // namespace granstab::statics
