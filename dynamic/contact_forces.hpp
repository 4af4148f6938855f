#pragma once
// Contact forces of one step from the common contact law (common/contact_law.hpp, SPEC §1.1).
// Parallel over fixed blocks of disks; every disk sums its pairs in ascending partner order
// (added as the rows are swept; a pair whose disks lie in two threads' parts is computed by
// both, each adding to its own disk: PairArrays::mirrors): the result is independent of the
// thread count and of when the Verlet list was last rebuilt (open pairs contribute nothing).
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "common/material.hpp"
#include "state.hpp"
#include "parts.hpp"
#include "team.hpp"

namespace granstab::dynamic {

struct ForceInputs {
  const Material* material = nullptr;
  bool periodic = true;
  std::array<double, 2> length{1.0, 1.0};
  // Time over which the tangential displacement is incremented (0: evaluate the state as is).
  double dt = 0.0;
  // Velocities entering the tangential increment (mid-step) and the viscous force (end of step):
  // periodic cells, affine strain rates dL_a/dt / L_a; walls, velocities of the mobile walls.
  std::array<double, 2> rate_tangential{0.0, 0.0};
  std::array<double, 2> rate_viscous{0.0, 0.0};
  // Disk velocities of the contact law (in a time step, those at t + dt/2, which the drift left
  // in DiskArrays::vx ..).
  const double* vx = nullptr;
  const double* vy = nullptr;
  const double* omega = nullptr;
  const double* vx_viscous = nullptr;  // disk velocities for the viscous force
  const double* vy_viscous = nullptr;
  // Run the per-block loops on the OpenMP team (false: on the calling thread; small samples,
  // where the synchronisation costs more than the work). The result is the same bits either way.
  bool parallel = true;
  // Also the second half kick of the disks, v(t + dt) = v(t + dt/2) + dt/2 a(t + dt) (same for
  // omega), as soon as a disk's forces are complete (the cell's half kick is the caller's).
  bool kick = false;
};

// Elastic, frictional and viscous forces of a state (no increment of delta_t unless in.dt > 0),
// on a team of its own (in.parallel) or the calling thread, with the inputs that `inputs` gives
// (called again once the team is planned: a new plan may move the disk arrays). Sums (stress,
// wall forces) of the whole sample are returned; blocks is scratch space.
BlockSums compute_contact_forces(DiskArrays& disks, PairArrays& pairs,
                                 const std::function<ForceInputs()>& inputs,
                                 std::vector<BlockSums>& blocks);

// --- the passes of a time step, run by a team inside one parallel region (engine.cpp) -------
// Each thread runs its part (parts.hpp): no sum depends on the split (docs/dynamic.md,
// "Determinism"). size_passes sizes the per-block scratch.
void size_passes(std::size_t n, PairArrays& pairs, std::vector<BlockSums>& blocks);

// The force pass of the member's part (pairs.team must be member.threads): updates delta_t,
// writes the per-disk sums and the per-block sums into blocks; with in.kick the per-disk sums
// must be zero on entry (kick_drift leaves them so), the disks get their second half kick as
// soon as their sums are complete (from in.vx ..: the mid-step velocities, which the pass reads
// and does not write), and fvx, fvy are left zero (viscous_forces_part adds into them). No
// barrier inside: after a barrier of the team, sum_blocks gives the sums of the sample.
void contact_forces_part(const TeamMember& member, DiskArrays& disks, PairArrays& pairs,
                         const ForceInputs& in, std::vector<BlockSums>& blocks);

// The viscous forces alone (viscous_forces.cpp), for the velocities in.vx_viscous /
// in.rate_viscous, with the contact geometry of the last contact_forces_part, which must have
// been run with in.kick (fills disks.fvx, fvy). No barrier inside: the block sums are complete
// after the next one.
void viscous_forces_part(const TeamMember& member, DiskArrays& disks, PairArrays& pairs,
                         const ForceInputs& in, std::vector<BlockSums>& blocks);

// The sample's sums of the last pass: the block sums added in block order (the same bits on
// every thread and for every team size).
BlockSums sum_blocks(const std::vector<BlockSums>& blocks, std::size_t n, bool periodic);
// The same sums on a team, without a barrier: each thread adds its own parts' blocks to the
// running sum of the threads before it in block order and hands it on (relay: 2 x team slots,
// reset before the team starts; epoch: 1, 2, .. for the team's successive reductions); every
// thread gets the total from the last. Each thread reads its own blocks and a few lines of the
// others', where sum_blocks reads every block (on the AMD VM the other core's lines cost
// ~230 ns each). Same bits as sum_blocks. pairs.part_block: the team's parts, one per thread.
BlockSums relay_sum_blocks(const TeamMember& member, const std::vector<BlockSums>& blocks,
                           const PairArrays& pairs, std::size_t n, bool periodic,
                           Relay<BlockSums>& relay, std::uint32_t epoch);

// Whether the force pass of a time step runs its distance tests and contact laws in the SIMD
// kernel (contact_forces_simd.hpp; AVX-512, chosen at run time) rather than in the scalar pair
// loop, and the drift its half kick and drift in integrator_simd.hpp's kernel: the same bits
// either way. On where the CPU has AVX-512 (F, DQ, BW, VL), unless the environment variable
// GRANSTAB_SCALAR_PAIRS is set (and not 0) at start-up. set_simd_pairs(false) forces the scalar
// loops (tests, comparisons); returns whether the kernels are now used.
bool simd_pairs();
bool set_simd_pairs(bool enabled);

}  // namespace granstab::dynamic
