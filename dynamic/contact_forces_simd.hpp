#pragma once
// The SIMD kernel of the force pass (contact_forces_simd.cpp, compiled for AVX-512 and called
// only where the CPU has it, see simd_pairs()): the distance test and the contact law of a
// block's listed pairs, eight pairs at a time, with the pair state stored for the closed ones and
// their forces left in a scratch for the scalar sweep that adds them to the disks in the order of
// the sums. Used in time steps only (ForceInputs::kick), where the viscous pass that follows
// rewrites every closed pair's viscous force, so the kernel does not store it (contact_forces.cpp,
// Sweep). Plain pointers only:
// that translation unit is compiled with -mavx512f and must not instantiate any inline function
// that the rest of the program could link to (std::vector's included).
#include <cstdint>

#include "contact_forces_law.hpp"

namespace granstab::dynamic::simd {

struct PairBlock {
  // Disks (read).
  const double *x, *y, *radius, *vx, *vy, *omega, *vvx, *vvy;
  // Pairs: i, j, alpha (read); the state of a closed pair (written for closed pairs only;
  // f_n is also read: f_n > 0 is "closed before the step").
  const std::int32_t *pair_i, *pair_j;
  const double* alpha;
  double *delta_t, *f_n, *nx, *ny, *lx, *ly;
  // Scratch, indexed from the first pair of the range, padded by lanes - 1: the pair's flags
  // (closed_now, was_closed: f_n > 0 before the step), and for closed pairs their force of i on j.
  std::uint8_t* closed;
  double *fx, *fy, *fvx, *fvy, *torque_i, *torque_j;
  // The indices (from the first pair) of the pairs closed before or after the step, in order:
  // the only ones the sweep adds, which then needs no branch per listed pair.
  std::int32_t* touched;
};

inline constexpr int lanes = 8;
inline constexpr std::uint8_t closed_now = 1, was_closed = 2;  // PairBlock::closed

// Pairs [begin, end) of the lists; returns the number of touched pairs. (Not x86-64: a stub
// that is never called.)
int pair_law(const PairBlock& b, const PairLawConstants& k, bool periodic, double l1, double l2,
             int begin, int end);

}  // namespace granstab::dynamic::simd
