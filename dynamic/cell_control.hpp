#pragma once
// Control of the two cell lengths (periodic cell) or mobile walls (SPEC §1.3), one axis at a
// time: stress control (Cauchy or nominal), strain-rate control, or fixed.
#include <array>

#include "common/configuration.hpp"
#include "state.hpp"

namespace granstab::dynamic {

// The default inertia of each cell length / mobile wall: M = sum m_i / pi^2. Under a length
// change dL the stress changes by E dL / L, so a square cell of mass M oscillates at
// sqrt(E / M); the sample's fundamental standing wave has pi c / L = pi sqrt(E / sum m_i). This
// M makes the two equal: the control follows the sample as fast as the sample itself can
// respond, without outrunning it. Quasistatic results do not depend on M
// (tests/dynamic/test_cell_control.cpp); see docs/dynamic.md.
double default_cell_mass(const std::vector<double>& disk_mass);

// The force driving axis a (the cell length or the mobile wall): the force the disks exert
// across a side of the cell minus the prescribed one,
//   Cauchy : (sigma_aa - sigma_ext_a) L_b          nominal: sigma_aa L_b - sigma_ext_a L_b0
// with sigma_aa the contact stress (periodic) or the disks' force on the wall divided by L_b.
// include_viscous adds the viscous forces to the disks' side (they vanish at equilibrium).
struct ControlForces {
  std::array<double, 2> disk_force{0.0, 0.0};  // disks on the side normal to a
};
ControlForces control_forces(const CellState& cell, const BlockSums& sums, bool include_viscous);

// d2L_a/dt2 for stress-controlled axes (0 for the others).
std::array<double, 2> length_acceleration(const CellState& cell, const Stage& stage,
                                          const ControlForces& forces);

// dL_a/dt imposed on a strain-rate controlled (or fixed) axis: epsilon_a = 1 - L_a / L_a0.
inline double imposed_length_rate(const Stage& stage, int a) {
  return stage.control[a] == LengthControl::strain_rate
             ? -stage.strain_rate[a] * stage.reference_length[a]
             : 0.0;
}

}  // namespace granstab::dynamic
