#include "integrator.hpp"

#include <algorithm>
#include <cmath>

#include "cell_control.hpp"

namespace granstab::dynamic {

std::array<double, 2> kick_drift_cell(CellState& cell, const Stage& stage, double dt) {
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
  return lambda;
}

double kick_drift_disks(DiskArrays& d, const CellState& cell, std::array<double, 2> lambda,
                        double dt, const NeighbourList& neighbours, int first, int end) {
  const double half = 0.5 * dt;
  const bool periodic = cell.periodic();
  const double l1 = cell.length[0], l2 = cell.length[1];
  // Non-affine displacement since the build: in reduced coordinates, times current lengths.
  const double sx = periodic ? 1.0 / l1 : 1.0, sy = periodic ? 1.0 / l2 : 1.0;
  const double ux = periodic ? l1 : 1.0, uy = periodic ? l2 : 1.0;
  const double* ref_x = neighbours.reference_x().data();
  const double* ref_y = neighbours.reference_y().data();
  const double lambda_x = lambda[0], lambda_y = lambda[1];
  double* const x = d.x.data();
  double* const y = d.y.data();
  double* const vx = d.vx.data();
  double* const vy = d.vy.data();
  double* const vpx = d.vpx.data();
  double* const vpy = d.vpy.data();
  double* const omega = d.omega.data();
  double* const theta = d.theta.data();
  double* const fx = d.fx.data();
  double* const fy = d.fy.data();
  double* const fvx = d.fvx.data();
  double* const fvy = d.fvy.data();
  double* const torque = d.torque.data();
  const double* const inv_mass = d.inv_mass.data();
  const double* const inv_inertia = d.inv_inertia.data();
  double max_d2 = 0.0;
  for (int i = first; i < end; ++i) {
    const double ax = (fx[i] + fvx[i]) * inv_mass[i];
    const double ay = (fy[i] + fvy[i]) * inv_mass[i];
    const double vx_half = vx[i] + half * ax, vy_half = vy[i] + half * ay;
    vx[i] = vx_half;
    vy[i] = vy_half;
    vpx[i] = vx_half + half * ax;
    vpy[i] = vy_half + half * ay;
    const double omega_half = omega[i] + half * torque[i] * inv_inertia[i];
    omega[i] = omega_half;
    // Used: cleared for the force pass, which adds every disk's pair forces into them.
    fx[i] = fy[i] = fvx[i] = fvy[i] = torque[i] = 0.0;
    double xi = x[i] * lambda_x + dt * vx_half;
    double yi = y[i] * lambda_y + dt * vy_half;
    if (periodic) {
      xi = wrap(xi, l1);
      yi = wrap(yi, l2);
    }
    x[i] = xi;
    y[i] = yi;
    theta[i] += dt * omega_half;
    double ex = xi * sx - ref_x[i], ey = yi * sy - ref_y[i];
    if (periodic) {  // |ex| < 1: nearest image by comparison (no rounding call)
      ex = ex > 0.5 ? ex - 1.0 : (ex < -0.5 ? ex + 1.0 : ex);
      ey = ey > 0.5 ? ey - 1.0 : (ey < -0.5 ? ey + 1.0 : ey);
    }
    ex *= ux;
    ey *= uy;
    max_d2 = std::max(max_d2, ex * ex + ey * ey);
  }
  return max_d2;
}

void kick_cell(CellState& cell, const Stage& stage, double dt) {
  const double half = 0.5 * dt;
  for (int a = 0; a < 2; ++a) {
    if (stage.control[a] == LengthControl::stress) {
      cell.length_rate[a] += half * cell.length_acceleration[a];
    }
  }
}

}  // namespace granstab::dynamic
