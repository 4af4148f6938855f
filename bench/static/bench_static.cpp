// Timing of the static solver (issue #5): one load step split into assembly, factorisation and
// complementarity, and optionally the whole q1 run, on a shipped periodic sample tiled
// nx x ny times. Not part of ctest.
//   bench_static SAMPLE [nx ny] [steps] [q1]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/io/configuration_file.hpp"
#include "static/load_step.hpp"
#include "static/q1.hpp"
#include "tile.hpp"

using namespace granstab;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SAMPLE [nx ny] [steps] [q1]\n", argv[0]);
    return 2;
  }
  const int nx = argc > 3 ? std::atoi(argv[2]) : 1, ny = argc > 3 ? std::atoi(argv[3]) : 1;
  const int steps = argc > 4 ? std::atoi(argv[4]) : 10;
  const bool q1 = argc > 5 && std::string(argv[5]) == "q1";
  const Configuration config = bench::tile(read_configuration(argv[1]), nx, ny);
  using Clock = std::chrono::steady_clock;

  statics::Network net = statics::network_from_configuration(config);
  const auto t0 = Clock::now();
  statics::prepare(net, statics::SolverOptions{});
  const double t_prepare = std::chrono::duration<double>(Clock::now() - t0).count();
  statics::Timings timings;
  int done = 0;
  const auto t1 = Clock::now();
  const double sigma1 = net.loading.sigma[0];
  for (int k = 0; k < steps; ++k) {
    net.loading.sigma[1] = sigma1 * (1.0 + 1e-3 * (k + 1));
    const statics::StepResult s = statics::load_step(net, statics::SolverOptions{}, &timings);
    if (!s.ok) break;
    ++done;
  }
  const double t_steps = std::chrono::duration<double>(Clock::now() - t1).count();
  std::printf("N = %zu, dofs = %d, contacts = %zu, prepare %.3f s\n", config.disks.size(),
              net.dofs.size, net.contacts.size(), t_prepare);
  std::printf("%d load steps of dq = 1e-3: %.4f s per step (assembly %.4f, factorisation %.4f, "
              "complementarity loop %.4f incl. its assembly and factorisation, corrector %.4f)\n",
              done, t_steps / done, timings.assembly / done, timings.factorisation / done,
              timings.complementarity / done, timings.corrector / done);
  if (q1) {
    statics::Q1Options o;
    o.hill = false;
    const auto t2 = Clock::now();
    const statics::StabilityResult r = statics::find_q1(config, o);
    std::printf("q1 = %.6f (%s), %d steps, %.2f s (assembly %.2f, factorisation %.2f, "
                "complementarity loops %.2f, correctors %.2f)\n",
                r.q1, statics::criterion_name(r.criterion), r.steps,
                std::chrono::duration<double>(Clock::now() - t2).count(), r.timings.assembly,
                r.timings.factorisation, r.timings.complementarity, r.timings.corrector);
  }
  return 0;
}
