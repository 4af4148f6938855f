#pragma once
// The measured quantities of SPEC §2, computed from a Configuration with the contact law of
// contact_law.hpp (elastic + frictional forces only; viscous forces never enter a measurement).
// Choices where SPEC is silent are documented in docs/data-model.md ("Measurements").
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "configuration.hpp"
#include "contact_law.hpp"

namespace granstab {

// Frame of contact c of the configuration: disk-disk with the periodic image of j, or disk-wall.
ContactFrame contact_frame(const Configuration& config, std::size_t c);

// Force of one listed contact, of i on j: f = f_n n + f_t t (zero unless carrying force).
struct ContactLoad {
  ContactFrame frame;
  double f_n = 0.0;       // elastic normal force K_N h
  double f_t = 0.0;       // -K_T delta_t returned to the Coulomb cone (mu, or mu_wall for walls)
  bool carrying = false;  // h > 0: the contact exists and carries force (SPEC §1.1)
  bool sliding = false;   // |f_t| = mu f_n to round-off (is_sliding)
};

std::vector<ContactLoad> contact_loads(const Configuration& config);

// Net force and torque on every disk from the elastic + frictional contact forces.
struct NetForces {
  std::vector<double> fx, fy, torque;
};
NetForces net_forces(const Configuration& config, const std::vector<ContactLoad>& loads);

// Rattlers: disks left after iteratively removing every disk with fewer than 2 force-carrying
// contacts with walls or with disks not yet removed. 1 marks a rattler.
std::vector<std::uint8_t> find_rattlers(const Configuration& config,
                                        const std::vector<ContactLoad>& loads);

// sigma[a][b] = (1/A) sum_c f_a l_b, compression positive (f of i on j, l from i to j; wall
// contacts use l = d n, so that at equilibrium sigma_aa is the wall force per unit length).
using StressTensor = std::array<std::array<double, 2>, 2>;
StressTensor stress_tensor(const Configuration& config, const std::vector<ContactLoad>& loads);

// Walls: the total normal force the disks exert on each wall, indexed left, right, bottom, top
// (-j - 1 for the Wall value j), positive when pushing. SPEC §2's second stress measure:
// at equilibrium sigma_11 = F_right / L2 = F_left / L2 and sigma_22 = F_top / L1 = F_bottom / L1.
std::array<double, 4> wall_forces(const Configuration& config,
                                  const std::vector<ContactLoad>& loads);

// The stress component a that the stage controls: the Cauchy sigma_aa, or for the nominal measure
// the force on the side normal to a divided by that side's reference length.
double controlled_stress(const Configuration& config, const StressTensor& sigma, int a);

struct Measurements {
  std::size_t n_disks = 0;
  double area = 0.0;
  double phi = 0.0;  // solid fraction
  StressTensor sigma{};
  double q = 0.0;  // (sigma_22 - sigma_11) / sigma_11
  double epsilon_1 = 0.0, epsilon_2 = 0.0, epsilon_v = 0.0;

  std::size_t n_contacts_listed = 0;
  std::size_t n_contacts_carrying = 0;  // h > 0
  std::size_t n_sliding = 0;            // among carrying contacts
  std::size_t n_rattlers = 0;
  // Force-carrying contacts of the non-rattler network: disk-disk and disk-wall.
  std::size_t n_network_disk_disk = 0;
  std::size_t n_network_wall = 0;
  double x0 = 0.0;   // rattler fraction
  double z = 0.0;    // (2 N_dd + N_wall) / N' (a wall contact counts once, for its disk)
  double x_s = 0.0;  // sliding fraction of force-carrying contacts

  double e_c = 0.0;             // mean kinetic energy per disk, fluctuating translation + rotation
  double f_2 = 0.0;             // rms net force over non-rattler disks
  double torque_2 = 0.0;        // rms net torque over non-rattler disks
  double max_net_force = 0.0;   // over non-rattler disks
  double max_net_torque = 0.0;  // over non-rattler disks
  std::size_t max_force_disk = 0, max_torque_disk = 0;
};

Measurements measure(const Configuration& config);

// Pieces of measure() for callers that need one quantity in a loop.
double solid_fraction(const Configuration& config);
double kinetic_energy_per_disk(const Disks& disks);
std::array<double, 3> strains(const Configuration& config);  // epsilon_1, epsilon_2, epsilon_v

}  // namespace granstab
