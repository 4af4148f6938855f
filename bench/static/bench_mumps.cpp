// MUMPS (sequential, Debian libmumps-seq-dev) against the factorisations the stability check uses
// now (issue #18 item 4, "measure before adopting"), on K(active set) on the kept dofs:
// - the inertia of S = (K + K^T)/2: Eigen's SimplicialLDLT (negative_eigenvalue_count_symmetric)
//   against MUMPS SYM = 2, INFOG(12) negative pivots;
// - the sign of det K: UMFPACK LU (LuFactor, symbolic analysis reused) against MUMPS SYM = 0 with
//   ICNTL(33) = 1, orderings AMD, SCOTCH, PORD and METIS (ICNTL(7) = 0, 3, 4, 5; Debian's
//   sequential build has no METIS: 5 falls back to QAMD, INFOG(7) = 6);
// - one solve (one right-hand side, no refinement) with each factor.
// The current ones reuse their symbolic analyses (per sparsity pattern, as in a run); MUMPS
// analyses once (timed apart), then factorises (JOB = 2) each repeat. Each figure is the median of
// `repeats` after one warm-up. The counts and signs must agree. Not part of ctest.
//   bench_mumps SAMPLE [nx ny] [repeats]   K of the prepared start state (tiled nx x ny)
//   bench_mumps K.mtx... [-r repeats]      K from Matrix Market files (bench_mumps_dump)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <dmumps_c.h>
#include <Eigen/SparseCholesky>
#include <unsupported/Eigen/SparseExtra>

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

// Median in ms of `repeats` calls of f after one warm-up call.
double median_ms(int repeats, const std::function<void()>& f) {
  f();
  std::vector<double> t;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = Clock::now();
    f();
    t.push_back(1e3 * seconds(t0));
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

// A MUMPS instance on one matrix: analysis once (JOB = 1), then factorisations (JOB = 2), as a
// run would reuse the analysis of a sparsity pattern (the LDL^T and the LU reuse theirs too).
class Mumps {
 public:
  Mumps(const statics::SparseMatrix& a, bool symmetric, bool determinant, int ordering)
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
    id_.icntl[6] = ordering;             // ICNTL(7): 0 AMD, 3 SCOTCH, 4 PORD, 5 METIS, 7 automatic
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
  Mumps(const Mumps&) = delete;
  Mumps& operator=(const Mumps&) = delete;
  int analyse() {
    id_.job = 1;
    dmumps_c(&id_);
    return id_.infog[0];
  }
  int ordering_used() const { return id_.infog[6]; }  // INFOG(7)
  int factorise() {
    id_.job = 2;
    dmumps_c(&id_);
    return id_.infog[0];
  }
  int negative() const { return id_.infog[11]; }  // INFOG(12)
  int det_sign() const {
    if (!determinant_) return 0;
    return id_.rinfog[11] > 0.0 ? 1 : (id_.rinfog[11] < 0.0 ? -1 : 0);  // RINFOG(12)
  }
  long factor_entries() const {  // INFOG(29)
    return id_.infog[28];
  }
  // x = A^-1 b (JOB = 3, no refinement: ICNTL(10) = 0).
  int solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    x = b;
    id_.rhs = x.data();
    id_.nrhs = 1;
    id_.lrhs = static_cast<MUMPS_INT>(x.size());
    id_.job = 3;
    dmumps_c(&id_);
    return id_.infog[0];
  }

 private:
  bool determinant_;
  std::vector<MUMPS_INT> irn_, jcn_;
  std::vector<double> val_;
  DMUMPS_STRUC_C id_{};
};

double residual_of(const statics::SparseMatrix& a, const Eigen::VectorXd& x,
                   const Eigen::VectorXd& b) {
  return (a * x - b).norm() / b.norm();
}

// All timings on one K; returns true when the counts and signs agree.
bool time_all(const std::string& name, const statics::SparseMatrix& k, int repeats) {
  const statics::SparseMatrix s = 0.5 * (k + statics::SparseMatrix(k.transpose()));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(k.rows(), 1.0, 2.0);
  std::printf("%s: %ld dofs, %ld nonzeros in K, %ld in S's lower triangle\n", name.c_str(),
              static_cast<long>(k.rows()), static_cast<long>(k.nonZeros()),
              static_cast<long>((s.nonZeros() + s.rows()) / 2));
  bool agree = true;

  // The check now: LDL^T of S (its inertia), UMFPACK LU of K (its determinant sign).
  int ldlt_negative = -1;
  const double t_ldlt =
      median_ms(repeats, [&] { ldlt_negative = statics::negative_eigenvalue_count_symmetric(s); });
  Eigen::SimplicialLDLT<statics::SparseMatrix, Eigen::Lower> ldlt;
  ldlt.analyzePattern(s);
  ldlt.factorize(s);
  Eigen::VectorXd x;
  const double t_ldlt_solve = median_ms(repeats, [&] { x = ldlt.solve(b); });
  const double r_ldlt = residual_of(s, x, b);
  const long ldlt_entries = ldlt.matrixL().nestedExpression().nonZeros();
  statics::LuReuse reuse;
  reuse.refine = false;
  int lu_sign = 0;
  bool reused = false;
  const double t_lu = median_ms(repeats, [&] {
    statics::LuFactor lu(reuse);
    lu.factorize(k);
    lu_sign = lu.determinant_sign();
    reused = lu.symbolic_reused();
  });
  statics::LuFactor lu(reuse);
  lu.factorize(k);
  const double t_lu_solve = median_ms(repeats, [&] { x = lu.solve_unrefined(b); });
  const double r_lu = residual_of(k, x, b);
  std::printf("  LDL^T of S: %d negative, factorise %.2f ms, solve %.3f ms (res %.1e, |L| %ld)\n",
              ldlt_negative, t_ldlt, t_ldlt_solve, r_ldlt, ldlt_entries);
  std::printf(
      "  UMFPACK LU of K: det sign %+d, factorise %.2f ms (symbolic reused %d), "
      "solve %.3f ms (res %.1e)\n",
      lu_sign, t_lu, reused ? 1 : 0, t_lu_solve, r_lu);

  for (const int ordering : {0, 3, 4, 5}) {
    {
      Mumps m(k, false, true, ordering);
      auto t0 = Clock::now();
      int e = m.analyse();
      const double t_an = 1e3 * seconds(t0);
      if (e < 0) {
        std::printf("  MUMPS SYM=0 ordering %d: analysis error %d\n", ordering, e);
        agree = false;
        continue;
      }
      const double t_f = median_ms(repeats, [&] { e = m.factorise(); });
      const double t_s = median_ms(repeats, [&] { m.solve(b, x); });
      const double r = residual_of(k, x, b);
      const bool ok = e >= 0 && m.det_sign() == lu_sign;
      agree = agree && ok;
      std::printf(
          "  MUMPS SYM=0 ICNTL(7)=%d (used %d): det sign %+d (%s), analysis %.2f ms, "
          "factorise %.2f ms (INFOG(1) %d, %ld factor entries, %d negative pivots), solve %.3f "
          "ms (res %.1e)\n",
          ordering, m.ordering_used(), m.det_sign(), ok ? "agrees" : "DIFFERS", t_an, t_f, e,
          m.factor_entries(), m.negative(), t_s, r);
    }
    {
      Mumps m(s, true, false, ordering);
      auto t0 = Clock::now();
      int e = m.analyse();
      const double t_an = 1e3 * seconds(t0);
      if (e < 0) {
        std::printf("  MUMPS SYM=2 ordering %d: analysis error %d\n", ordering, e);
        agree = false;
        continue;
      }
      const double t_f = median_ms(repeats, [&] { e = m.factorise(); });
      const double t_s = median_ms(repeats, [&] { m.solve(b, x); });
      const double r = residual_of(s, x, b);
      const bool ok = e >= 0 && m.negative() == ldlt_negative;
      agree = agree && ok;
      std::printf(
          "  MUMPS SYM=2 ICNTL(7)=%d (used %d): %d negative (%s), analysis %.2f ms, "
          "factorise %.2f ms (INFOG(1) %d, %ld factor entries), solve %.3f ms (res %.1e)\n",
          ordering, m.ordering_used(), m.negative(), ok ? "agrees" : "DIFFERS", t_an, t_f, e,
          m.factor_entries(), t_s, r);
    }
  }
  // det K > 0 on every state measured so far: check the negative sign too, on K with its first
  // row negated (det changes sign; the pivoting does not).
  statics::SparseMatrix flipped = k;
  for (int j = 0; j < flipped.outerSize(); ++j)
    for (statics::SparseMatrix::InnerIterator it(flipped, j); it; ++it)
      if (it.row() == 0) it.valueRef() = -it.value();
  statics::LuFactor lu_flipped(reuse);
  lu_flipped.factorize(flipped);
  Mumps m_flipped(flipped, false, true, 0);
  m_flipped.analyse();
  m_flipped.factorise();
  const bool ok = lu_flipped.determinant_sign() == -lu_sign && m_flipped.det_sign() == -lu_sign;
  agree = agree && ok;
  std::printf("  first row negated: det sign UMFPACK %+d, MUMPS SYM=0 %+d (%s)\n",
              lu_flipped.determinant_sign(), m_flipped.det_sign(), ok ? "agree" : "DIFFER");
  return agree;
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SAMPLE [nx ny] [repeats] | %s K.mtx... [-r repeats]\n", argv[0],
                 argv[0]);
    return 2;
  }
  bool agree = true;
  if (ends_with(argv[1], ".mtx")) {
    int repeats = 5;
    std::vector<std::string> files;
    for (int i = 1; i < argc; ++i) {
      if (std::strcmp(argv[i], "-r") == 0 && i + 1 < argc)
        repeats = std::atoi(argv[++i]);
      else
        files.emplace_back(argv[i]);
    }
    for (const std::string& f : files) {
      statics::SparseMatrix k;
      if (!Eigen::loadMarket(k, f)) {
        std::fprintf(stderr, "cannot read %s\n", f.c_str());
        return 2;
      }
      k.makeCompressed();
      agree = time_all(f, k, repeats) && agree;
    }
    return agree ? 0 : 1;
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
  agree = time_all("start state, N = " + std::to_string(config.disks.size()),
                   statics::reduce(k_full, r), repeats);
  return agree ? 0 : 1;
}
