// Particle-steps per second of the MD engine (issue #3 benchmark, issue #7 workload): dense
// periodic samples, kappa = 1e4, mu = 0.5, K_T = K_N, zeta = 1, biaxial strain-rate control
// (sigma_1 = P under stress control, d epsilon_2 / dt = 1e-4), dt = 0.05 sqrt(m_min / K_N).
// Runs for 1 and 2 threads are interleaved; the median of the repeats is reported.
//
//   bench_engine [--sizes 1400,5600,22400] [--threads 1,2] [--repeats 5] [--steps 2000]
//                [--shuffle 1]
// --shuffle 1 also times the same sample with its disks in random index order (as a sample
// prepared from a random gas is), and that one renumbered by spatial_order(): the lattice-built
// sample is ordered in space, which keeps the partners' data of a disk close in memory.
#include <omp.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "dynamic/spatial_order.hpp"
#include "sample.hpp"

namespace {

std::vector<int> parse_list(const std::string& s) {
  std::vector<int> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(std::stoi(item));
  return out;
}

// CPU seconds of the whole process (all threads): on a shared, loaded machine the wall clock
// also measures the other jobs; CPU time measures what the engine consumed.
double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace granstab;
  std::vector<int> sizes{1400, 5600, 22400}, threads{1, 2};
  int repeats = 5, steps = 2000;
  bool shuffle = false;
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string key = argv[k], value = argv[k + 1];
    if (key == "--sizes")
      sizes = parse_list(value);
    else if (key == "--threads")
      threads = parse_list(value);
    else if (key == "--repeats")
      repeats = std::stoi(value);
    else if (key == "--steps")
      steps = std::stoi(value);
    else if (key == "--shuffle")
      shuffle = std::stoi(value) != 0;
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  const Material material = Material::from_kappa(1e4, 1.0, 0.5, 1.0);
  std::printf("%8s %8s %14s %19s %16s %10s %9s\n", "N", "threads", "median p-s/s", "min..max",
              "median p-s/cpu-s", "contacts/N", "rebuilds");
  for (int n : sizes) {
    omp_set_num_threads(1);  // preparation: one thread (robust on a loaded machine)
    const auto t0 = std::chrono::steady_clock::now();
    Configuration sample = bench::dense_sample(n, material, 2026);
    const double prep =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    sample.stage.control = {LengthControl::stress, LengthControl::strain_rate};
    sample.stage.sigma_ext = {1.0, 1.0};
    sample.stage.strain_rate = {0.0, 1e-4};
    sample.cell.length_rate = {0.0, -1e-4 * sample.cell.length[1]};
    std::vector<Configuration> samples{sample};
    if (shuffle) {
      const Configuration random_order = bench::shuffled(sample, 7);
      samples.push_back(random_order);
      samples.push_back(renumbered(random_order, spatial_order(random_order)));
    }
    for (std::size_t v = 0; v < samples.size(); ++v) {
      std::vector<std::vector<double>> rates(threads.size()), cpu_rates(threads.size());
      std::size_t contacts = 0;
      std::uint64_t rebuilds = 0;
      for (int r = 0; r < repeats; ++r) {
        for (std::size_t t = 0; t < threads.size(); ++t) {
          omp_set_num_threads(threads[t]);
          Engine e(samples[v]);  // dt defaults to 0.05 sqrt(m_min / K_N)
          e.run(100);            // warm caches and the neighbour list
          const auto s0 = std::chrono::steady_clock::now();
          const double c0 = cpu_seconds();
          e.run(steps);
          const double cpu = cpu_seconds() - c0;
          const double secs =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
          rates[t].push_back(static_cast<double>(n) * steps / secs);
          cpu_rates[t].push_back(static_cast<double>(n) * steps / cpu);
          contacts = e.contact_count();
          rebuilds = e.neighbour_rebuilds();
        }
      }
      for (std::size_t t = 0; t < threads.size(); ++t) {
        std::printf("%8d %8d %14.3e %9.2e..%8.2e %16.3e %10.2f %9llu%s\n", n, threads[t],
                    median(rates[t]), *std::min_element(rates[t].begin(), rates[t].end()),
                    *std::max_element(rates[t].begin(), rates[t].end()), median(cpu_rates[t]),
                    static_cast<double>(contacts) / n, static_cast<unsigned long long>(rebuilds),
                    v == 1 ? "  shuffled" : (v == 2 ? "  shuffled, then spatial_order" : ""));
      }
    }
    std::printf("# N = %d: sample prepared in %.1f s\n", n, prep);
    std::fflush(stdout);
  }
  return 0;
}
