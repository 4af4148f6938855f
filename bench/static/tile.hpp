#pragma once
// A periodic equilibrium tiled nx x ny times is again an equilibrium (same forces, same
// delta_t): a way to benchmark the static solver at N = 100 nx ny from a shipped sample.
#include <stdexcept>

#include "common/configuration.hpp"

namespace granstab::bench {

inline Configuration tile(const Configuration& c, int nx, int ny) {
  if (nx == 1 && ny == 1) return c;  // (so that wall samples can be benchmarked as they are)
  if (!c.cell.periodic()) throw std::invalid_argument("tile: needs a periodic configuration");
  Configuration t = c;
  const std::size_t n = c.disks.size();
  const double l1 = c.cell.length[0], l2 = c.cell.length[1];
  t.disks = Disks{};
  t.contacts.clear();
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix)
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k =
            t.disks.add(c.disks.x[i] + ix * l1, c.disks.y[i] + iy * l2, c.disks.radius[i]);
        t.disks.theta[k] = c.disks.theta[i];
      }
  const auto wrap = [](int v, int m) { return ((v % m) + m) % m; };
  const auto floor_div = [](int v, int m) { return v >= 0 ? v / m : -((-v + m - 1) / m); };
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix)
      for (std::size_t c0 = 0; c0 < c.contacts.size(); ++c0) {
        const int tx = ix + c.contacts.k1[c0], ty = iy + c.contacts.k2[c0];
        const int i = (iy * nx + ix) * static_cast<int>(n) + c.contacts.i[c0];
        const int j = (wrap(ty, ny) * nx + wrap(tx, nx)) * static_cast<int>(n) + c.contacts.j[c0];
        t.contacts.add(i, j, floor_div(tx, nx), floor_div(ty, ny), c.contacts.delta_t[c0],
                       c.contacts.status[c0]);
      }
  t.cell.length = {l1 * nx, l2 * ny};
  t.stage.reference_length = {c.stage.reference_length[0] * nx, c.stage.reference_length[1] * ny};
  return t;
}

}  // namespace granstab::bench
