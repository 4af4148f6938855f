// MUMPS (sequential, Debian libmumps-seq-dev) against the factorisations the stability check uses
// now (issue #18 item 4, "measure before adopting"), on the tangent of a prepared start state:
// - the inertia of S = (K + K^T)/2: Eigen's SimplicialLDLT (negative_eigenvalue_count_symmetric)
//   against MUMPS SYM = 2, INFOG(12) negative pivots;
// - the sign of det K: UMFPACK LU (LuFactor) against MUMPS SYM = 0 with ICNTL(33) = 1.
// The current ones reuse their symbolic analyses (per sparsity pattern, as in a run); MUMPS
// analyses once, then factorises `repeats` times. The results must agree. Not part of ctest.
//   bench_mumps SAMPLE [nx ny] [repeats]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <dmumps_c.h>

#include "common/io/configuration_file.hpp"
#include "static/backbone.hpp"
#include "static/hill.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "static/network.hpp"
#include "static/tangent.hpp"
#include "tile.hpp"

using namespace granstab;
using Clock = std::chrono::steady_clock;

namespace {

double seconds(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct MumpsResult {
  int negative = -1;  // INFOG(12)
  int det_sign = 0;   // sign of RINFOG(12) when the determinant was asked
  int error = 0;      // INFOG(1)
};

// A MUMPS instance on one matrix: analysis once (JOB = 1), then factorisations (JOB = 2), as a
// run would reuse the analysis of a sparsity pattern (the LDL^T and the LU reuse theirs too).
class Mumps {
 public:
  Mumps(const statics::SparseMatrix& a, bool symmetric, bool determinant)
      : determinant_(determinant) {
    for (int j = 0; j < a.outerSize(); ++j)
      for (statics::SparseMatrix::InnerIterator it(a, j); it; ++it) {
        if (symmetric && it.row() < it.col()) continue;  // the lower triangle of S
        irn_.push_back(static_cast<MUMPS_INT>(it.row() + 1));
        jcn_.push_back(static_cast<MUMPS_INT>(it.col() + 1));
        val_.push_back(it.value());
      }
    id_.comm_fortran = -987654;  // USE_COMM_WORLD (the sequential library's stub)
    id_.par = 1;
    id_.sym = symmetric ? 2 : 0;
    id_.job = -1;
    dmumps_c(&id_);
    id_.icntl[0] = -1;  // no messages
    id_.icntl[1] = -1;
    id_.icntl[2] = -1;
    id_.icntl[3] = 0;
    if (determinant) id_.icntl[32] = 1;  // ICNTL(33)
    id_.n = static_cast<MUMPS_INT>(a.rows());
    id_.nnz = static_cast<MUMPS_INT8>(val_.size());
    id_.irn = irn_.data();
    id_.jcn = jcn_.data();
    id_.a = val_.data();
  }
  ~Mumps() {
    id_.job = -2;
    dmumps_c(&id_);
  }
  void analyse() {
    id_.job = 1;
    dmumps_c(&id_);
  }
  MumpsResult factorise() {
    id_.job = 2;
    dmumps_c(&id_);
    MumpsResult r;
    r.error = id_.infog[0];
    r.negative = id_.infog[11];
    if (determinant_) r.det_sign = id_.rinfog[11] > 0.0 ? 1 : (id_.rinfog[11] < 0.0 ? -1 : 0);
    return r;
  }

 private:
  bool determinant_;
  std::vector<MUMPS_INT> irn_, jcn_;
  std::vector<double> val_;
  DMUMPS_STRUC_C id_{};
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SAMPLE [nx ny] [repeats]\n", argv[0]);
    return 2;
  }
  const int nx = argc > 3 ? std::atoi(argv[2]) : 1, ny = argc > 3 ? std::atoi(argv[3]) : 1;
  const int repeats = argc > 4 ? std::atoi(argv[4]) : 5;
  const Configuration config = bench::tile(read_configuration(argv[1]), nx, ny);
  statics::Network net = statics::network_from_configuration(config);
  statics::prepare(net, statics::SolverOptions{});
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const auto states = statics::evaluate_contacts(net, zero);
  const auto statuses = statics::classify_contacts(states);
  const statics::SparseMatrix k_full = statics::assemble_tangent(net, states, statuses);
  const statics::Reduction r = statics::make_reduction(statics::kept_dofs(net, states, statuses));
  const statics::SparseMatrix k = statics::reduce(k_full, r);
  const statics::SparseMatrix s = 0.5 * (k + statics::SparseMatrix(k.transpose()));
  std::printf("N = %zu, %ld dofs, %ld nonzeros in K\n", config.disks.size(),
              static_cast<long>(k.rows()), static_cast<long>(k.nonZeros()));

  double t_ldlt = 0, t_lu = 0, t_mumps_s = 0, t_mumps_k = 0, t_analyse_s = 0, t_analyse_k = 0;
  int ldlt_negative = -1, lu_sign = 0;
  MumpsResult ms, mk;
  Mumps mumps_s(s, true, false), mumps_k(k, false, true);
  auto t0 = Clock::now();
  mumps_s.analyse();
  t_analyse_s = seconds(t0);
  t0 = Clock::now();
  mumps_k.analyse();
  t_analyse_k = seconds(t0);
  for (int rep = 0; rep < repeats; ++rep) {
    t0 = Clock::now();
    ldlt_negative = statics::negative_eigenvalue_count_symmetric(s);
    t_ldlt += seconds(t0);
    t0 = Clock::now();
    statics::LuFactor lu;
    lu.factorize(k);
    lu_sign = lu.determinant_sign();
    t_lu += seconds(t0);
    t0 = Clock::now();
    ms = mumps_s.factorise();
    t_mumps_s += seconds(t0);
    t0 = Clock::now();
    mk = mumps_k.factorise();
    t_mumps_k += seconds(t0);
  }
  std::printf("MUMPS analyses (once): S %.2f ms, K %.2f ms\n", 1e3 * t_analyse_s,
              1e3 * t_analyse_k);
  std::printf(
      "inertia of S: LDL^T %d negative, %.2f ms; MUMPS SYM=2 %d negative (INFOG(1) %d), "
      "%.2f ms\n",
      ldlt_negative, 1e3 * t_ldlt / repeats, ms.negative, ms.error, 1e3 * t_mumps_s / repeats);
  std::printf(
      "sign of det K: UMFPACK %d, %.2f ms; MUMPS SYM=0 %d (INFOG(1) %d, %d negative "
      "pivots), %.2f ms\n",
      lu_sign, 1e3 * t_lu / repeats, mk.det_sign, mk.error, mk.negative, 1e3 * t_mumps_k / repeats);
  return (ldlt_negative == ms.negative && lu_sign == mk.det_sign) ? 0 : 1;
}
