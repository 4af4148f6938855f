#pragma once
// Small configurations for the engine tests, built in the tests themselves.
#include <cstdint>
#include <random>
#include <stdexcept>

#include "common/configuration.hpp"
#include "dynamic/cell_control.hpp"
#include "dynamic/engine.hpp"

namespace granstab::testing {

inline Configuration empty_periodic(double l1, double l2, const Material& material) {
  Configuration c;
  c.cell.boundary = Boundary::periodic;
  c.cell.length = {l1, l2};
  c.material = material;
  c.stage.control = {LengthControl::fixed, LengthControl::fixed};
  c.stage.reference_length = {l1, l2};
  return c;
}

// A random gas of n disks with diameters uniform in [1/2, 1] at solid fraction phi (no
// overlaps, random sequential placement), seeded.
inline Configuration random_gas(int n, double phi, const Material& material, std::uint64_t seed,
                                Boundary boundary = Boundary::periodic) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> diameter(0.5, 1.0), unit(0.0, 1.0);
  std::vector<double> r(n);
  double area = 0.0;
  for (int i = 0; i < n; ++i) {
    r[i] = 0.5 * diameter(rng);
    area += 3.141592653589793 * r[i] * r[i];
  }
  const double side = std::sqrt(area / phi);
  Configuration c = empty_periodic(side, side, material);
  c.cell.boundary = boundary;
  for (int i = 0; i < n; ++i) {
    for (int attempt = 0; attempt < 100000; ++attempt) {
      double x = unit(rng) * side, y = unit(rng) * side;
      if (boundary == Boundary::walls) {
        x = r[i] + unit(rng) * (side - 2 * r[i]);
        y = r[i] + unit(rng) * (side - 2 * r[i]);
      }
      bool free = true;
      for (std::size_t j = 0; j < c.disks.size() && free; ++j) {
        double dx = c.disks.x[j] - x, dy = c.disks.y[j] - y;
        if (boundary == Boundary::periodic) {
          dx -= side * std::nearbyint(dx / side);
          dy -= side * std::nearbyint(dy / side);
        }
        free = dx * dx + dy * dy > (r[i] + c.disks.radius[j]) * (r[i] + c.disks.radius[j]);
      }
      if (free) {
        c.disks.add(x, y, r[i]);
        break;
      }
    }
  }
  const double m = dynamic::default_cell_mass(c.disks.mass);
  c.cell.mass = {m, m};
  return c;
}

// Largest net force over disks with at least two contacts (rattlers carry no force; SPEC §3.1).
inline double max_net_force_non_rattler(const Engine& e) {
  const Configuration c = e.configuration();
  std::vector<int> count(e.size(), 0);
  for (std::size_t k = 0; k < c.contacts.size(); ++k) {
    ++count[c.contacts.i[k]];
    if (c.contacts.j[k] >= 0) ++count[c.contacts.j[k]];
  }
  double f = 0.0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (count[i] >= 2) f = std::max(f, std::hypot(e.force_x(i), e.force_y(i)));
  }
  return f;
}

inline double max_stress_error(const Engine& e) {
  double err = 0.0;
  for (int a = 0; a < 2; ++a) {
    if (e.stage().control[a] != LengthControl::stress) continue;
    err = std::max(err, std::abs(e.controlled_stress(a) / e.stage().sigma_ext[a] - 1.0));
  }
  return err;
}

// Runs until forces (non-rattlers) < force_tol and controlled stresses within stress_tol
// (relative), checking every `chunk` steps; returns false if max_steps is reached first.
inline bool run_to_equilibrium(Engine& e, double force_tol, double stress_tol,
                               std::uint64_t max_steps, std::uint64_t chunk = 2000) {
  for (std::uint64_t s = 0; s < max_steps; s += chunk) {
    e.run(chunk);
    if (max_stress_error(e) < stress_tol && max_net_force_non_rattler(e) < force_tol) return true;
  }
  return false;
}

// A small dense packing at pressure 1: a random gas compressed by the engine itself under
// isotropic stress control, zeta = 1, to equilibrium (forces < 1e-6, stresses within 1e-6).
inline Configuration dense_packing(int n, const Material& material, std::uint64_t seed,
                                   Boundary boundary = Boundary::periodic) {
  Configuration c = random_gas(n, 0.2, material, seed, boundary);
  c.stage.control = {LengthControl::stress, LengthControl::stress};
  c.stage.sigma_ext = {1.0, 1.0};
  Engine e(c);
  if (!run_to_equilibrium(e, 1e-6, 1e-6, 2000000)) {
    throw std::runtime_error("dense_packing: no equilibrium reached");
  }
  Configuration out = e.configuration();
  out.stage.reference_length = out.cell.length;
  return out;
}

}  // namespace granstab::testing
