#include "integrator.hpp"

#include <algorithm>
#include <cmath>

#include "cell_control.hpp"

namespace granstab::dynamic {

void kick_drift(DiskArrays& d, CellState& cell, const Stage& stage, double dt,
                NeighbourList& neighbours, bool parallel) {
  const double half = 0.5 * dt;
  std::array<double, 2> lambda{1.0, 1.0};
  for (int a = 0; a < 2; ++a) {
    if (stage.control[a] == LengthControl::stress) {
      cell.length_rate[a] += half * cell.length_acceleration[a];
      cell.rate_predicted[a] = cell.length_rate[a] + half * cell.length_acceleration[a];
    } else {
      cell.length_rate[a] = imposed_length_rate(stage, a);
      cell.rate_predicted[a] = cell.length_rate[a];
    }
    const double old_length = cell.length[a];
    cell.length[a] += dt * cell.length_rate[a];
    if (cell.periodic()) lambda[a] = cell.length[a] / old_length;
  }
  const bool periodic = cell.periodic();
  const double l1 = cell.length[0], l2 = cell.length[1];
  // Non-affine displacement since the build: in reduced coordinates, times current lengths.
  const double sx = periodic ? 1.0 / l1 : 1.0, sy = periodic ? 1.0 / l2 : 1.0;
  const double ux = periodic ? l1 : 1.0, uy = periodic ? l2 : 1.0;
  const double* ref_x = neighbours.reference_x().data();
  const double* ref_y = neighbours.reference_y().data();
  const int n = static_cast<int>(d.size());
  double max_d2 = 0.0;
#pragma omp parallel for schedule(static) reduction(max : max_d2) if (parallel)
  for (int i = 0; i < n; ++i) {
    const double ax = (d.fx[i] + d.fvx[i]) * d.inv_mass[i];
    const double ay = (d.fy[i] + d.fvy[i]) * d.inv_mass[i];
    d.vx[i] += half * ax;
    d.vy[i] += half * ay;
    d.vpx[i] = d.vx[i] + half * ax;
    d.vpy[i] = d.vy[i] + half * ay;
    d.omega[i] += half * d.torque[i] * d.inv_inertia[i];
    double x = d.x[i] * lambda[0] + dt * d.vx[i];
    double y = d.y[i] * lambda[1] + dt * d.vy[i];
    if (periodic) {
      x = wrap(x, l1);
      y = wrap(y, l2);
    }
    d.x[i] = x;
    d.y[i] = y;
    d.theta[i] += dt * d.omega[i];
    double ex = x * sx - ref_x[i], ey = y * sy - ref_y[i];
    if (periodic) {  // |ex| < 1: nearest image by comparison (no rounding call)
      ex = ex > 0.5 ? ex - 1.0 : (ex < -0.5 ? ex + 1.0 : ex);
      ey = ey > 0.5 ? ey - 1.0 : (ey < -0.5 ? ey + 1.0 : ey);
    }
    ex *= ux;
    ey *= uy;
    max_d2 = std::max(max_d2, ex * ex + ey * ey);
  }
  neighbours.set_max_displacement_squared(max_d2);
}

void kick(DiskArrays& d, CellState& cell, const Stage& stage, double dt, bool parallel) {
  const double half = 0.5 * dt;
  for (int a = 0; a < 2; ++a) {
    if (stage.control[a] == LengthControl::stress) {
      cell.length_rate[a] += half * cell.length_acceleration[a];
    }
  }
  const int n = static_cast<int>(d.size());
#pragma omp parallel for schedule(static) if (parallel)
  for (int i = 0; i < n; ++i) {
    d.vx[i] += half * (d.fx[i] + d.fvx[i]) * d.inv_mass[i];
    d.vy[i] += half * (d.fy[i] + d.fvy[i]) * d.inv_mass[i];
    d.omega[i] += half * d.torque[i] * d.inv_inertia[i];
  }
}

}  // namespace granstab::dynamic
