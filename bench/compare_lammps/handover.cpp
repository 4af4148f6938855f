// The one-way cache-line hand-over time between two CPUs, which run.sh prints before the runs and
// after each (repeat, N) group. Two threads pinned to CPU A and CPU B pass a counter back and forth
// through one cache line; each pass moves the line from one core's cache to the other's.
//
//   handover [CPU_A CPU_B [PASSES]]      (default: 0 1 2000000)
//
// Prints "handover_ns T cpus A B". A two-thread or two-rank step pays this time at every exchange
// (barriers, halo data, sums). On the AMD EPYC VM of the issue #23 runs it was ~50 ns at some
// times and ~230 ns at others, and both codes' two-process speed-ups followed it
// (docs/notes/2026-12-05-threads-vm-topology.md). Linux only (thread affinity).
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>

namespace {

alignas(64) std::atomic<long> baton{0};

bool pin_to(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
}

// Waits for the baton to read `mine`, then hands it on as mine + 1, for every second value up
// to `passes`.
void relay(long first, long passes) {
  for (long mine = first; mine < passes; mine += 2) {
    while (baton.load(std::memory_order_acquire) != mine) {
    }
    baton.store(mine + 1, std::memory_order_release);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int cpu_a = argc > 2 ? std::atoi(argv[1]) : 0;
  const int cpu_b = argc > 2 ? std::atoi(argv[2]) : 1;
  const long passes = argc > 3 ? std::atol(argv[3]) : 2000000;
  if (cpu_a == cpu_b || passes < 2 || passes % 2 != 0) {
    std::fprintf(stderr, "handover: two different CPUs and an even number of passes >= 2\n");
    return 2;
  }
  // Without both CPUs (a machine or CPU set without one of them) the figure means nothing, and
  // two threads passing the baton on one CPU would take a time slice per pass.
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0 || cpu_a < 0 || cpu_b < 0 ||
      cpu_a >= CPU_SETSIZE || cpu_b >= CPU_SETSIZE || !CPU_ISSET(cpu_a, &allowed) ||
      !CPU_ISSET(cpu_b, &allowed)) {
    std::printf("handover_ns nan cpus %d %d\n", cpu_a, cpu_b);
    return 0;
  }
  bool pinned_b = false;
  std::thread other([&] {
    pinned_b = pin_to(cpu_b);
    relay(1, passes);
  });
  const bool pinned_a = pin_to(cpu_a);
  const auto t0 = std::chrono::steady_clock::now();
  relay(0, passes);
  while (baton.load(std::memory_order_acquire) != passes) {
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  other.join();
  const double ns = pinned_a && pinned_b ? seconds / static_cast<double>(passes) * 1e9 : NAN;
  std::printf("handover_ns %.0f cpus %d %d\n", ns, cpu_a, cpu_b);
  return 0;
}
