#pragma once
// The tiny shipped samples of data/samples/, built from closed-form equilibrium states so tests
// can compare measurements with hand-derived values. make_tiny_samples writes them to disk.
#include "common/configuration.hpp"

namespace granstab::samples {

// Contacts of every overlapping pair (minimum image in periodic cells) and every disk that
// overlaps a wall, by brute force: O(N^2), for tiny test configurations only.
void add_contacts_by_geometry(Configuration& config);

// 16 equal disks (d = 1) on a triangular lattice, 4 columns x 4 rows, in a periodic cell
// 4 s x 2 sqrt(3) s (s = centre distance), with the overlap h = 1 / (sqrt(3) K_N + 1) that makes
// sigma = P = 1 exactly (docs/file-format.md derives it). mu = 0.5, K_T = K_N, zeta = 1.
Configuration triangular_lattice(double kappa);
// The overlap of that lattice.
double triangular_lattice_overlap(double kappa);

// n x n equal disks (d = 1) stacked on a square lattice between four frictionless walls, under
// sigma_1 = sigma_2 = P = 1: every contact carries F = L / n, overlap h = 1 / (K_N + (n+1)/n).
// mu = 0.25, K_T/K_N = 1/2, zeta = 1, mu_wall = 0 (the series A recipe).
Configuration square_stack(int n, double kappa);
double square_stack_overlap(int n, double kappa);

}  // namespace granstab::samples
