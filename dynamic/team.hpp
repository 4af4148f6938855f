#pragma once
// The thread team of a run (issue #23): one parallel region for a whole Engine::run, each
// thread keeping the same part of the disks for every pass and every step, and a barrier of
// its own between the passes. libgomp's barrier sleeps at once under OMP_WAIT_POLICY=passive
// (10-20 us to wake a thread here, against a step of ~140 us at N = 5600 on two threads); this
// one spins briefly, then yields, and only then sleeps (wait_for). Also the relay that hands
// values from thread to thread (Relay), and where the team sleeps while one thread runs it alone
// (Wakeup; engine.cpp).
#include <omp.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <vector>

namespace granstab::dynamic {

// Returns once done(word) holds (word read with acquire). Spins 300 pause instructions (~3 us on
// the Xeon of the test VM, ~6 us on the AMD one): two threads on two cores arrive within that in
// most passes. Then yields: when both threads share one CPU (a loaded machine: Linux
// keeps waking threads on the waker's CPU) this hands it to the partner at once, where spinning
// would burn the time slice it waits for (10 us of spinning made two threads 25 % slower there,
// 100 us three to twenty times). Then sleeps on the word (futex).
template <class Done>
void wait_for(const std::atomic<std::uint32_t>& word, Done done) {
  constexpr int spin_iterations = 300;
  constexpr int yield_iterations = 1000;
  for (int k = 0; k < spin_iterations; ++k) {
    if (done(word.load(std::memory_order_acquire))) return;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }
  for (int k = 0; k < yield_iterations; ++k) {
    if (done(word.load(std::memory_order_acquire))) return;
    sched_yield();
  }
  for (std::uint32_t v = word.load(std::memory_order_acquire); !done(v);
       v = word.load(std::memory_order_acquire)) {
    word.wait(v, std::memory_order_acquire);
  }
}

class SpinBarrier {
 public:
  SpinBarrier() = default;
  // A barrier holds nothing between two runs of a team: copies (of an Engine) start afresh.
  SpinBarrier(const SpinBarrier&) {}
  SpinBarrier& operator=(const SpinBarrier&) { return *this; }
  // Sets the team size; call while no thread waits (before the team starts).
  void reset(int threads) {
    threads_ = threads;
    arrived_.store(0, std::memory_order_relaxed);
  }
  int threads() const { return threads_; }

  // Returns once every thread of the team has called wait(). What a thread wrote before it
  // called wait() is visible to every thread after it returns (release / acquire through the
  // arrival counter and the generation).
  void wait() {
    if (threads_ <= 1) return;
    // Read before arriving: the generation cannot change until this thread has arrived.
    const std::uint32_t gen = generation_.load(std::memory_order_relaxed);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) == threads_ - 1) {
      arrived_.store(0, std::memory_order_relaxed);
      generation_.store(gen + 1, std::memory_order_release);
      generation_.notify_all();  // no system call unless a thread sleeps
      return;
    }
    wait_for(generation_, [gen](std::uint32_t g) { return g != gen; });
  }

 private:
  // The counter and the generation on cache lines of their own: the spinning threads read the
  // generation only, and the arrivals do not invalidate it until the last one.
  alignas(64) std::atomic<int> arrived_{0};
  alignas(64) std::atomic<std::uint32_t> generation_{0};
  alignas(64) int threads_ = 1;
};

// Values passed from thread to thread in a fixed order (the chained block sums,
// contact_forces.cpp): slot k holds the k-th value of reduction number `epoch` (from 1 after a
// reset). A reader waits as at the barrier (wait_for). Slots on cache lines of their own.
template <class Value>
class Relay {
 public:
  Relay() = default;
  Relay(const Relay&) {}  // holds nothing between two runs
  Relay& operator=(const Relay&) { return *this; }
  // Call while no thread uses the relay (before a team starts); epochs then start at 1.
  void reset(int slots) {
    if (slots_.size() != static_cast<std::size_t>(slots)) slots_ = std::vector<Slot>(slots);
    for (Slot& s : slots_) s.epoch.store(0, std::memory_order_relaxed);
  }
  void publish(int k, const Value& value, std::uint32_t epoch) {
    Slot& s = slots_[k];
    s.value = value;
    s.epoch.store(epoch, std::memory_order_release);
    s.epoch.notify_all();  // no system call unless a thread sleeps
  }
  const Value& await(int k, std::uint32_t epoch) const {
    const Slot& s = slots_[k];
    wait_for(s.epoch, [epoch](std::uint32_t e) { return e == epoch; });
    return s.value;
  }

 private:
  struct alignas(64) Slot {
    std::atomic<std::uint32_t> epoch{0};
    Value value{};
  };
  std::vector<Slot> slots_;
};

// Where the threads of a team that one thread runs alone sleep (engine.cpp): until that thread
// has published its k-th hand-back. Sleeps at once (futex): the point is to leave the CPU.
class Wakeup {
 public:
  Wakeup() = default;
  Wakeup(const Wakeup&) {}  // holds nothing between two runs
  Wakeup& operator=(const Wakeup&) { return *this; }
  void reset() { count_.store(0, std::memory_order_relaxed); }
  void publish(std::uint32_t k) {
    count_.store(k, std::memory_order_release);
    count_.notify_all();
  }
  void await(std::uint32_t k) const {
    for (std::uint32_t c = count_.load(std::memory_order_acquire); c < k;
         c = count_.load(std::memory_order_acquire)) {
      count_.wait(c, std::memory_order_acquire);
    }
  }

 private:
  alignas(64) std::atomic<std::uint32_t> count_{0};
};

// A thread's work time between the team's barriers (its waits excluded), which the engine
// balances the parts by (EngineOptions::balance_steps). Two clock reads per barrier.
struct TeamClock {
  double busy = 0.0;   // seconds of work since the last reset
  double since = 0.0;  // when this thread last left a barrier
  static double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  void arrive() { busy += now() - since; }
  void leave() { since = now(); }
};

// One thread's view of the team inside the region: the parts it runs (a range of whole blocks
// each, PairArrays::part_block; its own one, or all of them when it runs alone), the team's
// barrier (threads: how many meet there) and, if any, the clock of its work.
struct TeamMember {
  int thread = 0;
  int threads = 1;
  int part_first = 0, part_end = 1;
  SpinBarrier* barrier = nullptr;
  TeamClock* clock = nullptr;
  void sync() const {
    if (threads <= 1) return;
    if (clock) clock->arrive();
    barrier->wait();
    if (clock) clock->leave();
  }
};

// Runs body(member) on every thread of a team of (at most) `threads`, in one parallel region,
// after prepare(team) has run on one thread with the team's actual size (OpenMP may give
// fewer threads than asked). threads <= 1: on the calling thread, no region.
template <class Prepare, class Body>
void on_team(int threads, SpinBarrier& barrier, Prepare prepare, Body body) {
  if (threads <= 1) {
    barrier.reset(1);
    prepare(1);
    body(TeamMember{0, 1, 0, 1, &barrier, nullptr});
    return;
  }
#pragma omp parallel num_threads(threads)
  {
    const int team = omp_get_num_threads();
#pragma omp single
    {
      barrier.reset(team);
      prepare(team);
    }  // (implicit barrier)
    const int t = omp_get_thread_num();
    body(TeamMember{t, team, t, t + 1, &barrier, nullptr});
  }
}

}  // namespace granstab::dynamic
