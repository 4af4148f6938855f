#pragma once
// The initial state of SPEC §3.2: a random gas of N disks at a low solid fraction, no overlaps,
// diameters uniform in [d_min, d_max] (SPEC §1: [a/2, a]), drawn from a seeded std::mt19937_64.
#include <random>

#include "common/configuration.hpp"

namespace granstab::protocols {

struct GasOptions {
  int n = 100;
  Boundary boundary = Boundary::periodic;
  double phi = 0.2;  // solid fraction of the gas
  double d_min = 0.5, d_max = 1.0;
  double aspect = 1.0;  // L2 / L1
};

// Diameters first (N draws), then random sequential placement: each disk is tried at uniform
// random positions (inside the walls, or anywhere in the periodic cell) until it overlaps no
// placed disk. Throws std::runtime_error if a disk cannot be placed (phi too high). The cell and
// wall masses are the engine's default (dynamic/cell_control.hpp); velocities are zero; the stage
// is isotropic stress control at sigma = 1 with the gas's lengths as reference.
Configuration random_gas(const GasOptions& options, const Material& material, std::mt19937_64& rng);

}  // namespace granstab::protocols
