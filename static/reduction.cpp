// The kept degrees of freedom: K, vectors and solutions restricted to them and expanded back
// (Reduction, linear_solvers.hpp).
#include "static/linear_solvers.hpp"

namespace granstab::statics {

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

// Each of these returns one named matrix on every path, so that it is built in place (NRVO):
// another return statement would make `return out` a copy, there being no move constructor.

SparseMatrix reduce(const SparseMatrix& k, const Reduction& r) {
  const int n = static_cast<int>(r.reduced_to_full.size());
  SparseMatrix out;
  if (r.keeps_all()) {
    out = k;
    return out;
  }
  // The kept columns and, in each, the kept rows in their order: no sums, the same entries as
  // building the submatrix from triplets, without the sort and the transposed copy.
  out.resize(n, n);
  out.reserve(k.nonZeros());
  for (int rc = 0; rc < n; ++rc) {
    out.startVec(rc);
    for (SparseMatrix::InnerIterator it(k, r.reduced_to_full[rc]); it; ++it) {
      const int rr = r.full_to_reduced[it.row()];
      if (rr >= 0) out.insertBack(rr, rc) = it.value();
    }
  }
  out.finalize();
  return out;
}

SparseMatrix reduce(SparseMatrix&& k, const Reduction& r) {
  SparseMatrix out;
  if (r.keeps_all())
    out.swap(k);
  else
    reduce(k, r).swap(out);  // an assignment would copy
  return out;
}

const SparseMatrix& kept_part(const SparseMatrix& k, const Reduction& r, SparseMatrix& reduced) {
  if (r.keeps_all()) return k;
  reduce(k, r).swap(reduced);
  return reduced;
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
