#pragma once
// The contact network of one load step (STATIC.md §S0-§S1): the start-of-step geometry, the
// contacts with their start-of-step tangential state, the loads and the degrees of freedom.
//
// Choice (docs/static.md): both boundary kinds use the cell extensions e1, e2 as their
// macroscopic degrees of freedom, with disk centres r_i = (I + E) r_i0 + u_i. In a periodic cell
// this is §S1 as written; with walls, the mobile walls sit at x = L1_0 (1 + e1), y = L2_0 (1 + e2)
// (wall displacement L_a0 e_a) and u_i is measured from the affinely following position, a
// linear change of variables that keeps det K, its sign and the definiteness of (K + K^T)/2.
#include <array>
#include <cstdint>
#include <vector>

#include "common/cell.hpp"
#include "common/configuration.hpp"
#include "common/contacts.hpp"
#include "common/material.hpp"
#include "static/dof_map.hpp"

namespace granstab::statics {

// External loads at the current value of the load parameter.
struct Loading {
  // Prescribed stresses (compression positive) on the cell directions that are degrees of freedom.
  std::array<double, 2> sigma{1.0, 1.0};
  StressMeasure measure = StressMeasure::cauchy;
  // Nominal measure: the stress acts on the lengths of the stage's reference cell (SPEC §1.3).
  std::array<double, 2> nominal_length{1.0, 1.0};
  // Extension e_a imposed on a direction that is not a degree of freedom (strain control; 0 for a
  // fixed length).
  std::array<double, 2> e_imposed{0.0, 0.0};
  // Dead loads on disks (force x, force y, torque), 3 per disk, or empty. Used by the tests of
  // STATIC.md §S4 T3-T4 that load single disks; the biaxial test leaves it empty.
  std::vector<double> dead;
};

// Which disks and directions may move (STATIC.md §S3.0): the solver re-derives the degrees of
// freedom from these and the current contacts at every preparation.
struct Constraints {
  std::vector<char> disk_fixed;      // per disk, or empty: the disk never moves (tests)
  std::vector<char> rotation_fixed;  // per disk, or empty: theta is not a degree of freedom
  std::array<bool, 2> cell_free{true, true};  // e_a is a degree of freedom (stress control)
  bool remove_rattlers = true;
};

struct Network {
  Boundary boundary = Boundary::periodic;
  std::array<double, 2> length{1.0, 1.0};  // L_a0, cell lengths at the start of the step
  std::vector<double> x, y, radius;        // start-of-step centres (not re-wrapped in a run)
  std::vector<double> theta;               // accumulated rotations
  Contacts contacts;                       // delta_t: start-of-step tangential elastic displacement
  Material material;
  Loading loading;
  Constraints constraints;
  DofMap dofs;

  std::size_t n_disks() const { return x.size(); }
  double area() const { return length[0] * length[1]; }
  double friction(std::size_t c) const {
    return is_wall(contacts.j[c]) ? material.mu_wall : material.mu;
  }
};

// Network of a configuration at its current state, every disk active, cell directions that the
// stage controls by stress as degrees of freedom; the loads are the stage's prescribed stresses.
Network network_from_configuration(const Configuration& config);

}  // namespace granstab::statics
