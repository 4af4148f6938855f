#include "static/umfpack_copy.hpp"

#include <stdexcept>

#include <umfpack.h>

#include "static/numeric_lu.hpp"

namespace granstab::statics {

bool UmfpackCopy::assign(void* numeric, int n) {
  int lnz = 0, unz = 0, rows = 0, columns = 0, udiag = 0;
  if (umfpack_di_get_lunz(&lnz, &unz, &rows, &columns, &udiag, numeric) != UMFPACK_OK ||
      rows != n || columns != n)
    return false;
  n_ = n;
  row_start_.resize(n + 1);
  column_.resize(lnz);
  value_.resize(lnz);
  row_of_pivot_.resize(n);
  std::vector<double> row_scale(n);
  int do_recip = 0;
  if (umfpack_di_get_numeric(row_start_.data(), column_.data(), value_.data(), nullptr, nullptr,
                             nullptr, row_of_pivot_.data(), nullptr, nullptr, &do_recip,
                             row_scale.data(), numeric) != UMFPACK_OK)
    return false;
  multiply_by_scale_ = do_recip != 0;
  pivot_row_scale_.resize(n);
  for (int k = 0; k < n; ++k) pivot_row_scale_[k] = row_scale[row_of_pivot_[k]];
  return true;
}

void UmfpackCopy::solve(void* numeric, const double* b, double* x) const {
  thread_local std::vector<double> y;
  thread_local std::vector<int> wi;
  thread_local std::vector<double> w;
  // L y = P R b by rows. y starts at zero, so the stored unit diagonal subtracts 1 * 0.
  y.assign(n_, 0.0);
  for (int k = 0; k < n_; ++k) {
    const double bk = b[row_of_pivot_[k]];
    double s = multiply_by_scale_ ? bk * pivot_row_scale_[k] : bk / pivot_row_scale_[k];
    for (int p = row_start_[k]; p < row_start_[k + 1]; ++p) s -= value_[p] * y[column_[p]];
    y[k] = s;
  }
  // U Q^T x = y: UMFPACK's own backward solve.
  wi.resize(n_);
  w.resize(static_cast<std::size_t>(n_));
  double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
  umfpack_control(control);
  if (umfpack_di_wsolve(UMFPACK_U_Qt, nullptr, nullptr, nullptr, x, y.data(), numeric, control,
                        info, wi.data(), w.data()) != UMFPACK_OK)
    throw std::runtime_error("UMFPACK solve failed");
}

}  // namespace granstab::statics
