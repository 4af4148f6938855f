// Low-rank (Woodbury) updates of a recent LU: their own algebra, apart from when to use one.
#include "static/low_rank_update.hpp"

namespace granstab::statics {

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

// K = K0 + (K - K0) with the change confined to cols: a rank-revealing QR of the changed block
// gives U V^T. Null when the change is too large for an update to pay.
std::unique_ptr<LowRankUpdate> low_rank_update(const SparseMatrix& k,
                                               std::shared_ptr<const NumericLu> base,
                                               const std::vector<int>& cols, int max_rank) {
  const int n = static_cast<int>(k.rows());
  std::vector<int> row_slot(n, -1);
  std::vector<int> rows;
  std::vector<Eigen::Triplet<double>> change;  // (row, column slot, K - K0)
  const SparseMatrix& k0 = base->k();
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
  up->z = Eigen::MatrixXd::Zero(n, r);
  for (Eigen::Index c = 0; c < r; ++c)
    for (std::size_t a = 0; a < up->rows.size(); ++a) up->z(up->rows[a], c) = up->u(a, c);
  up->base->solve_columns(UMFPACK_A, up->z);
  Eigen::MatrixXd cap = Eigen::MatrixXd::Identity(r, r);
  for (std::size_t a = 0; a < up->cols.size(); ++a)
    cap += up->v.row(a).transpose() * up->z.row(up->cols[a]);
  up->capacitance.compute(cap);
  return up;
}

// x = K^-1 b with one step of iterative refinement against K itself.
Eigen::VectorXd refined(const LowRankUpdate& up, const SparseMatrix& k, const Eigen::VectorXd& b,
                        bool transposed) {
  Eigen::VectorXd x = up.apply(b, transposed);
  const Eigen::VectorXd r =
      transposed ? Eigen::VectorXd(b - k.transpose() * x) : Eigen::VectorXd(b - k * x);
  return x + up.apply(r, transposed);
}

}  // namespace granstab::statics
