#include "networks.hpp"

#include <cmath>

#include "common/contact_law.hpp"

namespace granstab::statics::testing {

void add_overlapping_contacts(Network& net) {
  const std::size_t n = net.n_disks();
  for (std::size_t i = 0; i < n; ++i) {
    if (net.boundary == Boundary::walls) {
      Cell cell;
      cell.boundary = Boundary::walls;
      cell.length = net.length;
      for (Wall w : {wall_left, wall_right, wall_bottom, wall_top})
        if (disk_wall_frame(net.x[i], net.y[i], net.radius[i], w, cell).h > 0.0)
          net.contacts.add(static_cast<int>(i), w, 0, 0);
    }
    for (std::size_t j = i; j < n; ++j) {
      const int kmax = net.boundary == Boundary::periodic ? 1 : 0;
      for (int k1 = -kmax; k1 <= kmax; ++k1)
        for (int k2 = -kmax; k2 <= kmax; ++k2) {
          if (j == i && (k1 < 0 || (k1 == 0 && k2 <= 0))) continue;  // each self-image once
          const double lx = net.x[j] + k1 * net.length[0] - net.x[i];
          const double ly = net.y[j] + k2 * net.length[1] - net.y[i];
          if (std::hypot(lx, ly) < net.radius[i] + net.radius[j])
            net.contacts.add(static_cast<int>(i), static_cast<int>(j), k1, k2);
        }
    }
  }
}

Configuration configuration_from_network(const Network& net) {
  Configuration config;
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    config.disks.add(net.x[i], net.y[i], net.radius[i]);
    config.disks.theta[i] = net.theta[i];
  }
  config.cell.boundary = net.boundary;
  config.cell.length = net.length;
  config.material = net.material;
  config.contacts = net.contacts;
  config.stage.reference_length = net.length;
  config.stage.sigma_ext = net.loading.sigma;
  return config;
}

DofOptions all_active(const Network& net, bool pin_translation) {
  DofOptions o;
  o.active.assign(net.n_disks(), 1);
  o.pinned_translation = pin_translation && net.boundary == Boundary::periodic ? 0 : -1;
  return o;
}

namespace {
// Tangential states: contact c gets a trial F_T of (pattern) x mu F_N, alternating stick inside
// the cone and slip strictly beyond it in either direction.
void assign_tangential_states(Network& net) {
  static const double pattern[] = {0.4, -2.0, 2.5, -0.3, 0.0, 3.0, -0.6, -2.2};
  for (std::size_t c = 0; c < net.contacts.size(); ++c) {
    const int i = net.contacts.i[c], j = net.contacts.j[c];
    double h;
    if (is_wall(j)) {
      Cell cell;
      cell.boundary = Boundary::walls;
      cell.length = net.length;
      h = disk_wall_frame(net.x[i], net.y[i], net.radius[i], static_cast<Wall>(j), cell).h;
    } else {
      const double lx = net.x[j] + net.contacts.k1[c] * net.length[0] - net.x[i];
      const double ly = net.y[j] + net.contacts.k2[c] * net.length[1] - net.y[i];
      h = net.radius[i] + net.radius[j] - std::hypot(lx, ly);
    }
    const double f_trial = pattern[c % 8] * net.friction(c) * net.material.k_n * h;
    net.contacts.delta_t[c] = -f_trial / net.material.k_t;
  }
}
}  // namespace

Network periodic_mixed_network() {
  Network net;
  net.boundary = Boundary::periodic;
  net.length = {1.9, 1.62};
  net.x = {0.1, 1.04, 0.6, 1.5};
  net.y = {0.3, 0.36, 1.12, 1.17};
  net.radius = {0.52, 0.46, 0.5, 0.5};
  net.theta.assign(4, 0.0);
  net.material.k_n = 100.0;
  net.material.k_t = 50.0;
  net.material.mu = 0.4;
  net.loading.sigma = {1.0, 1.7};
  add_overlapping_contacts(net);
  assign_tangential_states(net);
  net.dofs = build_dof_map(all_active(net, true));
  return net;
}

Network walled_mixed_network() {
  Network net;
  net.boundary = Boundary::walls;
  net.length = {1.95, 1.9};
  net.x = {0.49, 1.45, 0.95};
  net.y = {0.48, 0.5, 1.42};
  net.radius = {0.5, 0.52, 0.5};
  net.theta.assign(3, 0.0);
  net.material.k_n = 100.0;
  net.material.k_t = 70.0;
  net.material.mu = 0.5;
  net.material.mu_wall = 0.3;
  net.loading.sigma = {0.8, 1.3};
  add_overlapping_contacts(net);
  assign_tangential_states(net);
  net.dofs = build_dof_map(all_active(net, false));
  return net;
}

Network triangular_lattice(double radius, double k_n, double k_t, double mu, double pressure) {
  // sigma = sqrt(3) F_N / d for the six-neighbour lattice; solve F_N = K_N (2R - d) for d.
  double d = 2.0 * radius;
  for (int it = 0; it < 100; ++it) d = 2.0 * radius - pressure * d / (std::sqrt(3.0) * k_n);
  Network net;
  net.boundary = Boundary::periodic;
  net.length = {d, std::sqrt(3.0) * d};
  net.x = {0.25 * d, 0.75 * d};
  net.y = {0.2 * d, 0.2 * d + 0.5 * std::sqrt(3.0) * d};
  net.radius = {radius, radius};
  net.theta = {0.0, 0.0};
  net.material.k_n = k_n;
  net.material.k_t = k_t;
  net.material.mu = mu;
  net.loading.sigma = {pressure, pressure};
  net.contacts.add(0, 0, 1, 0);
  net.contacts.add(1, 1, 1, 0);
  net.contacts.add(0, 1, 0, 0);
  net.contacts.add(0, 1, -1, 0);
  net.contacts.add(1, 0, 0, 1);
  net.contacts.add(1, 0, 1, 1);
  net.dofs = build_dof_map(all_active(net, true));
  return net;
}

}  // namespace granstab::statics::testing
