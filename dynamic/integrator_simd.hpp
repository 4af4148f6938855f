#pragma once
// The drift's SIMD kernel (integrator_simd.cpp, compiled for AVX-512 and called only where the
// CPU has it, under the same switch as the force pass's kernel: simd_pairs()): the first half
// kick and the drift of kick_drift_disks, eight disks at a time, the same bits as the scalar
// loop (both instantiate drift_disk). Plain pointers only, as contact_forces_simd.hpp.
#include "integrator.hpp"

namespace granstab::dynamic::simd {

struct DriftBlock {
  double *x, *y;
  double *vx, *vy, *omega;  // at t, then (written) at t + dt/2
  double *vpx, *vpy, *theta;
  double *fx, *fy, *fvx, *fvy, *torque;  // read, then cleared
  const double *inv_mass, *inv_inertia, *ref_x, *ref_y;
};

// Disks [first, end); returns the largest squared non-affine displacement among them.
// (Not x86-64: a stub that is never called.)
double kick_drift(const DriftBlock &b, const DriftConstants &k, bool periodic, int first, int end);

}  // namespace granstab::dynamic::simd
