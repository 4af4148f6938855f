#pragma once
// Contact forces of one step from the common contact law (common/contact_law.hpp, SPEC §1.1).
// Parallel over fixed blocks of disks; every disk sums its pairs in ascending partner order
// (added as the rows are swept, or gathered from per-pair slots after a barrier for the few
// disks that have partners in another thread's part): the result is independent of the thread
// count and of when the Verlet list was last rebuilt (open pairs contribute nothing).
#include <vector>

#include "common/material.hpp"
#include "state.hpp"

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
  const double* vx_viscous = nullptr;  // disk velocities for the viscous force
  const double* vy_viscous = nullptr;
  // Run the per-block loops on the OpenMP team (false: on the calling thread; small samples,
  // where the synchronisation costs more than the work). The result is the same bits either way.
  bool parallel = true;
  // Also the second half kick of the disks, v(t + dt) = v(t + dt/2) + dt/2 a(t + dt) (same for
  // omega), as soon as a disk's forces are complete (the cell's half kick is the caller's).
  bool kick = false;
};

// Elastic, frictional and viscous forces; updates delta_t of pairs and walls. Sums (stress,
// wall forces) of the whole sample are returned; blocks is scratch space. With in.kick the
// per-disk sums fx, fy, fvx, fvy, torque must be zero on entry (kick_drift leaves them so),
// and fvx, fvy are zero again on return (they are what compute_viscous_forces adds into).
BlockSums compute_contact_forces(DiskArrays& disks, PairArrays& pairs, const ForceInputs& in,
                                 std::vector<BlockSums>& blocks);

// The viscous forces alone, for the velocities in.vx_viscous / in.rate_viscous, with the
// contact geometry of the last compute_contact_forces, which must have been run with in.kick
// (fills disks.fvx, fvy; it adds into the zeros that pass left).
BlockSums compute_viscous_forces(DiskArrays& disks, PairArrays& pairs, const ForceInputs& in,
                                 std::vector<BlockSums>& blocks);

// Whether the force pass of a time step runs its distance tests and contact laws in the SIMD
// kernel (contact_forces_simd.hpp; AVX-512, chosen at run time) rather than in the scalar pair
// loop: the same bits either way. On where the CPU has AVX-512 (F, DQ, BW, VL), unless the
// environment variable GRANSTAB_SCALAR_PAIRS is set (and not 0) at start-up. set_simd_pairs(false)
// forces the scalar loop (tests, comparisons); returns whether the kernel is now used.
bool simd_pairs();
bool set_simd_pairs(bool enabled);

}  // namespace granstab::dynamic
