#include "tiny_samples.hpp"

#include <cmath>
#include <random>
#include <sstream>

#include "common/contact_law.hpp"

namespace granstab::samples {

void add_contacts_by_geometry(Configuration& c) {
  const Disks& d = c.disks;
  const Cell& cell = c.cell;
  const int n = static_cast<int>(d.size());
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const double dx = d.x[j] - d.x[i], dy = d.y[j] - d.y[i];
      const int k1 = cell.periodic() ? minimum_image_shift(dx, cell.length[0]) : 0;
      const int k2 = cell.periodic() ? minimum_image_shift(dy, cell.length[1]) : 0;
      const ContactFrame f = disk_disk_frame(dx + k1 * cell.length[0], dy + k2 * cell.length[1],
                                             d.radius[i], d.radius[j]);
      if (f.h > 0.0) c.contacts.add(i, j, k1, k2);
    }
    if (cell.periodic()) continue;
    for (const Wall w : {wall_left, wall_right, wall_bottom, wall_top})
      if (disk_wall_frame(d.x[i], d.y[i], d.radius[i], w, cell).h > 0.0) c.contacts.add(i, w, 0, 0);
  }
}

double triangular_lattice_overlap(double kappa) {
  // Per disk three contacts along 0, 60 and 120 degrees: sum n n = (3/2) I, area per disk
  // (sqrt 3 / 2) s^2, so sigma = sqrt(3) F_N / s. sigma = 1 with F_N = K_N h, s = 1 - h gives
  // K_N h = (1 - h) / sqrt(3), i.e. h = 1 / (sqrt(3) K_N + 1).
  return 1.0 / (std::sqrt(3.0) * kappa + 1.0);
}

Configuration triangular_lattice(double kappa) {
  Configuration c;
  c.material = Material::from_kappa(kappa, 1.0, 0.5, 1.0);
  const double s = 1.0 - triangular_lattice_overlap(kappa);
  const double row = 0.5 * std::sqrt(3.0) * s;
  const int columns = 4, rows = 4;  // 4 rows: each disk meets 6 distinct neighbours
  c.cell.length = {columns * s, rows * row};
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < columns; ++k)
      c.disks.add((k + 0.5 * (r % 2) + 0.25) * s, (r + 0.5) * row, 0.5);
  add_contacts_by_geometry(c);
  c.stage.reference_length = c.cell.length;
  // A real generator state, so the shipped sample exercises the rng_state field.
  std::ostringstream state;
  state << std::mt19937_64(2026);
  c.rng_state = state.str();
  return c;
}

double square_stack_overlap(int n, double kappa) {
  // Each of the n rows is a chain wall-disk-...-disk-wall carrying F = sigma L / n, with L the
  // box side: L = (n - 1)(1 - h) + 2 (1/2 - h) = n - (n + 1) h. K_N h = L / n gives h.
  return 1.0 / (kappa + (n + 1.0) / n);
}

Configuration square_stack(int n, double kappa) {
  Configuration c;
  c.material = Material::from_kappa(kappa, 0.5, 0.25, 1.0);
  const double h = square_stack_overlap(n, kappa);
  const double s = 1.0 - h;
  const double side = n - (n + 1) * h;
  c.cell.boundary = Boundary::walls;
  c.cell.length = {side, side};
  for (int r = 0; r < n; ++r)
    for (int k = 0; k < n; ++k) c.disks.add(0.5 - h + k * s, 0.5 - h + r * s, 0.5);
  add_contacts_by_geometry(c);
  c.stage.reference_length = c.cell.length;
  return c;
}

}  // namespace granstab::samples
