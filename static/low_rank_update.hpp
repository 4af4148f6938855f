#pragma once
// Low-rank (Woodbury) updates of a recent LU: their own algebra, apart from when to use one.
#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "static/numeric_lu.hpp"

namespace granstab::statics {

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
      zt = Eigen::MatrixXd::Zero(b.size(), r);
      for (Eigen::Index c = 0; c < r; ++c)
        for (std::size_t a = 0; a < cols.size(); ++a) zt(cols[a], c) = v(a, c);
      base->solve_columns(UMFPACK_At, zt);
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

// The columns in which k and k0 (same size, compressed) differ in value; false when more than
// limit. An entry stored in one and absent from the other counts as a difference unless it is 0.
bool changed_columns(const SparseMatrix& k, const SparseMatrix& k0, int limit,
                     std::vector<int>& cols);

// K = K0 + (K - K0) with the change confined to cols: a rank-revealing QR of the changed block
// gives U V^T. Null when the change is too large for an update to pay.
std::unique_ptr<LowRankUpdate> low_rank_update(const SparseMatrix& k,
                                               std::shared_ptr<const NumericLu> base,
                                               const std::vector<int>& cols, int max_rank);

// x = K^-1 b with one step of iterative refinement against K itself.
Eigen::VectorXd refined(const LowRankUpdate& up, const SparseMatrix& k, const Eigen::VectorXd& b,
                        bool transposed);

}  // namespace granstab::statics
