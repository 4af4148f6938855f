#include "integrator.hpp"

#include <algorithm>
#include <cmath>

#include "cell_control.hpp"
#include "contact_forces.hpp"
#include "integrator_simd.hpp"

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

namespace {
simd::DriftBlock simd_block(DiskArrays& d, const double* ref_x, const double* ref_y) {
  return {d.x.data(),   d.y.data(),   d.vx.data(),     d.vy.data(),       d.omega.data(),
          d.vpx.data(), d.vpy.data(), d.theta.data(),  d.fx.data(),       d.fy.data(),
          d.fvx.data(), d.fvy.data(), d.torque.data(), d.inv_mass.data(), d.inv_inertia.data(),
          ref_x,        ref_y};
}

template <bool Periodic>
double kick_drift_scalar(DiskArrays& d, const DriftConstants& k, const double* ref_x,
                         const double* ref_y, int first, int end) {
  double max_d2 = 0.0;
  for (int i = first; i < end; ++i) {
    const Drifted<double> o = drift_disk<Periodic>(
        k, d.x[i], d.y[i], d.vx[i], d.vy[i], d.omega[i], d.theta[i], d.fx[i], d.fy[i], d.fvx[i],
        d.fvy[i], d.torque[i], d.inv_mass[i], d.inv_inertia[i], ref_x[i], ref_y[i]);
    d.vx[i] = o.vx;
    d.vy[i] = o.vy;
    d.vpx[i] = o.vpx;
    d.vpy[i] = o.vpy;
    d.omega[i] = o.omega;
    // Used: cleared for the force pass, which adds every disk's pair forces into them.
    d.fx[i] = d.fy[i] = d.fvx[i] = d.fvy[i] = d.torque[i] = 0.0;
    d.x[i] = o.x;
    d.y[i] = o.y;
    d.theta[i] = o.theta;
    max_d2 = std::max(max_d2, o.d2);
  }
  return max_d2;
}
}  // namespace

double kick_drift_disks(DiskArrays& d, const CellState& cell, std::array<double, 2> lambda,
                        double dt, const NeighbourList& neighbours, int first, int end) {
  const bool periodic = cell.periodic();
  const double l1 = cell.length[0], l2 = cell.length[1];
  // Non-affine displacement since the build: in reduced coordinates, times current lengths.
  const DriftConstants k{0.5 * dt,
                         dt,
                         l1,
                         l2,
                         lambda[0],
                         lambda[1],
                         periodic ? 1.0 / l1 : 1.0,
                         periodic ? 1.0 / l2 : 1.0,
                         periodic ? l1 : 1.0,
                         periodic ? l2 : 1.0};
  const double* ref_x = neighbours.reference_x().data();
  const double* ref_y = neighbours.reference_y().data();
  if (simd_pairs()) {
    return simd::kick_drift(simd_block(d, ref_x, ref_y), k, periodic, first, end);
  }
  return periodic ? kick_drift_scalar<true>(d, k, ref_x, ref_y, first, end)
                  : kick_drift_scalar<false>(d, k, ref_x, ref_y, first, end);
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
