// Throw-away measurement of STATIC.md §S3.1's second route (issue #5/#7, docs/static.md
// "Performance"): one CHOLMOD factorisation of the symmetric all-stick matrix S per step and a
// dense reduced problem over the n_c critical contacts, against the UMFPACK LU of the full K that
// the complementarity loop makes today. Not wired into the solver; not part of ctest.
//   bench_schur SAMPLE [nx ny] [n_c ...]
// Times (thread CPU seconds) on the prepared start state of the tiled sample:
// - UMFPACK LU of K(statuses) on the kept dofs: with a symbolic analysis, and numeric only;
// - CHOLMOD LL^T (SymmetricFactor) of S = (K_stick + K_stick^T)/2: with the analysis, and numeric only;
// - the O(1/kappa) unsymmetric remainder: iterations of x += S^-1 (b - K_stick x) to 1e-10;
// - for each n_c (the n_c contacts nearest the Coulomb cone): Z = S^-1 W (blocked solve of the
//   n_c columns W_c = B_T,c^T), M = K_T I - V Z (V_c = s_c K_T B_T,c - mu K_N B_N,c) and a dense LU
//   of M, the cost of one principal pivoting pass over the reduced LCP.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numeric>
#include <vector>

#include <Eigen/Dense>

#include "common/io/configuration_file.hpp"
#include "static/backbone.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "tile.hpp"

using namespace granstab;
using namespace granstab::statics;

namespace {

double cpu() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Minimum over a few repetitions (the machine is shared).
template <class F>
double best_of(int repeats, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = cpu();
    f();
    best = std::min(best, cpu() - t0);
  }
  return best;
}

// The local row of contact s on the reduced dofs, as a dense column.
Eigen::VectorXd column(const ContactState& s, const LocalRow& row, const Reduction& r, int n) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
  for (int a = 0; a < n_local; ++a) {
    const int d = s.rows.dof[a];
    if (d >= 0 && r.full_to_reduced[d] >= 0) v[r.full_to_reduced[d]] += row[a];
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SAMPLE [nx ny] [n_c ...]\n", argv[0]);
    return 2;
  }
  const int nx = argc > 3 ? std::atoi(argv[2]) : 1, ny = argc > 3 ? std::atoi(argv[3]) : 1;
  std::vector<int> critical_counts;
  for (int a = 4; a < argc; ++a) critical_counts.push_back(std::atoi(argv[a]));
  if (critical_counts.empty()) critical_counts = {100, 300, 1000};

  const Configuration config = bench::tile(read_configuration(argv[1]), nx, ny);
  Network net = network_from_configuration(config);
  net.constraints.cell_free = {true, true};  // as find_q1 under stress control
  net.constraints.remove_rattlers = true;
  prepare(net, SolverOptions{});
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const std::vector<ContactState> states = evaluate_contacts(net, zero);
  const std::vector<ContactStatus> statuses = classify_contacts(states);
  std::vector<ContactStatus> stick = statuses;
  int sliding = 0;
  for (ContactStatus& s : stick)
    if (s == ContactStatus::slide_positive || s == ContactStatus::slide_negative) {
      s = ContactStatus::stick;
      ++sliding;
    }
  const Reduction r = make_reduction(kept_dofs(net, states, statuses));
  const SparseMatrix k = reduce(assemble_tangent(net, states, statuses), r);
  const SparseMatrix k_stick = reduce(assemble_tangent(net, states, stick), r);
  const SparseMatrix s = 0.5 * (k_stick + SparseMatrix(k_stick.transpose()));
  const int n = static_cast<int>(k.rows());
  std::printf("N = %zu, contacts %zu (%d sliding at the start), kept dofs %d, nnz(K) %ld\n",
              config.disks.size(), net.contacts.size(), sliding, n, long(k.nonZeros()));

  constexpr int repeats = 3;
  {
    LuFactor lu;
    const double t0 = cpu();
    lu.factorize(k);  // fills the symbolic cache
    const double first = cpu() - t0;
    const double numeric = best_of(repeats, [&] { lu.factorize(k); });
    const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
    const double solve = best_of(repeats, [&] { (void)lu.solve(b); });
    std::printf("UMFPACK LU of K: %.3f s with analysis, %.3f s numeric, solve %.4f s\n", first,
                numeric, solve);
  }
  SymmetricFactor chol;
  const double t0 = cpu();
  const bool pd = chol.factorize(s);
  const double chol_first = cpu() - t0;
  const double chol_numeric = best_of(repeats, [&] { chol.factorize(s); });
  std::printf("CHOLMOD LL^T of S: %s, %.3f s with analysis, %.3f s numeric\n",
              pd ? "positive definite" : "NOT positive definite", chol_first, chol_numeric);
  if (!pd) return 1;
  {
    const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
    const double solve = best_of(repeats, [&] { (void)chol.solve(b); });
    const SparseMatrix remainder = k_stick - s;
    int it = 0;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    const double t1 = cpu();
    for (; it < 100; ++it) {
      const Eigen::VectorXd res = b - k_stick * x;
      if (res.norm() <= 1e-10 * b.norm()) break;
      x += chol.solve(res);
    }
    std::printf(
        "  solve %.4f s; |K_stick - S|_F / |S|_F = %.2e; K_stick x = b to 1e-10 by "
        "S-preconditioned iteration: %d iterations, %.3f s\n",
        solve, remainder.norm() / s.norm(), it, cpu() - t1);
  }

  // Contacts nearest the cone first.
  std::vector<int> order;
  for (std::size_t c = 0; c < states.size(); ++c)
    if (states[c].frictional && states[c].f_n > 0.0) order.push_back(static_cast<int>(c));
  const auto closeness = [&](int c) {
    return std::abs(states[c].f_t) / (states[c].mu * states[c].f_n);
  };
  std::sort(order.begin(), order.end(), [&](int a, int b) { return closeness(a) > closeness(b); });
  const double k_n = net.material.k_n, k_t = net.material.k_t;
  for (const int n_c : critical_counts) {
    if (n_c > static_cast<int>(order.size())) continue;
    Eigen::MatrixXd w(n, n_c);
    std::vector<std::vector<std::pair<int, double>>> v(n_c);  // V_c: a few entries each
    for (int a = 0; a < n_c; ++a) {
      const ContactState& st = states[order[a]];
      const double sign = st.f_t >= 0.0 ? 1.0 : -1.0;
      const Eigen::VectorXd bt = column(st, st.rows.bt0, r, n);
      w.col(a) = sign * k_t * bt;
      const Eigen::VectorXd va = sign * k_t * bt - st.mu * k_n * column(st, st.rows.bn, r, n);
      for (int i = 0; i < n; ++i)
        if (va[i] != 0.0) v[a].emplace_back(i, va[i]);
    }
    Eigen::MatrixXd z;
    const double t_block = best_of(repeats, [&] { z = chol.solve_columns(w); });
    const double t_columns = best_of(1, [&] {
      for (int a = 0; a < n_c; ++a) (void)chol.solve(Eigen::VectorXd(w.col(a)));
    });
    Eigen::MatrixXd m;
    const double t_m = best_of(repeats, [&] {
      m = k_t * Eigen::MatrixXd::Identity(n_c, n_c);
      for (int a = 0; a < n_c; ++a)
        for (const auto& [i, x] : v[a]) m.row(a) -= x * z.row(i);
    });
    Eigen::PartialPivLU<Eigen::MatrixXd> lu_m;
    const double t_lu = best_of(repeats, [&] { lu_m.compute(m); });
    std::printf(
        "n_c = %4d: S^-1 W %.3f s blocked (%.3f s column by column), M = K_T I - V S^-1 W "
        "%.3f s, LU of M %.4f s\n",
        n_c, t_block, t_columns, t_m, t_lu);
  }
  return 0;
}
