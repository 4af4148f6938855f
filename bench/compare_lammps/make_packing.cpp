// Generator of the issue #7 comparison (bench/compare_lammps/run.sh): one dense periodic packing
// of N disks (diameters uniform in [1/2, 1], m = d^2, I = m d^2 / 8, prepared as in
// bench/dynamic/sample.hpp), written for both codes:
//   PREFIX.granstab   the granstab configuration (docs/file-format.md)
//   PREFIX.data       a LAMMPS data file, atom_style sphere
//   PREFIX.env        shell variables for run.sh: N, L1, L2, DT, GAMMA_N, ...
//
//   make_packing N SEED PREFIX [strain_rate]
//
// The contact parameters are those of issue #7: kappa = 1e4, K_T = K_N, mu = 0.5, zeta = 1.
// LAMMPS's pair gran/hooke/history damps with meff gamma_n dh/dt, granstab with
// alpha_ij dh/dt, alpha_ij = 2 zeta sqrt(K_N meff_ij): one gamma_n cannot match every pair.
// gamma_n = 2 zeta sqrt(K_N / m_ref) with m_ref the mean effective mass over the contacts of
// the packing; a pair then has LAMMPS damping ratio zeta sqrt(meff / m_ref) (range printed).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "common/io/configuration_file.hpp"
#include "dynamic/sample.hpp"

int main(int argc, char** argv) {
  using namespace granstab;
  if (argc < 4) {
    std::fprintf(stderr, "usage: make_packing N SEED PREFIX [strain_rate]\n");
    return 2;
  }
  const int n = std::atoi(argv[1]);
  const auto seed = static_cast<std::uint64_t>(std::atoll(argv[2]));
  const std::string prefix = argv[3];
  const double strain_rate = argc > 4 ? std::atof(argv[4]) : 1e-4;
  const Material material = Material::from_kappa(1e4, 1.0, 0.5, 1.0);

  Configuration c = bench::dense_sample(n, material, seed);
  // The test of both codes: L1 fixed, epsilon_2 grows at strain_rate from the current state.
  c.stage.control = {LengthControl::fixed, LengthControl::strain_rate};
  c.stage.strain_rate = {0.0, strain_rate};
  c.stage.reference_length = c.cell.length;
  c.cell.length_rate = {0.0, -strain_rate * c.cell.length[1]};
  c.time = 0.0;
  c.step = 0;
  write_configuration(c, prefix + ".granstab");

  const Disks& d = c.disks;
  const double l1 = c.cell.length[0], l2 = c.cell.length[1];
  const double m_min = *std::min_element(d.mass.begin(), d.mass.end());
  const double dt = 0.05 * std::sqrt(m_min / material.k_n);

  // Mean effective mass over the contacts of the packing (the damping reference).
  double meff_sum = 0.0, meff_min = INFINITY, meff_max = 0.0;
  for (std::size_t k = 0; k < c.contacts.size(); ++k) {
    const double mi = d.mass[c.contacts.i[k]], mj = d.mass[c.contacts.j[k]];
    const double meff = mi * mj / (mi + mj);
    meff_sum += meff;
    meff_min = std::min(meff_min, meff);
    meff_max = std::max(meff_max, meff);
  }
  if (c.contacts.size() == 0) throw std::runtime_error("make_packing: packing has no contacts");
  const double m_ref = meff_sum / static_cast<double>(c.contacts.size());
  const double gamma_n = 2.0 * material.zeta * std::sqrt(material.k_n / m_ref);

  // LAMMPS data file. atom_style sphere: id type diameter density x y z; this LAMMPS computes
  // the mass as density * 4/3 pi r^3 (run.sh checks the total mass it reports), so density =
  // d^2 / (pi d^3 / 6) gives m = d^2. Velocities: the fluctuating velocity plus the affine
  // field of the strain-rate test about the box centre (fix deform ... remap v).
  const double erate = -strain_rate;  // LAMMPS engineering rate of L2
  FILE* f = std::fopen((prefix + ".data").c_str(), "w");
  if (!f) throw std::runtime_error("make_packing: cannot write " + prefix + ".data");
  std::fprintf(f, "granstab issue #7 packing, N = %d, seed %llu\n\n%d atoms\n1 atom types\n\n", n,
               static_cast<unsigned long long>(seed), n);
  std::fprintf(f, "0 %.17g xlo xhi\n0 %.17g ylo yhi\n-0.5 0.5 zlo zhi\n\nAtoms # sphere\n\n", l1,
               l2);
  for (int i = 0; i < n; ++i) {
    const double diameter = 2.0 * d.radius[i];
    const double density = d.mass[i] / (M_PI * diameter * diameter * diameter / 6.0);
    std::fprintf(f, "%d 1 %.17g %.17g %.17g %.17g 0\n", i + 1, diameter, density, d.x[i], d.y[i]);
  }
  std::fprintf(f, "\nVelocities\n\n");
  for (int i = 0; i < n; ++i) {
    std::fprintf(f, "%d %.17g %.17g 0 0 0 %.17g\n", i + 1, d.vx[i],
                 d.vy[i] + erate * (d.y[i] - 0.5 * l2), d.omega[i]);
  }
  std::fclose(f);

  double total_mass = 0.0;
  for (double m : d.mass) total_mass += m;
  FILE* e = std::fopen((prefix + ".env").c_str(), "w");
  if (!e) throw std::runtime_error("make_packing: cannot write " + prefix + ".env");
  std::fprintf(e, "N=%d\nL1=%.17g\nL2=%.17g\nDT=%.17g\nKN=%.17g\nKT=%.17g\nMU=%.17g\n", n, l1, l2,
               dt, material.k_n, material.k_t, material.mu);
  std::fprintf(e, "GAMMA_N=%.17g\nM_REF=%.17g\nERATE=%.17g\nTOTAL_MASS=%.17g\nCONTACTS=%zu\n",
               gamma_n, m_ref, erate, total_mass, c.contacts.size());
  std::fprintf(e, "ZETA_LAMMPS_MIN=%.4f\nZETA_LAMMPS_MAX=%.4f\n",
               material.zeta * std::sqrt(meff_min / m_ref),
               material.zeta * std::sqrt(meff_max / m_ref));
  std::fclose(e);
  std::printf("N = %d: L = %.6g x %.6g, %zu contacts, dt = %.6g, gamma_n = %.6g (m_ref = %.6g)\n",
              n, l1, l2, c.contacts.size(), dt, gamma_n, m_ref);
  return 0;
}
