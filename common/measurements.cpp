#include "measurements.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace granstab {

ContactFrame contact_frame(const Configuration& config, std::size_t c) {
  const Disks& d = config.disks;
  const Contacts& k = config.contacts;
  const int i = k.i[c], j = k.j[c];
  if (is_wall(j))
    return disk_wall_frame(d.x[i], d.y[i], d.radius[i], static_cast<Wall>(j), config.cell);
  const double lx = d.x[j] + k.k1[c] * config.cell.length[0] - d.x[i];
  const double ly = d.y[j] + k.k2[c] * config.cell.length[1] - d.y[i];
  return disk_disk_frame(lx, ly, d.radius[i], d.radius[j]);
}

std::vector<ContactLoad> contact_loads(const Configuration& config) {
  const Material& m = config.material;
  const Contacts& k = config.contacts;
  std::vector<ContactLoad> loads(k.size());
  for (std::size_t c = 0; c < k.size(); ++c) {
    ContactLoad& load = loads[c];
    load.frame = contact_frame(config, c);
    if (!(load.frame.h > 0.0)) continue;
    const double mu = is_wall(k.j[c]) ? m.mu_wall : m.mu;
    load.carrying = true;
    load.f_n = m.k_n * load.frame.h;
    load.f_t = tangential_force(m.k_t, mu, load.f_n, k.delta_t[c]).f_t;
    load.sliding = is_sliding(load.f_t, load.f_n, mu);
  }
  return loads;
}

NetForces net_forces(const Configuration& config, const std::vector<ContactLoad>& loads) {
  const std::size_t n = config.disks.size();
  const Contacts& k = config.contacts;
  NetForces net{std::vector<double>(n, 0.0), std::vector<double>(n, 0.0),
                std::vector<double>(n, 0.0)};
  for (std::size_t c = 0; c < loads.size(); ++c) {
    const ContactLoad& l = loads[c];
    if (!l.carrying) continue;
    const ContactFrame& f = l.frame;
    const double fx = l.f_n * f.nx + l.f_t * f.tx;
    const double fy = l.f_n * f.ny + l.f_t * f.ty;
    // f acts on j, -f on i, at the contact point; torques -a F_T on both (contact_law.hpp).
    const int i = k.i[c], j = k.j[c];
    net.fx[i] -= fx;
    net.fy[i] -= fy;
    net.torque[i] -= f.a_i * l.f_t;
    if (!is_wall(j)) {
      net.fx[j] += fx;
      net.fy[j] += fy;
      net.torque[j] -= f.a_j * l.f_t;
    }
  }
  return net;
}

std::vector<std::uint8_t> find_rattlers(const Configuration& config,
                                        const std::vector<ContactLoad>& loads) {
  const std::size_t n = config.disks.size();
  const Contacts& k = config.contacts;
  std::vector<int> count(n, 0);
  for (std::size_t c = 0; c < loads.size(); ++c) {
    if (!loads[c].carrying) continue;
    ++count[k.i[c]];
    if (!is_wall(k.j[c])) ++count[k.j[c]];
  }
  // Removing a disk lowers its partners' counts, which may remove them in turn: a work list
  // visits each removal once. Adjacency is built once (CSR) so this stays O(N + Nc).
  std::vector<std::size_t> start(n + 1, 0);
  for (std::size_t c = 0; c < loads.size(); ++c) {
    if (!loads[c].carrying || is_wall(k.j[c])) continue;
    ++start[k.i[c] + 1];
    ++start[k.j[c] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<int> partner(start[n]);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t c = 0; c < loads.size(); ++c) {
    if (!loads[c].carrying || is_wall(k.j[c])) continue;
    partner[fill[k.i[c]]++] = k.j[c];
    partner[fill[k.j[c]]++] = k.i[c];
  }
  std::vector<std::uint8_t> rattler(n, 0);
  std::vector<int> pending;
  for (std::size_t i = 0; i < n; ++i)
    if (count[i] < 2) {
      rattler[i] = 1;
      pending.push_back(static_cast<int>(i));
    }
  while (!pending.empty()) {
    const int r = pending.back();
    pending.pop_back();
    for (std::size_t p = start[r]; p < start[r + 1]; ++p) {
      const int other = partner[p];
      if (rattler[other]) continue;
      if (--count[other] < 2) {
        rattler[other] = 1;
        pending.push_back(other);
      }
    }
  }
  return rattler;
}

StressTensor stress_tensor(const Configuration& config, const std::vector<ContactLoad>& loads) {
  StressTensor s{};
  for (const ContactLoad& l : loads) {
    if (!l.carrying) continue;
    const ContactFrame& f = l.frame;
    const double force[2] = {l.f_n * f.nx + l.f_t * f.tx, l.f_n * f.ny + l.f_t * f.ty};
    const double branch[2] = {f.lx, f.ly};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) s[a][b] += force[a] * branch[b];
  }
  const double area = config.cell.area();
  for (auto& row : s)
    for (double& v : row) v /= area;
  return s;
}

std::array<double, 4> wall_forces(const Configuration& config,
                                  const std::vector<ContactLoad>& loads) {
  std::array<double, 4> force{};
  const Contacts& k = config.contacts;
  for (std::size_t c = 0; c < loads.size(); ++c)
    // n points from the disk into the wall: the push on the wall is F_N; F_T runs along it.
    if (loads[c].carrying && is_wall(k.j[c])) force[-k.j[c] - 1] += loads[c].f_n;
  return force;
}

double controlled_stress(const Configuration& config, const StressTensor& sigma, int a) {
  if (config.stage.measure == StressMeasure::cauchy) return sigma[a][a];
  // Nominal: the force on the side normal to a (sigma_aa times the current side length L_b)
  // over the side's length at the start of the stage.
  const int b = 1 - a;
  return sigma[a][a] * config.cell.length[b] / config.stage.reference_length[b];
}

double solid_fraction(const Configuration& config) {
  double disks_area = 0.0;
  for (const double r : config.disks.radius) disks_area += std::numbers::pi * r * r;
  return disks_area / config.cell.area();
}

double kinetic_energy_per_disk(const Disks& d) {
  if (d.empty()) return 0.0;
  double e = 0.0;
  for (std::size_t i = 0; i < d.size(); ++i)
    e += 0.5 * d.mass[i] * (d.vx[i] * d.vx[i] + d.vy[i] * d.vy[i]) +
         0.5 * d.inertia[i] * d.omega[i] * d.omega[i];
  return e / static_cast<double>(d.size());
}

std::array<double, 3> strains(const Configuration& config) {
  const double e1 = 1.0 - config.cell.length[0] / config.stage.reference_length[0];
  const double e2 = 1.0 - config.cell.length[1] / config.stage.reference_length[1];
  return {e1, e2, e1 + e2 - e1 * e2};
}

Measurements measure(const Configuration& config) {
  Measurements m;
  const std::size_t n = config.disks.size();
  const Contacts& k = config.contacts;
  m.n_disks = n;
  m.area = config.cell.area();
  m.phi = solid_fraction(config);
  const auto loads = contact_loads(config);
  m.sigma = stress_tensor(config, loads);
  m.q = (m.sigma[1][1] - m.sigma[0][0]) / m.sigma[0][0];
  const auto eps = strains(config);
  m.epsilon_1 = eps[0];
  m.epsilon_2 = eps[1];
  m.epsilon_v = eps[2];

  const auto rattler = find_rattlers(config, loads);
  m.n_contacts_listed = k.size();
  for (std::size_t c = 0; c < loads.size(); ++c) {
    if (!loads[c].carrying) continue;
    ++m.n_contacts_carrying;
    if (loads[c].sliding) ++m.n_sliding;
    const bool wall = is_wall(k.j[c]);
    if (rattler[k.i[c]] || (!wall && rattler[k.j[c]])) continue;
    ++(wall ? m.n_network_wall : m.n_network_disk_disk);
  }
  for (const auto r : rattler) m.n_rattlers += r;
  const std::size_t n_active = n - m.n_rattlers;
  m.x0 = n > 0 ? static_cast<double>(m.n_rattlers) / static_cast<double>(n) : 0.0;
  m.z = n_active > 0 ? static_cast<double>(2 * m.n_network_disk_disk + m.n_network_wall) /
                           static_cast<double>(n_active)
                     : 0.0;
  m.x_s = m.n_contacts_carrying > 0
              ? static_cast<double>(m.n_sliding) / static_cast<double>(m.n_contacts_carrying)
              : 0.0;

  m.e_c = kinetic_energy_per_disk(config.disks);
  const NetForces net = net_forces(config, loads);
  double sum_f2 = 0.0, sum_t2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (rattler[i]) continue;
    const double f2 = net.fx[i] * net.fx[i] + net.fy[i] * net.fy[i];
    const double t2 = net.torque[i] * net.torque[i];
    sum_f2 += f2;
    sum_t2 += t2;
    if (std::sqrt(f2) > m.max_net_force) {
      m.max_net_force = std::sqrt(f2);
      m.max_force_disk = i;
    }
    if (std::abs(net.torque[i]) > m.max_net_torque) {
      m.max_net_torque = std::abs(net.torque[i]);
      m.max_torque_disk = i;
    }
  }
  if (n_active > 0) {
    m.f_2 = std::sqrt(sum_f2 / static_cast<double>(n_active));
    m.torque_2 = std::sqrt(sum_t2 / static_cast<double>(n_active));
  }
  return m;
}

}  // namespace granstab
