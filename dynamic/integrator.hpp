#pragma once
// Velocity Verlet for the disks (translation and rotation) and the cell lengths / mobile walls,
// split in its two half kicks (see docs/dynamic.md for the treatment of the viscous force).
#include <array>

#include "common/configuration.hpp"
#include "contact_forces_law.hpp"
#include "neighbour_list.hpp"
#include "state.hpp"

namespace granstab::dynamic {

// The first half kick and the drift, in two pieces so that each thread of a team drifts its
// own disks (engine.cpp). kick_drift_cell: dL/dt(t + dt/2) = dL/dt(t) + dt/2 d2L/dt2(t) on
// stress-controlled axes (the others get their imposed rate), the end-of-step prediction of
// the rate for the viscous force, and L(t + dt); returns lambda_a = L_a(t + dt) / L_a(t) (the
// affine part in a periodic cell; walls: 1).
std::array<double, 2> kick_drift_cell(CellState& cell, const Stage& stage, double dt);

// For the disks [first, end): v(t + dt/2) = v(t) + dt/2 a(t) (the same for omega), over vx, vy,
// omega (a team's other parts read their ghosts: Halo); then r(t + dt) = lambda r(t) + dt v(t +
// dt/2); predicts the end-of-step velocities for the viscous force (vpx, vpy) and leaves the
// per-disk force sums at zero for the force pass (contact_forces_part with kick). `cell` is the one
// kick_drift_cell returned lambda for. Returns the largest non-affine displacement since the last
// list build (squared, in current lengths) of these disks.
double kick_drift_disks(DiskArrays& disks, const CellState& cell, std::array<double, 2> lambda,
                        double dt, const NeighbourList& neighbours, int first, int end);

// dL/dt(t + dt) = dL/dt(t + dt/2) + dt/2 d2L/dt2(t + dt) on stress-controlled axes. The disks'
// second half kick is done by the force pass as soon as each disk's forces are complete
// (ForceInputs::kick): one pass over the disks less per step.
void kick_cell(CellState& cell, const Stage& stage, double dt);

// Brings x into [0, length) after a drift (displacements per step are far below a length).
// A template over the number type, as the contact law (common/contact_law.hpp): double here,
// the SIMD type of integrator_simd.cpp there, the same bits lane by lane.
template <class T>
inline T wrap(T x, double length) {
  return select_lazy(
      x < 0.0,
      [&] {
        const T up = x + length;
        return select(up < length, up, T(0.0));
      },
      [&] { return select(x >= length, x - length, x); });
}

// Constants of one drift pass (kick_drift_disks).
struct DriftConstants {
  double half, dt;
  double l1, l2;              // cell lengths after the drift
  double lambda_x, lambda_y;  // affine stretch of the step (periodic; 1 between walls)
  double sx, sy, ux, uy;      // to reduced coordinates and back (periodic; 1 between walls)
};

// One disk's first half kick and drift (kick_drift_disks), for double and for the SIMD type.
template <class T>
struct Drifted {
  T vx, vy, vpx, vpy, omega, x, y, theta;
  T d2;  // squared non-affine displacement since the list build
};
template <bool Periodic, class T>
inline Drifted<T> drift_disk(const DriftConstants& k, T x, T y, T vx, T vy, T omega, T theta, T fx,
                             T fy, T fvx, T fvy, T torque, T inv_mass, T inv_inertia, T ref_x,
                             T ref_y) {
  Drifted<T> out;
  const T ax = (fx + fvx) * inv_mass;
  const T ay = (fy + fvy) * inv_mass;
  out.vx = vx + k.half * ax;
  out.vy = vy + k.half * ay;
  out.vpx = out.vx + k.half * ax;
  out.vpy = out.vy + k.half * ay;
  out.omega = omega + k.half * torque * inv_inertia;
  out.x = x * k.lambda_x + k.dt * out.vx;
  out.y = y * k.lambda_y + k.dt * out.vy;
  if constexpr (Periodic) {
    out.x = wrap(out.x, k.l1);
    out.y = wrap(out.y, k.l2);
  }
  out.theta = theta + k.dt * out.omega;
  T ex = out.x * k.sx - ref_x, ey = out.y * k.sy - ref_y;
  if constexpr (Periodic) {  // |ex| < 1: nearest image by comparison (no rounding call)
    ex = minimum_image(ex, 1.0, 0.5);
    ey = minimum_image(ey, 1.0, 0.5);
  }
  ex = ex * k.ux;
  ey = ey * k.uy;
  out.d2 = ex * ex + ey * ey;
  return out;
}

}  // namespace granstab::dynamic
