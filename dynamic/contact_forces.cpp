#include "contact_forces.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <string_view>

#include "contact_forces_law.hpp"
#include "contact_forces_simd.hpp"
#include "force_pass_team.hpp"
#include "wall_forces.hpp"

namespace granstab::dynamic {
namespace {

// Adds a pair's force to its disks in the order of the sums (docs/dynamic.md,
// "Determinism"): j's running sum in memory (its rows come later), i's in registers. Gathered
// disks get theirs after the barrier from the pair's slot instead.
template <bool Gathering>
inline void add_pair(DiskArrays& d, PairArrays& pairs, int p, int j, const PairArrays::Force& f,
                     RowSums& row) {
  if constexpr (Gathering) {
    if (pairs.slotted[p]) pairs.force[p] = f;
    if (pairs.gathered[j]) {
      row.fx -= f.fx;
      row.fy -= f.fy;
      row.fvx -= f.fvx;
      row.fvy -= f.fvy;
      row.torque += f.torque_i;
      return;
    }
  }
  d.fx[j] += f.fx;
  d.fy[j] += f.fy;
  d.fvx[j] += f.fvx;
  d.fvy[j] += f.fvy;
  d.torque[j] += f.torque_j;
  row.fx -= f.fx;
  row.fy -= f.fy;
  row.fvx -= f.fvx;
  row.fvy -= f.fvy;
  row.torque += f.torque_i;
}

// Scratch of the SIMD kernel for one block's pairs (per thread; grown as needed).
struct KernelScratch {
  std::vector<std::uint8_t> closed;
  std::vector<double> fx, fy, fvx, fvy, torque_i, torque_j;
  simd::PairBlock view(DiskArrays& d, PairArrays& pairs, const ForceInputs& in, int count) {
    const std::size_t n = static_cast<std::size_t>(count) + simd::lanes - 1;
    if (closed.size() < n) {
      closed.resize(n);
      for (auto* v : {&fx, &fy, &fvx, &fvy, &torque_i, &torque_j}) v->resize(n);
    }
    simd::PairBlock v;
    v.x = d.x.data();
    v.y = d.y.data();
    v.radius = d.radius.data();
    v.vx = d.vx.data();
    v.vy = d.vy.data();
    v.omega = d.omega.data();
    v.vvx = in.vx_viscous;
    v.vvy = in.vy_viscous;
    v.pair_i = pairs.i.data();
    v.pair_j = pairs.j.data();
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
// viscous pass that follows rewrites every closed pair's viscous force (PairArrays::viscous_x,
// _y; with zeta = 0 there is none, but then every such force is a zero, and a zero of either
// sign leaves the sums, which start at +0, unchanged), so the force pass stores it only when it
// evaluates a state (no viscous pass follows; the next step's opening pairs read it).
enum class Sweep {
  evaluate,   // scalar law, stores the viscous forces
  step,       // scalar law
  step_simd,  // the SIMD kernel's law (same bits), read from its scratch
};

// The pairs (rows) of the disks [first, end) of block b, added to both disks as they go. Also
// lists the block's closed pairs (from the start of its pair range) and the pairs that opened
// during the step (from the end), for the viscous pass. With Sweep::step_simd, the kernel has
// done the distance test and the law of the block's pairs first and the sweep reads them from
// its scratch. The inputs are copied to locals: the stores into the force arrays could
// otherwise alias them.
template <bool Gathering, bool Periodic, Sweep How>
[[gnu::always_inline]] inline void pair_forces(DiskArrays& d, PairArrays& pairs,
                                               const ForceInputs& in, int b, int first, int end,
                                               BlockSums& block_sums) {
  // The sums in a local: through the reference, GCC keeps them in memory (3 instructions more
  // per closed pair when this function is not inlined).
  BlockSums sums = block_sums;
  const PairLawConstants k = law_constants(in);
  const double l1 = in.length[0], l2 = in.length[1], half_l1 = 0.5 * l1, half_l2 = 0.5 * l2;
  const double dt = in.dt;
  const double* const x = d.x.data();
  const double* const y = d.y.data();
  const double* const radius = d.radius.data();
  const double* const vx = d.vx.data();
  const double* const vy = d.vy.data();
  const double* const omega = d.omega.data();
  const double* const vvx = in.vx_viscous;
  const double* const vvy = in.vy_viscous;
  const std::int32_t* const row_start = pairs.row_start.data();
  const std::int32_t* const pair_j = pairs.j.data();
  const int range_begin = row_start[first], range_end = row_start[end];
  int next_closed = range_begin, next_opened = range_end;
  [[maybe_unused]] simd::PairBlock kernel{};
  if constexpr (How == Sweep::step_simd) {
    thread_local KernelScratch scratch;
    kernel = scratch.view(d, pairs, in, range_end - range_begin);
    simd::pair_law(kernel, k, Periodic, l1, l2, range_begin, range_end);
  }
  for (int i = first; i < end; ++i) {
    const double xi = x[i], yi = y[i], ri = radius[i];
    const double vxi = vx[i], vyi = vy[i], omega_i = omega[i];
    const double vvxi = vvx[i], vvyi = vvy[i];
    // The column part of i's sums (pairs where i is j) is complete: those rows came first.
    RowSums row{d.fx[i], d.fy[i], d.fvx[i], d.fvy[i], d.torque[i]};
    const int row_end = row_start[i + 1];
    for (int p = row_start[i]; p < row_end; ++p) {
      const int j = pair_j[p];
      const auto separation = [&](double& dx, double& dy) {
        dx = x[j] - xi;
        dy = y[j] - yi;
        if constexpr (Periodic) {
          dx = minimum_image(dx, l1, half_l1);
          dy = minimum_image(dy, l2, half_l2);
        }
      };
      double dx, dy, rj;
      bool closed, was_closed;
      if constexpr (How == Sweep::step_simd) {
        const std::uint8_t flags = kernel.closed[p - range_begin];
        closed = (flags & simd::closed_now) != 0;
        was_closed = (flags & simd::was_closed) != 0;
      } else {
        separation(dx, dy);
        rj = radius[j];
        const double reach = ri + rj;
        closed = !(dx * dx + dy * dy >= reach * reach);
        was_closed = pairs.f_n[p] > 0.0;
      }
      if (!closed) {
        if (!was_closed) {  // open before and after: adds nothing
          if constexpr (Gathering) {
            if (pairs.slotted[p]) pairs.force[p] = PairArrays::Force{};
          }
          continue;
        }
        // Opened during the step: the tangential state is dropped (SPEC §1.1), and the closing
        // half kick keeps the share of the viscous force of the part of the step it was closed.
        if constexpr (How == Sweep::step_simd) {
          separation(dx, dy);
          rj = radius[j];
        }
        double share = 0.0;
        if (dt > 0.0) {
          const ContactFrame f = disk_disk_frame(dx, dy, ri, rj);
          const double affine_x = Periodic ? k.rate_t1 * dx : 0.0;
          const double affine_y = Periodic ? k.rate_t2 * dy : 0.0;
          const double h_rate = deflection_rate(f, vx[j] - vxi + affine_x, vy[j] - vyi + affine_y);
          share = viscous_share_opening(f.h, h_rate, dt);
        }
        const PairArrays::Force out{
            0.0, 0.0, share * pairs.viscous_x[p], share * pairs.viscous_y[p], 0.0, 0.0};
        pairs.delta_t[p] = 0.0;
        pairs.f_n[p] = 0.0;
        pairs.active[--next_opened] = p;
        add_pair<Gathering>(d, pairs, p, j, out, row);
        continue;
      }
      pairs.active[next_closed++] = p;
      if constexpr (How == Sweep::step_simd) {
        dx = pairs.lx[p];
        dy = pairs.ly[p];
      }
      const PairArrays::Force f = [&]() -> PairArrays::Force {
        if constexpr (How == Sweep::step_simd) {
          const int s = p - range_begin;
          return {kernel.fx[s],  kernel.fy[s],       kernel.fvx[s],
                  kernel.fvy[s], kernel.torque_i[s], kernel.torque_j[s]};
        } else {
          const auto keep_state = [&](double delta_t, double f_n, double nx, double ny) {
            pairs.delta_t[p] = delta_t;
            pairs.f_n[p] = f_n;
            pairs.nx[p] = nx;
            pairs.ny[p] = ny;
            pairs.lx[p] = dx;
            pairs.ly[p] = dy;
          };
          const ClosedPair<double> c = closed_pair_law<Periodic>(
              k, dx, dy, ri, rj, vxi, vyi, omega_i, vx[j], vy[j], omega[j], vvxi, vvyi, vvx[j],
              vvy[j], pairs.alpha[p], pairs.delta_t[p], was_closed, keep_state);
          if constexpr (How == Sweep::evaluate) {
            pairs.viscous_x[p] = c.fvx;
            pairs.viscous_y[p] = c.fvy;
          }
          return {c.fx, c.fy, c.fvx, c.fvy, c.torque_i, c.torque_j};
        }
      }();
      add_pair<Gathering>(d, pairs, p, j, f, row);
      sums.sigma[0] += f.fx * dx;
      sums.sigma[1] += f.fx * dy;
      sums.sigma[2] += f.fy * dx;
      sums.sigma[3] += f.fy * dy;
      sums.sigma_viscous[0] += f.fvx * dx;
      sums.sigma_viscous[1] += f.fvy * dy;
    }
    d.fx[i] = row.fx;
    d.fy[i] = row.fy;
    d.fvx[i] = row.fvx;
    d.fvy[i] = row.fvy;
    d.torque[i] = row.torque;
  }
  pairs.block_closed[b] = next_closed - range_begin;
  pairs.block_opened[b] = range_end - next_opened;
  block_sums = sums;
}

// The sweep of a state's evaluation (rare) out of line, so that GCC inlines the sweeps of the
// time step into the pass (fewer instructions per block).
template <bool Gathering, bool Periodic>
[[gnu::noinline]] void pair_forces_evaluate(DiskArrays& d, PairArrays& pairs, const ForceInputs& in,
                                            int b, int first, int end, BlockSums& sums) {
  pair_forces<Gathering, Periodic, Sweep::evaluate>(d, pairs, in, b, first, end, sums);
}

// Viscous force only, at the velocities of in, over the closed pairs listed by pair_forces
// (whose frame it stored); pairs that opened during the step drop their share.
template <bool Gathering, bool Periodic>
[[gnu::always_inline]] inline void pair_viscous(DiskArrays& d, PairArrays& pairs,
                                                const ForceInputs& in, int b, int first, int end,
                                                BlockSums& sums) {
  const double rate_v1 = Periodic ? in.rate_viscous[0] : 0.0;
  const double rate_v2 = Periodic ? in.rate_viscous[1] : 0.0;
  const double* const vvx = in.vx_viscous;
  const double* const vvy = in.vy_viscous;
  double* const fvx_sum = d.fvx.data();
  double* const fvy_sum = d.fvy.data();
  const int range_begin = pairs.row_start[first], range_end = pairs.row_start[end];
  for (int k = range_end - pairs.block_opened[b]; k < range_end; ++k) {
    const int p = pairs.active[k];
    pairs.viscous_x[p] = pairs.viscous_y[p] = 0.0;
    if constexpr (Gathering) {
      if (pairs.slotted[p]) pairs.force[p].fvx = pairs.force[p].fvy = 0.0;
    }
  }
  const int closed_end = range_begin + pairs.block_closed[b];
  for (int k = range_begin; k < closed_end; ++k) {
    const int p = pairs.active[k];
    const int i = pairs.i[p], j = pairs.j[p];
    const double dx = pairs.lx[p], dy = pairs.ly[p];
    ContactFrame f{};
    f.nx = pairs.nx[p];
    f.ny = pairs.ny[p];
    const double affine_vx = Periodic ? rate_v1 * dx : 0.0;
    const double affine_vy = Periodic ? rate_v2 * dy : 0.0;
    const double h_rate =
        deflection_rate(f, vvx[j] - vvx[i] + affine_vx, vvy[j] - vvy[i] + affine_vy);
    const double f_v = pairs.alpha[p] * h_rate;  // as contact_force() computes it
    const double fvx = f_v * f.nx, fvy = f_v * f.ny;
    pairs.viscous_x[p] = fvx;
    pairs.viscous_y[p] = fvy;
    sums.sigma_viscous[0] += fvx * dx;
    sums.sigma_viscous[1] += fvy * dy;
    // Rows in ascending i: j's sum gets its column part, i's its row part, in order.
    if constexpr (Gathering) {
      if (pairs.slotted[p]) {
        pairs.force[p].fvx = fvx;
        pairs.force[p].fvy = fvy;
      }
      if (!pairs.gathered[j]) {
        fvx_sum[j] += fvx;
        fvy_sum[j] += fvy;
      }
      if (!pairs.gathered[i]) {
        fvx_sum[i] -= fvx;
        fvy_sum[i] -= fvy;
      }
    } else {
      fvx_sum[j] += fvx;
      fvy_sum[j] += fvy;
      fvx_sum[i] -= fvx;
      fvy_sum[i] -= fvy;
    }
  }
}

// The disk's forces once its pair sums are complete: walls, then the external force, then
// (if asked) the second half kick.
[[gnu::always_inline]] inline void finish_disk(DiskArrays& d, const ForceInputs& in,
                                               const Cell& cell, int i, bool viscous_only,
                                               RowSums s, BlockSums& sums) {
  if (!in.periodic) {
    wall_forces(d, in, cell, i, viscous_only, s.fx, s.fy, s.fvx, s.fvy, s.torque, sums);
  }
  d.fvx[i] = s.fvx;
  d.fvy[i] = s.fvy;
  if (viscous_only) return;
  if (!d.ext_fx.empty()) {
    s.fx += d.ext_fx[i];
    s.fy += d.ext_fy[i];
  }
  d.fx[i] = s.fx;
  d.fy[i] = s.fy;
  d.torque[i] = s.torque;
  if (in.kick) {
    const double half = 0.5 * in.dt;
    d.vx[i] += half * (s.fx + s.fvx) * d.inv_mass[i];
    d.vy[i] += half * (s.fy + s.fvy) * d.inv_mass[i];
    d.omega[i] += half * s.torque * d.inv_inertia[i];
    // The viscous pass that follows adds the viscous forces of the final velocities into
    // these (compute_viscous_forces).
    d.fvx[i] = 0.0;
    d.fvy[i] = 0.0;
  }
}

// Calls f.operator()<Gathering, Periodic>() with the two flags as compile-time constants (the
// pair loops are specialised on them).
template <class F>
void with_flags(bool gathering, bool periodic, F f) {
  const auto on_periodic = [&]<bool Gathering>() {
    if (periodic) {
      f.template operator()<Gathering, true>();
    } else {
      f.template operator()<Gathering, false>();
    }
  };
  if (gathering) {
    on_periodic.template operator()<true>();
  } else {
    on_periodic.template operator()<false>();
  }
}

Cell cell_of(const ForceInputs& in) {
  Cell cell;
  cell.boundary = in.periodic ? Boundary::periodic : Boundary::walls;
  cell.length = in.length;
  return cell;
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

std::vector<std::int32_t> even_parts(std::size_t n, int team) {
  const long long nb = block_count(n);
  std::vector<std::int32_t> part_block(team + 1);
  for (int k = 0; k <= team; ++k) part_block[k] = static_cast<std::int32_t>(nb * k / team);
  return part_block;
}

bool valid_parts(const std::vector<std::int32_t>& part_block, std::size_t n, int team) {
  if (static_cast<int>(part_block.size()) != team + 1 || part_block.front() != 0 ||
      part_block.back() != block_count(n)) {
    return false;
  }
  for (int k = 0; k < team; ++k)
    if (part_block[k + 1] <= part_block[k]) return false;
  return true;
}

std::vector<std::int32_t> balanced_parts(const std::vector<std::int32_t>& part_block,
                                         const std::vector<double>& busy, double tolerance) {
  const int team = static_cast<int>(part_block.size()) - 1;
  if (team < 2 || static_cast<int>(busy.size()) != team) return part_block;
  double mean = 0.0, worst = 0.0, speed_sum = 0.0;
  std::vector<double> speed(team);
  for (int k = 0; k < team; ++k) {
    if (!(busy[k] > 0.0)) return part_block;
    mean += busy[k] / team;
    worst = std::max(worst, busy[k]);
    speed[k] = (part_block[k + 1] - part_block[k]) / busy[k];
    speed_sum += speed[k];
  }
  if (worst <= (1.0 + tolerance) * mean) return part_block;
  // Each part moves half way towards the size its thread's speed would finish with the others.
  const double blocks = part_block.back();
  std::vector<std::int32_t> out = part_block;
  double target_start = 0.0;
  for (int k = 1; k < team; ++k) {
    target_start += blocks * speed[k - 1] / speed_sum;
    const double moved = part_block[k] + 0.5 * (target_start - part_block[k]);
    out[k] = static_cast<std::int32_t>(std::lround(moved));
  }
  for (int k = 1; k < team; ++k)  // at least one block per part
    out[k] = std::clamp(out[k], out[k - 1] + 1, part_block.back() - (team - k));
  return out;
}

void plan_parts(PairArrays& pairs, std::size_t n, const std::vector<std::int32_t>& part_block,
                bool periodic) {
  plan_team(pairs, static_cast<int>(n), part_block, !periodic);
}

std::array<int, 2> part_disks(const PairArrays& pairs, std::size_t n, int part) {
  const int end = static_cast<int>(n);
  return {std::min(end, pairs.part_block[part] * block_size),
          std::min(end, pairs.part_block[part + 1] * block_size)};
}

void size_passes(std::size_t n, PairArrays& pairs, std::vector<BlockSums>& blocks) {
  const int nb = block_count(n);
  blocks.resize(2 * static_cast<std::size_t>(nb));
  pairs.block_closed.resize(nb);
  pairs.block_opened.resize(nb);
}

BlockSums sum_blocks(const std::vector<BlockSums>& blocks, std::size_t n) {
  return add_blocks(blocks, 2 * block_count(n));
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
  const auto rows = [&](int b, int first, int end, BlockSums& sums) {
    with_flags(pairs.block_slotted[b], in.periodic, [&]<bool Gathering, bool Periodic>() {
      switch (how) {
        case Sweep::evaluate:
          pair_forces_evaluate<Gathering, Periodic>(disks, pairs, in, b, first, end, sums);
          break;
        case Sweep::step:
          pair_forces<Gathering, Periodic, Sweep::step>(disks, pairs, in, b, first, end, sums);
          break;
        case Sweep::step_simd:
          pair_forces<Gathering, Periodic, Sweep::step_simd>(disks, pairs, in, b, first, end, sums);
          break;
      }
    });
  };
  const auto finish = [&](int i, bool gathered, BlockSums& sums) {
    const RowSums s =
        gathered ? gather(pairs, i)
                 : RowSums{disks.fx[i], disks.fy[i], disks.fvx[i], disks.fvy[i], disks.torque[i]};
    finish_disk(disks, in, cell, i, false, s, sums);
  };
  run_part(member, disks, pairs, blocks, clear, rows, finish);
}

void viscous_forces_part(const TeamMember& member, DiskArrays& disks, PairArrays& pairs,
                         const ForceInputs& in, std::vector<BlockSums>& blocks) {
  const Cell cell = cell_of(in);
  const auto clear = [](int, int) {};  // the force pass with the kick left zeros
  const auto rows = [&](int b, int first, int end, BlockSums& sums) {
    with_flags(pairs.block_slotted[b], in.periodic, [&]<bool Gathering, bool Periodic>() {
      pair_viscous<Gathering, Periodic>(disks, pairs, in, b, first, end, sums);
    });
  };
  const auto finish = [&](int i, bool gathered, BlockSums& sums) {
    RowSums s{0.0, 0.0, disks.fvx[i], disks.fvy[i], 0.0};
    if (gathered) s = gather(pairs, i);
    if (in.periodic && !gathered) return;  // the sums are complete already
    finish_disk(disks, in, cell, i, true, s, sums);
  };
  run_part(member, disks, pairs, blocks, clear, rows, finish);
}

BlockSums compute_contact_forces(DiskArrays& disks, PairArrays& pairs, const ForceInputs& in,
                                 std::vector<BlockSums>& blocks) {
  SpinBarrier barrier;
  const std::size_t n = disks.size();
  on_team(
      in.parallel ? omp_get_max_threads() : 1, barrier,
      [&](int team) {
        if (pairs.team != team) plan_parts(pairs, n, even_parts(n, team), in.periodic);
        size_passes(n, pairs, blocks);
      },
      [&](const TeamMember& member) { contact_forces_part(member, disks, pairs, in, blocks); });
  return sum_blocks(blocks, n);
}

}  // namespace granstab::dynamic
