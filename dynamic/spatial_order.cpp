#include "spatial_order.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace granstab {

std::vector<std::int32_t> spatial_order(const Configuration& config) {
  const Disks& d = config.disks;
  const std::size_t n = d.size();
  double r_max = 0.0;
  for (double r : d.radius) r_max = std::max(r_max, r);
  const double side = std::max(2.0 * r_max, 1e-12);
  const int nx = std::max(1, static_cast<int>(config.cell.length[0] / side));
  const int ny = std::max(1, static_cast<int>(config.cell.length[1] / side));
  std::vector<std::int64_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    int cx = static_cast<int>(std::floor(d.x[i] / config.cell.length[0] * nx));
    int cy = static_cast<int>(std::floor(d.y[i] / config.cell.length[1] * ny));
    cx = std::clamp(cx, 0, nx - 1);
    cy = std::clamp(cy, 0, ny - 1);
    if (cy % 2 == 1) cx = nx - 1 - cx;  // boustrophedon: consecutive rows stay adjacent
    key[i] = static_cast<std::int64_t>(cy) * nx + cx;
  }
  std::vector<std::int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::int32_t a, std::int32_t b) { return key[a] < key[b]; });
  return order;
}

Configuration renumbered(const Configuration& config, const std::vector<std::int32_t>& order) {
  const std::size_t n = config.disks.size();
  if (order.size() != n) throw std::invalid_argument("renumbered: order must have N entries");
  std::vector<std::int32_t> new_index(n, -1);
  for (std::size_t k = 0; k < n; ++k) {
    const std::int32_t o = order[k];
    if (o < 0 || static_cast<std::size_t>(o) >= n || new_index[o] >= 0) {
      throw std::invalid_argument("renumbered: order is not a permutation (entry " +
                                  std::to_string(k) + ")");
    }
    new_index[o] = static_cast<std::int32_t>(k);
  }
  Configuration out = config;
  const Disks& s = config.disks;
  Disks& d = out.disks;
  for (std::size_t k = 0; k < n; ++k) {
    const std::int32_t o = order[k];
    d.x[k] = s.x[o];
    d.y[k] = s.y[o];
    d.radius[k] = s.radius[o];
    d.mass[k] = s.mass[o];
    d.inertia[k] = s.inertia[o];
    d.vx[k] = s.vx[o];
    d.vy[k] = s.vy[o];
    d.omega[k] = s.omega[o];
    d.theta[k] = s.theta[o];
  }
  Contacts& c = out.contacts;
  for (std::size_t k = 0; k < c.size(); ++k) {
    c.i[k] = new_index[config.contacts.i[k]];
    if (is_wall(config.contacts.j[k])) continue;
    c.j[k] = new_index[config.contacts.j[k]];
    if (c.i[k] > c.j[k]) {
      // l changes sign with the swap: the image of the new j is the negated one.
      std::swap(c.i[k], c.j[k]);
      c.k1[k] = -c.k1[k];
      c.k2[k] = -c.k2[k];
    }
  }
  return out;
}

}  // namespace granstab
