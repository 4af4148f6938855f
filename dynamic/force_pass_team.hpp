#pragma once
// A pass's run over a team's parts (mirrors, rows, disks, sums) and each disk's completion
// (walls, external force, half kick), apart from the pair physics. Included, in an anonymous
// namespace, by the two passes of a step (contact_forces.cpp, viscous_forces.cpp), so that each
// stays one translation unit and the compiler inlines its sweeps into run_part().
#include <omp.h>

#include <algorithm>
#include <vector>

#include "contact_forces.hpp"
#include "team.hpp"
#include "wall_forces.hpp"

namespace granstab::dynamic {
namespace {

// The blocks' sums added in block order. In a periodic cell the disks' blocks (from nb on) and
// the wall forces are zeros (+0), which leave a sum that starts at +0 unchanged: they are not
// read, which spares each thread the lines the others wrote (cross-core misses, ~230 ns each on
// the AMD VM; 2 x 176 blocks per step at N = 5600).
inline void fold_blocks(BlockSums& total, const std::vector<BlockSums>& blocks, int begin, int end,
                        bool periodic) {
  for (int b = begin; b < end; ++b) {
    for (int k = 0; k < 4; ++k) total.sigma[k] += blocks[b].sigma[k];
    for (int k = 0; k < 2; ++k) total.sigma_viscous[k] += blocks[b].sigma_viscous[k];
    if (periodic) continue;
    for (int k = 0; k < 2; ++k) {
      total.wall_force[k] += blocks[b].wall_force[k];
      total.wall_force_viscous[k] += blocks[b].wall_force_viscous[k];
    }
  }
}

inline BlockSums add_blocks(const std::vector<BlockSums>& blocks, int nb, bool periodic) {
  BlockSums total;
  fold_blocks(total, blocks, 0, periodic ? nb : 2 * nb, periodic);
  return total;
}

// A disk's pair sums while its row is swept.
struct RowSums {
  double fx, fy, fvx, fvy, torque;
};

// One thread's share of a pass over the pairs (its parts: each a fixed range of whole blocks):
// per part, it clears its disks' sums, adds the part's mirrors into them, then sweeps the rows
// of its blocks and completes each disk after its block's rows. No disk gets additions from
// another thread, so no barrier is needed inside. Per-block sums go to `blocks` (pairs first,
// then disks); sum_blocks adds them in block order, so every reduction is thread-independent.
// A thread running several parts runs them in order: the same additions as their threads.
// finish_disks = false: the disks' sums are complete after the rows (no finish, no disk sums).
template <class Clear, class Mirrors, class Rows, class Finish>
void run_part(const TeamMember& member, DiskArrays& disks, PairArrays& pairs,
              std::vector<BlockSums>& blocks, Clear clear, Mirrors mirrors, Rows rows,
              bool finish_disks, Finish finish) {
  const int n = static_cast<int>(disks.size());
  const int nb = block_count(disks.size());
  for (int part = member.part_first; part < member.part_end; ++part) {
    const int b0 = pairs.part_block[part], b1 = pairs.part_block[part + 1];
    clear(b0 * block_size, std::min(n, b1 * block_size));
    mirrors(part);
    for (int b = b0; b < b1; ++b) {
      const int first = b * block_size, end = std::min(n, first + block_size);
      BlockSums sums;
      rows(b, first, end, sums);
      blocks[b] = sums;
      BlockSums disk_sums;
      if (finish_disks) {
        for (int i = first; i < end; ++i) finish(i, disk_sums);
      }
      blocks[nb + b] = disk_sums;
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
    d.vx[i] = in.vx[i] + half * (s.fx + s.fvx) * d.inv_mass[i];  // from the mid-step ones
    d.vy[i] = in.vy[i] + half * (s.fy + s.fvy) * d.inv_mass[i];
    d.omega[i] = in.omega[i] + half * s.torque * d.inv_inertia[i];
    // The viscous pass that follows adds the viscous forces of the final velocities into
    // these (viscous_forces_part).
    d.fvx[i] = 0.0;
    d.fvy[i] = 0.0;
  }
}

// Calls f.operator()<Crossing, Periodic>() with the two flags as compile-time constants (the
// pair loops are specialised on them).
template <class F>
void with_flags(bool crossing, bool periodic, F f) {
  const auto on_periodic = [&]<bool Crossing>() {
    if (periodic) {
      f.template operator()<Crossing, true>();
    } else {
      f.template operator()<Crossing, false>();
    }
  };
  if (crossing) {
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
}  // namespace granstab::dynamic
