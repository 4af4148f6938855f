// Cost of the engine's synchronisation points on this machine (issue #7, two threads): the time
// of an empty parallel region (a fork/join, as each pass of the step opens) and of a barrier
// inside one (as the engine's team meets three times per step), averaged over many. The wait policy
// comes from the environment (OMP_WAIT_POLICY), as for the engine.
//
//   bench_sync [THREADS] [COUNT]
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
  const int count = argc > 2 ? std::atoi(argv[2]) : 20000;
  int work = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < count; ++k) {
#pragma omp parallel num_threads(threads) reduction(+ : work)
    work += 1;
  }
  const auto t1 = std::chrono::steady_clock::now();
#pragma omp parallel num_threads(threads)
  for (int k = 0; k < count; ++k) {
#pragma omp barrier
  }
  const auto t2 = std::chrono::steady_clock::now();
  const auto us = [&](auto a, auto b) {
    return std::chrono::duration<double, std::micro>(b - a).count() / count;
  };
  std::printf("threads %d regions %d fork_join_us %.2f barrier_us %.2f\n", threads, work / threads,
              us(t0, t1), us(t1, t2));
  return 0;
}
