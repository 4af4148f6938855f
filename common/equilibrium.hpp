#pragma once
// The mechanical equilibrium criterion of SPEC §3.1, written once for every protocol and for the
// static solver's corrector: net forces and torques on non-rattler disks, and each stress-
// controlled component against its prescribed value, all below their tolerances.
#include <array>
#include <cstddef>

#include "configuration.hpp"
#include "measurements.hpp"

namespace granstab {

struct EquilibriumTolerances {
  double force = 1e-4;   // units of aP
  double torque = 1e-4;  // units of a^2 P
  double stress = 1e-4;  // relative
};

struct EquilibriumReport {
  double max_net_force = 0.0;   // over non-rattler disks
  double max_net_torque = 0.0;  // over non-rattler disks
  std::size_t max_force_disk = 0, max_torque_disk = 0;
  // |sigma_aa - sigma_ext_a| / |sigma_ext_a| (absolute when sigma_ext_a = 0) for each
  // stress-controlled direction; stress_checked[a] is false for strain-rate or fixed lengths.
  std::array<double, 2> stress_error{0.0, 0.0};
  std::array<bool, 2> stress_checked{false, false};
  double e_c = 0.0;  // reported beside the criterion, not part of it
  double f_2 = 0.0;
  bool force_ok = false, torque_ok = false, stress_ok = false;
  bool in_equilibrium = false;
};

EquilibriumReport check_equilibrium(const Configuration& config,
                                    const EquilibriumTolerances& tolerances = {});
// The same from measurements already taken (avoids recomputing the forces).
EquilibriumReport check_equilibrium(const Configuration& config, const Measurements& measured,
                                    const EquilibriumTolerances& tolerances = {});

}  // namespace granstab
