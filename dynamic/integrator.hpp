#pragma once
// Velocity Verlet for the disks (translation and rotation) and the cell lengths / mobile walls,
// split in its two half kicks (see docs/dynamic.md for the treatment of the viscous force).
#include <array>

#include "common/configuration.hpp"
#include "neighbour_list.hpp"
#include "state.hpp"

namespace granstab::dynamic {

// The first half kick and the drift, in two pieces so that each thread of a team drifts its
// own disks (engine.cpp). kick_drift_cell: dL/dt(t + dt/2) = dL/dt(t) + dt/2 d2L/dt2(t) on
// stress-controlled axes (the others get their imposed rate), the end-of-step prediction of
// the rate for the viscous force, and L(t + dt); returns lambda_a = L_a(t + dt) / L_a(t) (the
// affine part in a periodic cell; walls: 1).
std::array<double, 2> kick_drift_cell(CellState& cell, const Stage& stage, double dt);

// For the disks [first, end): v(t + dt/2) = v(t) + dt/2 a(t) (the same for omega), then
// r(t + dt) = lambda r(t) + dt v(t + dt/2); predicts the end-of-step velocities for the viscous
// force (vpx, vpy) and leaves the per-disk force sums at zero for the force pass
// (contact_forces_part with kick). `cell` is the one kick_drift_cell returned lambda for.
// Returns the largest non-affine displacement since the last list build (squared, in current
// lengths) of these disks.
double kick_drift_disks(DiskArrays& disks, const CellState& cell, std::array<double, 2> lambda,
                        double dt, const NeighbourList& neighbours, int first, int end);

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
