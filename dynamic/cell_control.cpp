#include "cell_control.hpp"

namespace granstab::dynamic {

double default_cell_mass(const std::vector<double>& disk_mass) {
  double total = 0.0;
  for (double m : disk_mass) total += m;
  constexpr double pi = 3.141592653589793;
  return total > 0.0 ? total / (pi * pi) : 1.0;
}

ControlForces control_forces(const CellState& cell, const BlockSums& sums, bool include_viscous) {
  ControlForces out;
  for (int a = 0; a < 2; ++a) {
    if (cell.periodic()) {
      // sigma_aa L_b = (sum f_a l_a) / L_a: the force transmitted across a side of length L_b.
      double s = sums.sigma[3 * a];
      if (include_viscous) s += sums.sigma_viscous[a];
      out.disk_force[a] = s / cell.length[a];
    } else {
      out.disk_force[a] = sums.wall_force[a] + (include_viscous ? sums.wall_force_viscous[a] : 0.0);
    }
  }
  return out;
}

std::array<double, 2> length_acceleration(const CellState& cell, const Stage& stage,
                                          const ControlForces& forces) {
  std::array<double, 2> acc{0.0, 0.0};
  for (int a = 0; a < 2; ++a) {
    if (stage.control[a] != LengthControl::stress) continue;
    const int b = 1 - a;
    const double side =
        stage.measure == StressMeasure::cauchy ? cell.length[b] : stage.reference_length[b];
    acc[a] = (forces.disk_force[a] - stage.sigma_ext[a] * side) / cell.mass[a];
  }
  return acc;
}

}  // namespace granstab::dynamic
