#include "contact_forces.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string_view>

#include "contact_forces_law.hpp"
#include "contact_forces_simd.hpp"
#include "force_pass_team.hpp"
#include "halo.hpp"

namespace granstab::dynamic {
namespace {

// A pair's force of i on j and its torques (the sweep's; the kernel's scratch holds the same).
struct PairForce {
  double fx, fy;    // elastic + frictional
  double fvx, fvy;  // viscous
  double torque_i, torque_j;
};

// Adds a pair's force to disk j's running sum in memory (its own row comes later).
[[gnu::always_inline]] inline void add_to_j(DiskArrays& d, int j, const PairForce& f) {
  d.fx[j] += f.fx;
  d.fy[j] += f.fy;
  d.fvx[j] += f.fvx;
  d.fvy[j] += f.fvy;
  d.torque[j] += f.torque_j;
}

// Adds a pair's force to its disks in the order of the sums (docs/dynamic.md,
// "Determinism"): j's running sum in memory, i's in registers. A crossing pair's j belongs to a
// later part, whose thread adds it through the pair's mirror.
template <bool Crossing>
[[gnu::always_inline]] inline void add_pair(DiskArrays& d, const PairArrays& pairs, int p, int j,
                                            const PairForce& f, RowSums& row) {
  if (!Crossing || !pairs.crossing[p]) add_to_j(d, j, f);
  row.fx -= f.fx;
  row.fy -= f.fy;
  row.fvx -= f.fvx;
  row.fvy -= f.fvy;
  row.torque += f.torque_i;
}

// A closed pair's share of the block's stress sums (branch vector dx, dy).
[[gnu::always_inline]] inline void add_stress(BlockSums& sums, const PairForce& f, double dx,
                                              double dy) {
  sums.sigma[0] += f.fx * dx;
  sums.sigma[1] += f.fx * dy;
  sums.sigma[2] += f.fy * dx;
  sums.sigma[3] += f.fy * dy;
  sums.sigma_viscous[0] += f.fvx * dx;
  sums.sigma_viscous[1] += f.fvy * dy;
}

// Scratch of the SIMD kernel for one range of pairs (per thread; grown as needed).
struct KernelScratch {
  std::vector<std::uint8_t> closed;
  std::vector<double> fx, fy, fvx, fvy, torque_i, torque_j;
  std::vector<std::int32_t> touched;
  simd::PairBlock view(DiskArrays& d, PairState& pairs, const std::int32_t* read_j,
                       const ForceInputs& in, int count) {
    const std::size_t n = static_cast<std::size_t>(count) + simd::lanes - 1;
    if (closed.size() < n) {
      closed.resize(n);
      for (auto* v : {&fx, &fy, &fvx, &fvy, &torque_i, &torque_j}) v->resize(n);
      touched.resize(n + 1);  // the kernel stores whole vectors of 8 from any count <= count
    }
    simd::PairBlock v;
    v.x = d.x.data();
    v.y = d.y.data();
    v.radius = d.radius.data();
    v.vx = in.vx;
    v.vy = in.vy;
    v.omega = in.omega;
    v.vvx = in.vx_viscous;
    v.vvy = in.vy_viscous;
    v.pair_i = pairs.i.data();
    v.pair_j = read_j;
    v.alpha = pairs.alpha.data();
    v.delta_t = pairs.delta_t.data();
    v.f_n = pairs.f_n.data();
    v.nx = pairs.nx.data();
    v.ny = pairs.ny.data();
    v.lx = pairs.lx.data();
    v.ly = pairs.ly.data();
    v.closed = closed.data();
    v.fx = fx.data();
    v.fy = fy.data();
    v.fvx = fvx.data();
    v.fvy = fvy.data();
    v.torque_i = torque_i.data();
    v.torque_j = torque_j.data();
    v.touched = touched.data();
    return v;
  }
};

PairLawConstants law_constants(const ForceInputs& in) {
  const Material& m = *in.material;
  const bool periodic = in.periodic;
  return {m.k_n,
          m.k_t,
          m.mu,
          in.dt,
          periodic ? in.rate_tangential[0] : 0.0,
          periodic ? in.rate_tangential[1] : 0.0,
          periodic ? in.rate_viscous[0] : 0.0,
          periodic ? in.rate_viscous[1] : 0.0};
}

// How a force pass computes the law of the closed pairs. In a time step (ForceInputs::kick) the
// viscous pass that follows rewrites every closed pair's viscous force (PairState::viscous_x,
// _y; with zeta = 0 there is none, but then every such force is a zero, and a zero of either
// sign leaves the sums, which start at +0, unchanged), so the force pass stores it only when it
// evaluates a state (no viscous pass follows; the next step's opening pairs read it).
enum class Sweep {
  evaluate,   // scalar law, stores the viscous forces
  step,       // scalar law
  step_simd,  // the SIMD kernel's law (same bits), read from its scratch
};

// What a force pass reads of the disks, and the pass's constants; copied to locals, since the
// stores into the force arrays could otherwise alias them.
struct PassInputs {
  const double *x, *y, *radius, *vx, *vy, *omega, *vvx, *vvy;
  PairLawConstants k;
  double l1, l2, half_l1, half_l2, dt;
  PassInputs(const DiskArrays& d, const ForceInputs& in)
      : x(d.x.data()),
        y(d.y.data()),
        radius(d.radius.data()),
        vx(in.vx),
        vy(in.vy),
        omega(in.omega),
        vvx(in.vx_viscous),
        vvy(in.vy_viscous),
        k(law_constants(in)),
        l1(in.length[0]),
        l2(in.length[1]),
        half_l1(0.5 * l1),
        half_l2(0.5 * l2),
        dt(in.dt) {}
};

// Disk i of a pair, as the sweep of its row holds it.
struct RowDisk {
  double x, y, r, vx, vy, omega, vvx, vvy;
  RowDisk(const PassInputs& a, int i)
      : x(a.x[i]),
        y(a.y[i]),
        r(a.radius[i]),
        vx(a.vx[i]),
        vy(a.vy[i]),
        omega(a.omega[i]),
        vvx(a.vvx[i]),
        vvy(a.vvy[i]) {}
};

enum class Outcome { open, opened, closed };

// The law of pair p of `s` (the list's or a mirror's) between disk i (held in `di`) and j, for
// the sweep: updates the pair's state and, unless it was open before and after, gives its force
// (an opened pair keeps the share of its viscous force of the part of the step it was closed)
// and lists it in s.active (closed from next_closed on, opened from next_opened down). dx, dy:
// the branch vector of a closed pair.
template <bool Periodic, Sweep How>
[[gnu::always_inline]] inline Outcome pair_force(PairState& s, int p, int j, const RowDisk& di,
                                                 const PassInputs& a, const simd::PairBlock& kernel,
                                                 int range_begin, int& next_closed,
                                                 int& next_opened, PairForce& f, double& dx,
                                                 double& dy) {
  const auto separation = [&]() {
    dx = a.x[j] - di.x;
    dy = a.y[j] - di.y;
    if constexpr (Periodic) {
      dx = minimum_image(dx, a.l1, a.half_l1);
      dy = minimum_image(dy, a.l2, a.half_l2);
    }
  };
  double rj = 0.0;
  bool closed, was_closed;
  if constexpr (How == Sweep::step_simd) {
    const std::uint8_t flags = kernel.closed[p - range_begin];
    closed = (flags & simd::closed_now) != 0;
    was_closed = (flags & simd::was_closed) != 0;
  } else {
    separation();
    rj = a.radius[j];
    const double reach = di.r + rj;
    closed = !(dx * dx + dy * dy >= reach * reach);
    was_closed = s.f_n[p] > 0.0;
  }
  if (!closed) {
    if (!was_closed) return Outcome::open;  // open before and after: adds nothing
    // Opened during the step: the tangential state is dropped (SPEC §1.1), and the closing
    // half kick keeps the share of the viscous force of the part of the step it was closed.
    if constexpr (How == Sweep::step_simd) {
      separation();
      rj = a.radius[j];
    }
    double share = 0.0;
    if (a.dt > 0.0) {
      const ContactFrame frame = disk_disk_frame(dx, dy, di.r, rj);
      const double affine_x = Periodic ? a.k.rate_t1 * dx : 0.0;
      const double affine_y = Periodic ? a.k.rate_t2 * dy : 0.0;
      const double h_rate =
          deflection_rate(frame, a.vx[j] - di.vx + affine_x, a.vy[j] - di.vy + affine_y);
      share = viscous_share_opening(frame.h, h_rate, a.dt);
    }
    f = {0.0, 0.0, share * s.viscous_x[p], share * s.viscous_y[p], 0.0, 0.0};
    s.delta_t[p] = 0.0;
    s.f_n[p] = 0.0;
    s.active[--next_opened] = p;
    return Outcome::opened;
  }
  s.active[next_closed++] = p;
  if constexpr (How == Sweep::step_simd) {
    dx = s.lx[p];
    dy = s.ly[p];
    const int k = p - range_begin;
    f = {kernel.fx[k],  kernel.fy[k],       kernel.fvx[k],
         kernel.fvy[k], kernel.torque_i[k], kernel.torque_j[k]};
  } else {
    const auto keep_state = [&](double delta_t, double f_n, double nx, double ny) {
      s.delta_t[p] = delta_t;
      s.f_n[p] = f_n;
      s.nx[p] = nx;
      s.ny[p] = ny;
      s.lx[p] = dx;
      s.ly[p] = dy;
    };
    const ClosedPair<double> c = closed_pair_law<Periodic>(
        a.k, dx, dy, di.r, rj, di.vx, di.vy, di.omega, a.vx[j], a.vy[j], a.omega[j], di.vvx, di.vvy,
        a.vvx[j], a.vvy[j], s.alpha[p], s.delta_t[p], was_closed, keep_state);
    if constexpr (How == Sweep::evaluate) {
      s.viscous_x[p] = c.fvx;
      s.viscous_y[p] = c.fvy;
    }
    f = {c.fx, c.fy, c.fvx, c.fvy, c.torque_i, c.torque_j};
  }
  return Outcome::closed;
}

// With Sweep::step_simd, the kernel's distance tests and laws of the pairs [begin, end) of s
// (before the sweep reads them from its scratch); `touched`: how many it listed.
template <Sweep How>
[[gnu::always_inline]] inline simd::PairBlock run_kernel(DiskArrays& d, PairState& s,
                                                         const std::int32_t* read_j,
                                                         const ForceInputs& in, const PassInputs& a,
                                                         int begin, int end, int& touched) {
  [[maybe_unused]] simd::PairBlock kernel{};
  touched = 0;
  if constexpr (How == Sweep::step_simd) {
    thread_local KernelScratch scratch;
    kernel = scratch.view(d, s, read_j, in, end - begin);
    // A copy: a's address must not escape, or GCC reloads its members after every store.
    const PairLawConstants k = a.k;
    touched = simd::pair_law(kernel, k, in.periodic, a.l1, a.l2, begin, end);
  }
  return kernel;
}

// The SIMD sweep of the pairs [range_begin, range_end) that the kernel listed as touched
// (closed before or after the step), in list order: each adds to j's sum and subtracts from
// i's in memory. Row by row in ascending i, with j > i, these are the additions of
// pair_forces' scalar sweep in the same order (i's column part first, then its row), so the
// same bits; without a branch per listed pair or per row (mispredicted: a row lists 3-4
// pairs, about half of them closed).
template <bool Crossing, bool Periodic>
[[gnu::always_inline]] inline void touched_pair_forces(DiskArrays& d, PairArrays& pairs,
                                                       const PassInputs& a,
                                                       const simd::PairBlock& kernel, int touched,
                                                       int range_begin, int& next_closed,
                                                       int& next_opened, BlockSums& sums) {
  const std::int32_t* const pair_i = pairs.i.data();
  const std::int32_t* const pair_j = pairs.j_slot.data();  // j itself unless the pair crosses
  double* const fx = d.fx.data();
  double* const fy = d.fy.data();
  double* const fvx = d.fvx.data();
  double* const fvy = d.fvy.data();
  double* const torque = d.torque.data();
  for (int t = 0; t < touched; ++t) {
    const int k = kernel.touched[t];
    const int p = range_begin + k;
    const int i = pair_i[p], j = pair_j[p];
    PairForce f{};  // (GCC cannot tell that pair_force sets it: the pair is touched)
    double dx = 0.0, dy = 0.0;
    const bool closed = (kernel.closed[k] & simd::closed_now) != 0;
    if (closed) {
      pairs.active[next_closed++] = p;
      dx = pairs.lx[p];
      dy = pairs.ly[p];
      f = {kernel.fx[k],  kernel.fy[k],       kernel.fvx[k],
           kernel.fvy[k], kernel.torque_i[k], kernel.torque_j[k]};
    } else {  // opened during the step (rare)
      pair_force<Periodic, Sweep::step_simd>(pairs, p, j, RowDisk(a, i), a, kernel, range_begin,
                                             next_closed, next_opened, f, dx, dy);
    }
    if (!Crossing || !pairs.crossing[p]) add_to_j(d, j, f);
    fx[i] -= f.fx;
    fy[i] -= f.fy;
    fvx[i] -= f.fvx;
    fvy[i] -= f.fvy;
    torque[i] += f.torque_i;
    if (closed) add_stress(sums, f, dx, dy);
  }
}

// The pairs (rows) of the disks [first, end) of block b, added to both disks as they go (a
// crossing pair to i only). Also lists the block's closed pairs (from the start of its pair
// range) and the pairs that opened during the step (from the end), for the viscous pass.
template <bool Crossing, bool Periodic, Sweep How>
[[gnu::always_inline]] inline void pair_forces(DiskArrays& d, PairArrays& pairs,
                                               const ForceInputs& in, int b, int first, int end,
                                               BlockSums& block_sums) {
  // The sums in a local: through the reference, GCC keeps them in memory (3 instructions more
  // per closed pair when this function is not inlined).
  BlockSums sums = block_sums;
  const PassInputs a(d, in);
  const std::int32_t* const row_start = pairs.row_start.data();
  const std::int32_t* const pair_j = pairs.j_slot.data();  // j itself unless the pair crosses
  const int range_begin = row_start[first], range_end = row_start[end];
  int next_closed = range_begin, next_opened = range_end;
  int touched;
  const simd::PairBlock kernel =
      run_kernel<How>(d, pairs, pair_j, in, a, range_begin, range_end, touched);
  if constexpr (How == Sweep::step_simd) {
    touched_pair_forces<Crossing, Periodic>(d, pairs, a, kernel, touched, range_begin, next_closed,
                                            next_opened, sums);
  } else {
    for (int i = first; i < end; ++i) {
      const RowDisk di(a, i);
      // The column part of i's sums (pairs where i is j) is complete: those rows came first.
      RowSums row{d.fx[i], d.fy[i], d.fvx[i], d.fvy[i], d.torque[i]};
      const int row_end = row_start[i + 1];
      for (int p = row_start[i]; p < row_end; ++p) {
        const int j = pair_j[p];
        PairForce f;
        double dx, dy;
        const Outcome o = pair_force<Periodic, How>(pairs, p, j, di, a, kernel, range_begin,
                                                    next_closed, next_opened, f, dx, dy);
        if (o == Outcome::open) continue;
        add_pair<Crossing>(d, pairs, p, j, f, row);
        if (o == Outcome::closed) add_stress(sums, f, dx, dy);
      }
      d.fx[i] = row.fx;
      d.fy[i] = row.fy;
      d.fvx[i] = row.fvx;
      d.fvy[i] = row.fvy;
      d.torque[i] = row.torque;
    }
  }
  pairs.block_closed[b] = next_closed - range_begin;
  pairs.block_opened[b] = range_end - next_opened;
  block_sums = sums;
}

// The mirrors of `part` (pairs whose i lies in an earlier part), added to their disk j only,
// before the part's own rows: these pairs have the smallest partners of j's sum. The listed
// pair adds the stress.
template <bool Periodic, Sweep How>
[[gnu::always_inline]] inline void mirror_forces(DiskArrays& d, MirrorPairs& m,
                                                 const ForceInputs& in, int part) {
  const int begin = m.part_start[part], end = m.part_start[part + 1];
  int next_closed = begin, next_opened = end;
  if (begin < end) {
    const PassInputs a(d, in);
    int touched;
    const simd::PairBlock kernel = run_kernel<How>(d, m, m.j.data(), in, a, begin, end, touched);
    for (int p = begin; p < end; ++p) {
      const RowDisk di(a, m.i[p]);
      const int j = m.j[p];
      PairForce f;
      double dx, dy;
      const Outcome o = pair_force<Periodic, How>(m, p, j, di, a, kernel, begin, next_closed,
                                                  next_opened, f, dx, dy);
      if (o != Outcome::open) add_to_j(d, j, f);
    }
  }
  m.part_closed[part] = next_closed - begin;
  m.part_opened[part] = end - next_opened;
}

// The sweeps of a state's evaluation (rare) out of line, so that GCC inlines the sweeps of the
// time step into the pass (fewer instructions per block).
template <bool Crossing, bool Periodic>
[[gnu::noinline]] void pair_forces_evaluate(DiskArrays& d, PairArrays& pairs, const ForceInputs& in,
                                            int b, int first, int end, BlockSums& sums) {
  pair_forces<Crossing, Periodic, Sweep::evaluate>(d, pairs, in, b, first, end, sums);
}
template <bool Periodic>
[[gnu::noinline]] void mirror_forces_evaluate(DiskArrays& d, MirrorPairs& m, const ForceInputs& in,
                                              int part) {
  mirror_forces<Periodic, Sweep::evaluate>(d, m, in, part);
}

}  // namespace

namespace {
bool cpu_has_kernel() {
#if defined(__x86_64__)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl");
#else
  return false;
#endif
}
bool scalar_pairs_asked() {
  const char* v = std::getenv("GRANSTAB_SCALAR_PAIRS");
  return v != nullptr && *v != '\0' && std::string_view(v) != "0";
}
std::atomic<bool> simd_pairs_enabled{cpu_has_kernel() && !scalar_pairs_asked()};
}  // namespace

bool simd_pairs() { return simd_pairs_enabled.load(std::memory_order_relaxed); }

bool set_simd_pairs(bool enabled) {
  simd_pairs_enabled.store(enabled && cpu_has_kernel(), std::memory_order_relaxed);
  return simd_pairs();
}

void size_passes(std::size_t n, PairArrays& pairs, std::vector<BlockSums>& blocks) {
  const int nb = block_count(n);
  blocks.resize(2 * static_cast<std::size_t>(nb));
  pairs.block_closed.resize(nb);
  pairs.block_opened.resize(nb);
}

BlockSums sum_blocks(const std::vector<BlockSums>& blocks, std::size_t n, bool periodic) {
  return add_blocks(blocks, block_count(n), periodic);
}

// The order of add_blocks as a chain of segments: the pair blocks of part 0, 1, .. (thread t
// runs part t), then (walls) their disk blocks. Segment k's thread waits for the sum up to
// segment k - 1 (slot k - 1), adds its blocks, hands it on (slot k).
BlockSums relay_sum_blocks(const TeamMember& member, const std::vector<BlockSums>& blocks,
                           const PairArrays& pairs, std::size_t n, bool periodic,
                           Relay<BlockSums>& relay, std::uint32_t epoch) {
  const int nb = block_count(n);
  if (member.threads <= 1) return add_blocks(blocks, nb, periodic);
  const int team = member.threads, t = member.thread;
  const int segments = periodic ? team : 2 * team;
  BlockSums sum;
  for (int k = t; k < segments; k += team) {
    if (k > 0) {
      if (member.clock) member.clock->arrive();
      sum = relay.await(k - 1, epoch);
      if (member.clock) member.clock->leave();
    }
    const int offset = k < team ? 0 : nb;
    fold_blocks(sum, blocks, offset + pairs.part_block[t], offset + pairs.part_block[t + 1],
                periodic);
    relay.publish(k, sum, epoch);
  }
  if ((segments - 1) % team == t) return sum;
  if (member.clock) member.clock->arrive();
  sum = relay.await(segments - 1, epoch);
  if (member.clock) member.clock->leave();
  return sum;
}

void contact_forces_part(const TeamMember& member, DiskArrays& disks, PairArrays& pairs,
                         const ForceInputs& in, std::vector<BlockSums>& blocks) {
  const Cell cell = cell_of(in);
  // With the kick, the first half kick (kick_drift) has cleared the sums after using them.
  const auto clear = [&](int first, int end) {
    if (in.kick) return;
    for (auto* v : {&disks.fx, &disks.fy, &disks.fvx, &disks.fvy, &disks.torque}) {
      std::fill(v->begin() + first, v->begin() + end, 0.0);
    }
  };
  // The kernel in time steps only (Sweep).
  const Sweep how = !in.kick ? Sweep::evaluate : simd_pairs() ? Sweep::step_simd : Sweep::step;
  const auto mirrors = [&](int part) {
    with_flags(false, in.periodic, [&]<bool, bool Periodic>() {
      switch (how) {
        case Sweep::evaluate:
          mirror_forces_evaluate<Periodic>(disks, pairs.mirrors, in, part);
          break;
        case Sweep::step:
          mirror_forces<Periodic, Sweep::step>(disks, pairs.mirrors, in, part);
          break;
        case Sweep::step_simd:
          mirror_forces<Periodic, Sweep::step_simd>(disks, pairs.mirrors, in, part);
          break;
      }
    });
  };
  const auto rows = [&](int b, int first, int end, BlockSums& sums) {
    with_flags(
        pairs.block_crossing[b],
        in.periodic, [&]<bool Crossing, bool Periodic>() __attribute__((noinline)) {
          switch (how) {
            case Sweep::evaluate:
              pair_forces_evaluate<Crossing, Periodic>(disks, pairs, in, b, first, end, sums);
              break;
            case Sweep::step:
              pair_forces<Crossing, Periodic, Sweep::step>(disks, pairs, in, b, first, end, sums);
              break;
            case Sweep::step_simd:
              pair_forces<Crossing, Periodic, Sweep::step_simd>(disks, pairs, in, b, first, end,
                                                                sums);
              break;
          }
        });
  };
  const auto finish = [&](int i, BlockSums& sums) {
    const RowSums s{disks.fx[i], disks.fy[i], disks.fvx[i], disks.fvy[i], disks.torque[i]};
    finish_disk(disks, in, cell, i, false, s, sums);
  };
  run_part(member, disks, pairs, blocks, clear, mirrors, rows, true, finish);
}

BlockSums compute_contact_forces(DiskArrays& disks, PairArrays& pairs,
                                 const std::function<ForceInputs()>& inputs,
                                 std::vector<BlockSums>& blocks) {
  SpinBarrier barrier;
  const std::size_t n = disks.size();
  ForceInputs in = inputs();
  on_team(
      in.parallel ? omp_get_max_threads() : 1, barrier,
      [&](int team) {
        // The ghosts of the arrays this pass reads: a new plan fills them; a step leaves
        // omega's stale.
        if (pairs.team != team) {
          plan_parts(disks, pairs, even_parts(n, team));
        } else {
          fill_ghosts(disks, pairs.halo);
        }
        size_passes(n, pairs, blocks);
        in = inputs();  // a new plan may have moved the arrays (their ghosts)
      },
      [&](const TeamMember& member) { contact_forces_part(member, disks, pairs, in, blocks); });
  return sum_blocks(blocks, n, in.periodic);
}

}  // namespace granstab::dynamic
