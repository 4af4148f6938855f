#pragma once
// Velocity Verlet for the disks (translation and rotation) and the cell lengths / mobile walls,
// split in its two half kicks (see docs/dynamic.md for the treatment of the viscous force).
#include "common/configuration.hpp"
#include "neighbour_list.hpp"
#include "state.hpp"

namespace granstab::dynamic {

// v(t + dt/2) = v(t) + dt/2 a(t), the same for omega and dL/dt (stress-controlled axes; the
// others get their imposed rate); then the drift r(t + dt) = lambda r(t) + dt v(t + dt/2) with
// lambda_a = L_a(t + dt) / L_a(t) the affine part in a periodic cell (walls: lambda = 1).
// Also predicts the end-of-step velocities for the viscous force (vpx, vpy, rate_predicted) and
// reports the largest non-affine displacement since the last list build to the list. Leaves
// the per-disk force sums at zero for the force pass (compute_contact_forces with kick).
// parallel: on the OpenMP team (false: on the calling thread; same bits).
void kick_drift(DiskArrays& disks, CellState& cell, const Stage& stage, double dt,
                NeighbourList& neighbours, bool parallel);

// dL/dt(t + dt) = dL/dt(t + dt/2) + dt/2 d2L/dt2(t + dt) on stress-controlled axes. The disks'
// second half kick is done by the force pass as soon as each disk's forces are complete
// (ForceInputs::kick): one pass over the disks less per step.
void kick_cell(CellState& cell, const Stage& stage, double dt);

// Brings x into [0, length) after a drift (displacements per step are far below a length).
inline double wrap(double x, double length) {
  if (x < 0.0) {
    x += length;
    return x < length ? x : 0.0;
  }
  return x >= length ? x - length : x;
}

}  // namespace granstab::dynamic
