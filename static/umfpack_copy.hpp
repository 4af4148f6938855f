#pragma once
// UMFPACK's L factor copied by rows, for the unrefined solves of a factor that is solved with
// many times (GMRES preconditioners, the Arnoldi operator, low-rank updates' bases). Internal to
// static/.
#include <vector>

namespace granstab::statics {

// P R K Q = L U (UMFPACK). UMFPACK keeps L by columns, in chains of patterns that its forward
// solve rebuilds column by column while it scatters into the solution. The copy holds L by rows
// (umfpack_di_get_numeric, increasing columns) and gathers: row i gets UMFPACK's operations in
// UMFPACK's order, so a solve gives the same bits (test LuCopy.*). U stays UMFPACK's, which keeps
// it by rows already. At 15240 dofs: 3.1 -> 2.0 ms per solve, 6 ms for the copy
// (docs/static.md, "Performance").
class UmfpackCopy {
 public:
  // Copies L, P and R of `numeric` (n rows). False when UMFPACK refuses.
  bool assign(void* numeric, int n);
  // x = K^-1 b without refinement, as umfpack_di_solve(UMFPACK_A) with UMFPACK_IRSTEP = 0
  // computes it (x and b of n entries, distinct).
  void solve(void* numeric, const double* b, double* x) const;

 private:
  int n_ = 0;
  std::vector<int> row_start_, column_;  // L by rows, unit diagonal included
  std::vector<double> value_;
  std::vector<int> row_of_pivot_;        // P: pivot k's row of K
  std::vector<double> pivot_row_scale_;  // R's factor of that row
  bool multiply_by_scale_ = true;        // else divide (UMFPACK's do_recip)
};

}  // namespace granstab::statics
