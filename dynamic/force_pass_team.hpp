#pragma once
// The force pass's split over the team (parts, gathered blocks, sums), apart from the pair physics.
// Included by contact_forces.cpp only, in an anonymous namespace: the force pass stays one
// translation unit, so the compiler inlines the sweeps and gather() into run_part().
#include <omp.h>

#include <algorithm>
#include <vector>

#include "contact_forces.hpp"
#include "team.hpp"

namespace granstab::dynamic {
namespace {

int block_count(std::size_t n) { return static_cast<int>((n + block_size - 1) / block_size); }

BlockSums add_blocks(const std::vector<BlockSums>& blocks, int count) {
  BlockSums total;
  for (int b = 0; b < count; ++b) {
    for (int k = 0; k < 4; ++k) total.sigma[k] += blocks[b].sigma[k];
    for (int k = 0; k < 2; ++k) {
      total.sigma_viscous[k] += blocks[b].sigma_viscous[k];
      total.wall_force[k] += blocks[b].wall_force[k];
      total.wall_force_viscous[k] += blocks[b].wall_force_viscous[k];
    }
  }
  return total;
}

// A disk's pair sums: running while its rows are swept, or collected from the slots (gather).
struct RowSums {
  double fx, fy, fvx, fvy, torque;
};

// Pair sums of a disk of a gathered block from the slots, in ascending partner order: pairs
// where the disk is j (partners < i), then pairs where it is i (partners > i).
RowSums gather(const PairArrays& pairs, int i) {
  RowSums s{0.0, 0.0, 0.0, 0.0, 0.0};
  for (int k = pairs.column_start[i]; k < pairs.column_start[i + 1]; ++k) {
    const PairArrays::Force& f = pairs.force[pairs.column_pair[k]];
    s.fx += f.fx;
    s.fy += f.fy;
    s.fvx += f.fvx;
    s.fvy += f.fvy;
    s.torque += f.torque_j;
  }
  for (int p = pairs.row_start[i]; p < pairs.row_start[i + 1]; ++p) {
    const PairArrays::Force& f = pairs.force[p];
    s.fx -= f.fx;
    s.fy -= f.fy;
    s.fvx -= f.fvx;
    s.fvy -= f.fvy;
    s.torque += f.torque_i;
  }
  return s;
}

// Which disks a split into parts (their first blocks, part_block) must gather (see PairArrays):
// those whose first partner (smallest i of its column) lies before the start of their part. With
// walls, whole blocks: a block's disk sums (the walls') are then added in disk order after the
// barrier.
void plan_team(PairArrays& pairs, int n, const std::vector<std::int32_t>& part_block,
               bool whole_blocks) {
  const int nb = block_count(static_cast<std::size_t>(n));
  const int team = static_cast<int>(part_block.size()) - 1;
  pairs.part_block = part_block;
  pairs.gathered.assign(n, 0);
  pairs.block_gathered.assign(nb, 0);
  pairs.any_gathered = false;
  for (int part = 0; part < team; ++part) {
    const int b0 = part_block[part], b1 = part_block[part + 1];
    const int part_first = b0 * block_size;
    for (int k = part_first; k < std::min(n, b1 * block_size); ++k) {
      const int s = pairs.column_start[k];
      if (s < pairs.column_start[k + 1] && pairs.i[pairs.column_pair[s]] < part_first) {
        pairs.gathered[k] = 1;
        pairs.block_gathered[k / block_size] = 1;
        pairs.any_gathered = true;
      }
    }
  }
  if (whole_blocks) {
    for (int k = 0; k < n; ++k) pairs.gathered[k] = pairs.block_gathered[k / block_size];
  }
  pairs.slotted.resize(pairs.size());
  pairs.block_slotted.assign(nb, 0);
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    pairs.slotted[p] = pairs.gathered[pairs.i[p]] | pairs.gathered[pairs.j[p]];
    pairs.block_slotted[pairs.i[p] / block_size] |= pairs.slotted[p];
  }
  pairs.team = team;
  pairs.whole_blocks = whole_blocks;
}

// One thread's share of a pass over the pairs (its part: a fixed range of whole blocks): it
// clears its disks' sums, sweeps the rows of its blocks and completes each disk that is not
// gathered after its block's rows; after a barrier (only if some disk is gathered) it completes
// its gathered disks from the slots. Per-block sums go to `blocks` (pairs first, then disks);
// sum_blocks adds them in block order, so every reduction is thread-independent. Periodic cells
// have no disk sums (those are the walls'): the zeros of the blocks with gathered disks are written
// before the barrier, so that after it only the disks' own arrays are still being written and the
// team may take the sums.
template <class Clear, class Rows, class Finish>
void run_part(const TeamMember& member, DiskArrays& disks, PairArrays& pairs,
              std::vector<BlockSums>& blocks, Clear clear, Rows rows, Finish finish) {
  const int n = static_cast<int>(disks.size());
  const int nb = block_count(disks.size());
  const int b0 = pairs.part_block[member.part_first];
  const int b1 = pairs.part_block[member.part_end];
  clear(b0 * block_size, std::min(n, b1 * block_size));
  // A thread running several parts sweeps them in order: the running sums of a disk then get
  // their additions in the order of one thread's sweep, and a gathered disk's slots are all
  // written before the (skipped) barrier.
  for (int b = b0; b < b1; ++b) {
    const int first = b * block_size, end = std::min(n, first + block_size);
    BlockSums sums;
    rows(b, first, end, sums);
    blocks[b] = sums;
    if (!pairs.block_gathered[b]) {
      BlockSums disk_sums;
      for (int i = first; i < end; ++i) finish(i, false, disk_sums);
      blocks[nb + b] = disk_sums;
    } else if (!pairs.whole_blocks) {  // periodic: no disk sums
      BlockSums none;
      for (int i = first; i < end; ++i) {
        if (!pairs.gathered[i]) finish(i, false, none);
      }
      blocks[nb + b] = BlockSums{};
    }
  }
  if (!pairs.any_gathered) return;
  member.sync();
  for (int b = b0; b < b1; ++b) {
    if (!pairs.block_gathered[b]) continue;
    const int first = b * block_size, end = std::min(n, first + block_size);
    BlockSums disk_sums;
    for (int i = first; i < end; ++i) {
      if (pairs.gathered[i]) finish(i, true, disk_sums);
    }
    if (pairs.whole_blocks) blocks[nb + b] = disk_sums;
  }
}

}  // namespace
}  // namespace granstab::dynamic
