#pragma once
// Dense periodic benchmark samples (issue #3 / #7 workload): N disks with diameters uniform in
// [1/2, 1], placed with jitter on a triangular lattice of spacing 1.05 (no overlap, Phi ~ 0.5) and
// compressed by the engine under isotropic stress P = 1 (see dense_sample).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "common/configuration.hpp"
#include "dynamic/cell_control.hpp"
#include "dynamic/engine.hpp"

namespace granstab::bench {

inline Configuration lattice_gas(int n, const Material& material, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> diameter(0.5, 1.0), jitter(-0.02, 0.02);
  // Rows of `per_row` disks, spacing 1 along x and sqrt(3)/2 along y; an even number of rows
  // keeps the lattice periodic.
  const int per_row = static_cast<int>(std::ceil(std::sqrt(n / (std::sqrt(3.0) / 2.0))));
  int rows = (n + per_row - 1) / per_row;
  rows += rows % 2;
  const double a = 1.05;  // lattice spacing: no two disks of diameter <= 1 overlap
  Configuration c;
  c.cell.boundary = Boundary::periodic;
  c.cell.length = {a * per_row, a * rows * std::sqrt(3.0) / 2.0};
  c.material = material;
  for (int k = 0; k < n; ++k) {
    const int row = k / per_row, col = k % per_row;
    const double x = a * (col + 0.5 * (row % 2)) + jitter(rng);
    const double y = a * (row + 0.5) * std::sqrt(3.0) / 2.0 + jitter(rng);
    c.disks.add(std::fmod(x + c.cell.length[0], c.cell.length[0]), y, 0.5 * diameter(rng));
  }
  const double m = dynamic::default_cell_mass(c.disks.mass);
  c.cell.mass = {m, m};
  c.stage.reference_length = c.cell.length;
  return c;
}

inline double solid_fraction(const Engine& e) {  // of the current state
  double area = 0.0;
  for (double r : e.radius()) area += M_PI * r * r;
  return area / (e.length()[0] * e.length()[1]);
}

// Compresses under P = 1 (both axes stress-controlled) with a quick recipe: frictionless,
// kappa = 1e3, zeta = 1, a light cell (mass independent of N so the collapse time does not
// grow with the sample), until the sample is dense (z N / 2 contacts with z >= 3.6, calm);
// then lets it settle with the benchmark stiffness (frictionless) and hands it the benchmark
// material.
inline Configuration dense_sample(int n, const Material& material, std::uint64_t seed) {
  Configuration c = lattice_gas(n, Material::from_kappa(1e3, 1.0, 0.0, 1.0), seed);
  c.stage.control = {LengthControl::stress, LengthControl::stress};
  c.stage.sigma_ext = {1.0, 1.0};
  for (double& m : c.cell.mass) m *= 0.1 * 1400.0 / n;
  Engine e(c);
  for (int k = 0; k < 200; ++k) {
    e.run(1000);
    const double contacts_per_disk = static_cast<double>(e.contact_count()) / n;
    if (contacts_per_disk >= 1.8 && e.kinetic_energy() / n < 1e-3) break;
  }
  // The stiffer benchmark contacts first push the cell open (sigma ~ 10 P at the same
  // overlaps): let the sample settle at P with them.
  Material settle = material;
  settle.mu = 0.0;
  e.set_material(settle);
  for (int k = 0; k < 40; ++k) {
    e.run(1000);
    const double contacts_per_disk = static_cast<double>(e.contact_count()) / n;
    if (contacts_per_disk >= 1.75 && e.kinetic_energy() / n < 1e-4) break;
  }
  Configuration out = e.configuration();
  out.material = material;
  out.stage.reference_length = out.cell.length;
  return out;
}

// The same sample with its disks in random index order (contacts renumbered alike).
inline Configuration shuffled(const Configuration& c, std::uint64_t seed) {
  const std::size_t n = c.disks.size();
  std::vector<int> order(n);  // new index k holds old disk order[k]
  for (std::size_t k = 0; k < n; ++k) order[k] = static_cast<int>(k);
  std::mt19937_64 rng(seed);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<int> new_index(n);
  for (std::size_t k = 0; k < n; ++k) new_index[order[k]] = static_cast<int>(k);
  Configuration out = c;
  Disks& d = out.disks;
  const Disks& s = c.disks;
  for (std::size_t k = 0; k < n; ++k) {
    const int o = order[k];
    d.x[k] = s.x[o], d.y[k] = s.y[o], d.radius[k] = s.radius[o], d.mass[k] = s.mass[o];
    d.inertia[k] = s.inertia[o], d.vx[k] = s.vx[o], d.vy[k] = s.vy[o];
    d.omega[k] = s.omega[o], d.theta[k] = s.theta[o];
  }
  for (std::size_t k = 0; k < out.contacts.size(); ++k) {
    out.contacts.i[k] = new_index[c.contacts.i[k]];
    if (c.contacts.j[k] >= 0) out.contacts.j[k] = new_index[c.contacts.j[k]];
  }
  return out;
}

}  // namespace granstab::bench
