#pragma once
// Small hand-built networks for the tests of STATIC.md §S4 (no MD packings exist yet).
#include <vector>

#include "static/network.hpp"

namespace granstab::statics::testing {

// Adds every overlapping pair (and periodic self-image) of the network's disks as a contact with
// delta_t = 0, scanning images k in {-1, 0, 1}^2 (periodic) or the four walls (walled).
void add_overlapping_contacts(Network& net);

// Four disks of unequal radii in a small periodic cell: image and self-image contacts, with
// tangential states chosen so that some contacts stick with F_T != 0 and others have trial
// forces strictly beyond the cone in both directions. Not in equilibrium (K is checked anyway).
Network periodic_mixed_network();

// Three disks in a walled box touching all four walls (mu_wall > 0) and each other.
Network walled_mixed_network();

// The two-disk triangular lattice (spacing d = 2R - h) under isotropic pressure, in equilibrium.
Network triangular_lattice(double radius, double k_n, double k_t, double mu, double pressure);

// A configuration holding the network's state, stage stresses = its loads, references = its cell.
Configuration configuration_from_network(const Network& net);

// DofOptions with every disk active, translation pinned on disk 0 for periodic cells.
DofOptions all_active(const Network& net, bool pin_translation);

}  // namespace granstab::statics::testing
