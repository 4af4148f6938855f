// Matrices of the stability check for bench_mumps (issue #18 item 4): runs find_q1 on a sample
// (dq = 1e-3, Hill off, the library's defaults otherwise) up to the last of the given loads,
// keeps the first accepted state at or past each, rebuilds its check (as stability_check.cpp
// check_state: the statuses of a 1e-6 dq load increment) and writes K(active set) on the kept dofs
// as Matrix Market, DIR/k-n{N}-q{load}.mtx. With tiles nx ny > 1 the state is also tiled nx x ny (a
// periodic equilibrium again, as bench_static tiles the start) and its check written too.
// Not part of ctest; no MUMPS here.
//   bench_mumps_dump SAMPLE DIR nx ny LOAD...
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <unsupported/Eigen/SparseExtra>

#include "common/io/configuration_file.hpp"
#include "drivers/stability_probe.hpp"
#include "static/hill.hpp"
#include "static/kinematics.hpp"
#include "static/linear_solvers.hpp"
#include "static/load_step.hpp"
#include "static/network.hpp"
#include "static/q1.hpp"
#include "static/tangent.hpp"
#include "tile.hpp"

using namespace granstab;

namespace {

constexpr double dq = 1e-3;

void write_check(const statics::Network& net, double q, double sigma1, const std::string& dir) {
  statics::Network probe = net;
  probe.loading.sigma = {sigma1, sigma1 * (1.0 + q + 1e-6 * dq)};
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(net.dofs.size);
  const Eigen::VectorXd increment =
      statics::residual(probe, zero, statics::evaluate_contacts(probe, zero)) -
      statics::residual(net, zero, statics::evaluate_contacts(net, zero));
  const statics::PredictorResult p =
      statics::predict(probe, statics::SolverOptions{}, nullptr, &increment);
  if (!p.ok) {
    std::printf("q %.4f N %zu: check failed (%s)\n", q, net.n_disks(), p.failure.c_str());
    return;
  }
  const statics::SparseMatrix k = statics::reduce(*p.tangent, statics::make_reduction(p.kept));
  const statics::SparseMatrix s = 0.5 * (k + statics::SparseMatrix(k.transpose()));
  int sliding = 0;
  for (const auto st : p.statuses)
    sliding += st == ContactStatus::slide_positive || st == ContactStatus::slide_negative;
  char name[256];
  std::snprintf(name, sizeof name, "%s/k-n%zu-q%.4f.mtx", dir.c_str(), net.n_disks(), q);
  Eigen::saveMarket(k, name);
  std::printf("%s: %ld dofs, %ld nonzeros, %d sliding, det sign %d, S negative %d\n", name,
              static_cast<long>(k.rows()), static_cast<long>(k.nonZeros()), sliding,
              p.determinant_sign, statics::negative_eigenvalue_count_symmetric(s));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 6) {
    std::fprintf(stderr, "usage: %s SAMPLE DIR nx ny LOAD...\n", argv[0]);
    return 2;
  }
  const Configuration config = read_configuration(argv[1]);
  const std::string dir = argv[2];
  const int nx = std::atoi(argv[3]), ny = std::atoi(argv[4]);
  std::vector<double> loads;
  for (int i = 5; i < argc; ++i) loads.push_back(std::atof(argv[i]));
  const double sigma1 = config.stage.sigma_ext[0];

  struct Kept {
    double load;
    statics::Network net;
  };
  std::vector<Kept> kept;
  statics::Q1Options o;
  o.dq = dq;
  o.hill_every = 0;
  o.load_stop = loads.back();
  o.on_accepted = [&](double load, const statics::Network& net) {
    if (kept.size() < loads.size() && load >= loads[kept.size()] - 1e-9)
      kept.push_back({load, net});
  };
  const statics::StabilityResult r = statics::find_q1(config, o);
  const statics::LuStatistics& lu = statics::lu_statistics();
  std::printf("run to %.4f: %d steps, %d attempts, %ld numeric LU, %ld symbolic analyses\n",
              r.curve.empty() ? 0.0 : r.curve.back().load, r.steps, r.attempts, lu.numeric,
              lu.symbolic);
  for (const Kept& s : kept) {
    write_check(s.net, s.load, sigma1, dir);
    if (nx * ny > 1) {
      const Configuration t =
          bench::tile(crosscheck::configuration_of_static_state(s.net, config), nx, ny);
      statics::Network net = statics::network_from_configuration(t);
      net.constraints.cell_free = {true, true};
      net.constraints.remove_rattlers = true;
      net.loading.sigma = {sigma1, sigma1 * (1.0 + s.load)};
      statics::polish_start(net, statics::SolverOptions{});
      write_check(net, s.load, sigma1, dir);
    }
  }
  return 0;
}
