#pragma once
// A team's halo (Halo, state.hpp): which disks each part reads from the others, their ghost
// slots, and the copies that keep the ghosts equal to their disks (the same bits, so the passes
// give what they give without a halo).
#include <cstdint>
#include <vector>

#include "state.hpp"

namespace granstab::dynamic {

// After plan_parts has marked the crossing pairs and built the mirrors: each part's ghosts, the
// pairs' j_slot and the mirrors' i, then every ghost filled (fill_ghosts). part_of_block: the
// part of each block.
void plan_halo(DiskArrays& disks, PairArrays& pairs,
               const std::vector<std::int32_t>& part_of_block);

// Copies every array a pass may read into the ghosts (one thread; a state's evaluation, a new
// plan).
void fill_ghosts(DiskArrays& disks, const Halo& halo);

// In a time step, per part: its owner packs the values its ghosts on other parts need, the
// ghosts' part copies them out after a barrier. The mid-step values (x, y, vx, vy, omega, vpx,
// vpy) after the drift, for the force pass; the final velocities (vx, vy) after the force
// pass, for the viscous one.
void pack_mid_step(const DiskArrays& disks, Halo& halo, int part);
void unpack_mid_step(DiskArrays& disks, const Halo& halo, int part);
void pack_final(const DiskArrays& disks, Halo& halo, int part);
void unpack_final(DiskArrays& disks, const Halo& halo, int part);

}  // namespace granstab::dynamic
