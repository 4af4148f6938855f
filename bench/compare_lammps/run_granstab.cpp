// granstab side of the issue #7 comparison (bench/compare_lammps/run.sh): reads a packing
// written by make_packing, runs STEPS steps of its strain-rate test (L1 fixed, epsilon_2 at the
// stored rate) and prints the loop time, particle-steps per second and the stress every EVERY
// steps (elastic + frictional, SPEC §2, compression positive) and the diagonal of the viscous
// contact forces' stress (which LAMMPS's pair virial includes).
//
//   run_granstab FILE.granstab STEPS EVERY THREADS [skin] [OUT.granstab]
// OUT.granstab: the final state (bitwise comparisons of engine versions). The environment
// variable GS_PARALLEL_MIN_DISKS overrides EngineOptions::parallel_min_disks.
#include <omp.h>
#include <time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "common/io/configuration_file.hpp"
#include "dynamic/engine.hpp"

int main(int argc, char** argv) {
  using namespace granstab;
  if (argc < 5) {
    std::fprintf(stderr, "usage: run_granstab FILE STEPS EVERY THREADS [skin] [OUT]\n");
    return 2;
  }
  const Configuration c = read_configuration(argv[1]);
  const long steps = std::atol(argv[2]), every = std::atol(argv[3]);
  const int threads = std::atoi(argv[4]);
  EngineOptions options;
  if (argc > 5) options.skin = std::atof(argv[5]);
  if (const char* m = std::getenv("GS_PARALLEL_MIN_DISKS"))
    options.parallel_min_disks = std::atol(m);
  omp_set_num_threads(threads);
  Engine e(c, options);  // dt = 0.05 sqrt(m_min / K_N), as in the LAMMPS input
  struct Sample {
    long step;
    double l2, s11, s22, v11, v22;
  };
  std::vector<Sample> curve;
  curve.reserve(steps / every + 2);
  const auto record = [&](long s) {
    const Engine::Tensor sigma = e.stress();
    const std::array<double, 2> viscous = e.viscous_stress();
    curve.push_back({s, e.length()[1], sigma[0][0], sigma[1][1], viscous[0], viscous[1]});
  };
  record(0);
  const auto cpu = [] {  // CPU seconds of the process, all threads
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
  };
  const double c0 = cpu();
  const auto t0 = std::chrono::steady_clock::now();
  for (long s = 0; s < steps; s += every) {
    const long chunk = std::min(every, steps - s);
    e.run(static_cast<std::uint64_t>(chunk));
    record(s + chunk);
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu_secs = cpu() - c0;
  std::printf(
      "# dt %.17g skin %g threads %d rebuilds %llu part moves %llu alone steps %llu, parts (first "
      "blocks)",
      e.dt(), options.skin, threads, static_cast<unsigned long long>(e.neighbour_rebuilds()),
      static_cast<unsigned long long>(e.part_moves()),
      static_cast<unsigned long long>(e.alone_step_count()));
  for (const std::int32_t b : e.part_blocks()) std::printf(" %d", b);
  std::printf("\n");
  for (const Sample& s : curve) {
    std::printf("curve %ld %.10g %.10g %.10g %.10g %.10g\n", s.step, s.l2, s.s11, s.s22, s.v11,
                s.v22);
  }
  std::printf("loop_time %.6f steps %ld atoms %zu ps_per_s %.6e cpu_time %.6f\n", secs, steps,
              e.size(), static_cast<double>(e.size()) * steps / secs, cpu_secs);
  if (argc > 6) write_configuration(e.configuration(), argv[6]);
  return 0;
}
