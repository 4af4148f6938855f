// The rigid-limit LP's network (rigid_network.hpp).
#include "static/rigid_network.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace granstab::statics::rigid {
namespace {

ContactFrame frame_of(const Configuration& config, std::size_t k) {
  const Contacts& c = config.contacts;
  const Disks& d = config.disks;
  const int i = c.i[k], j = c.j[k];
  if (is_wall(j)) return disk_wall_frame(d.x[i], d.y[i], d.radius[i], Wall(j), config.cell);
  const double lx = d.x[j] + c.k1[k] * config.cell.length[0] - d.x[i];
  const double ly = d.y[j] + c.k2[k] * config.cell.length[1] - d.y[i];
  return disk_disk_frame(lx, ly, d.radius[i], d.radius[j]);
}

// A disk with fewer than two contacts must carry zero force (one contact cannot balance), so
// removing it and its contact is exact; iterate, as in the rattler definition of SPEC §2.
void remove_weak_disks(const Configuration& config, FrozenNetwork& net) {
  const Contacts& c = config.contacts;
  const std::size_t n = config.disks.size();
  std::vector<std::vector<int>> touching(n);
  std::vector<int> degree(n, 0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!net.active[k]) continue;
    touching[c.i[k]].push_back(static_cast<int>(k));
    ++degree[c.i[k]];
    if (!is_wall(c.j[k])) {
      touching[c.j[k]].push_back(static_cast<int>(k));
      ++degree[c.j[k]];
    }
  }
  std::deque<int> weak;
  for (std::size_t i = 0; i < n; ++i)
    if (degree[i] < 2) weak.push_back(static_cast<int>(i));
  while (!weak.empty()) {
    const int i = weak.front();
    weak.pop_front();
    for (const int k : touching[i]) {
      if (!net.active[k]) continue;
      net.active[k] = 0;
      for (const int end : {c.i[k], c.j[k]}) {
        if (is_wall(end)) continue;
        if (--degree[end] == 1) weak.push_back(end);  // reaching 0 means it was queued at 1
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) net.disk_active[i] = degree[i] >= 2;
}

// Components of the disk-disk graph. A component that neither touches a wall nor wraps around
// the periodic cell is a finite floating cluster: its self-stress contributes
// sum l (x) f = sum_i r_i (x) F_i = 0 to the stress, so dropping it is exact (and removes its
// three dependent balance rows). A component without walls that wraps keeps its rows except the
// force rows of one disk, which are the negative sum of the others.
void classify_components(const Configuration& config, FrozenNetwork& net) {
  const Contacts& c = config.contacts;
  const std::size_t n = config.disks.size();
  struct Link {
    int other, contact, sx, sy;
  };  // image shift of `other` seen from this disk
  std::vector<std::vector<Link>> links(n);
  std::vector<char> on_wall(n, 0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!net.active[k]) continue;
    const int i = c.i[k], j = c.j[k];
    if (is_wall(j)) {
      on_wall[i] = 1;
      continue;
    }
    links[i].push_back({j, static_cast<int>(k), c.k1[k], c.k2[k]});
    links[j].push_back({i, static_cast<int>(k), -c.k1[k], -c.k2[k]});
  }
  std::vector<int> component(n, -1);
  std::vector<std::array<int, 2>> offset(n, {0, 0});
  std::vector<int> members;
  for (std::size_t root = 0; root < n; ++root) {
    if (!net.disk_active[root] || component[root] >= 0) continue;
    members.assign(1, static_cast<int>(root));
    component[root] = static_cast<int>(root);
    bool wraps = false, walled = false;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const int i = members[m];
      walled = walled || on_wall[i];
      for (const Link& link : links[i]) {
        const std::array<int, 2> o{offset[i][0] + link.sx, offset[i][1] + link.sy};
        if (component[link.other] < 0) {
          component[link.other] = static_cast<int>(root);
          offset[link.other] = o;
          members.push_back(link.other);
        } else if (offset[link.other] != o) {
          wraps = true;  // a loop of contacts with a nonzero net image shift
        }
      }
    }
    if (walled) continue;
    if (wraps) {
      net.pinned[root] = 1;
      continue;
    }
    for (const int i : members) {
      net.disk_active[i] = 0;
      for (const Link& link : links[i]) net.active[link.contact] = 0;
    }
  }
}

// Torque rows involve only the tangential forces of frictional contacts. A "gear" mode,
// a_i theta_i + a_j theta_j = 0 on every frictional contact of a component (theta alternating
// around even loops, e.g. two disks touching twice across a periodic cell, or any tree of
// frictional contacts), makes sum_i theta_i (torque row i) vanish identically, so the torque
// row of one disk is dependent: drop it (Ipopt fails on, or returns no valid dual for, dependent
// rows). A frictional wall contact (a_wall = 0) or a frictional self-image contact forces
// theta = 0 and excludes the mode.
void drop_gear_torque_rows(const Configuration& config, FrozenNetwork& net) {
  const Contacts& c = config.contacts;
  const std::size_t n = config.disks.size();
  struct Link {
    int other, contact;
    bool from_i;
  };
  std::vector<std::vector<Link>> links(n);
  std::vector<char> blocked(n, 0), frictional(n, 0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!net.active[k] || !(net.mu[k] > 0.0)) continue;
    const int i = c.i[k], j = c.j[k];
    frictional[i] = 1;
    if (is_wall(j) || i == j) {
      blocked[i] = 1;
      continue;
    }
    frictional[j] = 1;
    links[i].push_back({j, static_cast<int>(k), true});
    links[j].push_back({i, static_cast<int>(k), false});
  }
  std::vector<double> theta(n, 0.0);
  std::vector<char> seen(n, 0);
  std::vector<int> members;
  for (std::size_t root = 0; root < n; ++root) {
    if (!frictional[root] || seen[root]) continue;
    members.assign(1, static_cast<int>(root));
    seen[root] = 1;
    theta[root] = 1.0;
    bool gear = true;
    for (std::size_t m = 0; m < members.size(); ++m) {
      const int x = members[m];
      gear = gear && !blocked[x];
      for (const Link& link : links[x]) {
        const ContactFrame& f = net.frame[link.contact];
        const double wanted = link.from_i ? -f.a_i * theta[x] / f.a_j : -f.a_j * theta[x] / f.a_i;
        if (!seen[link.other]) {
          seen[link.other] = 1;
          theta[link.other] = wanted;
          members.push_back(link.other);
        } else if (std::abs(wanted - theta[link.other]) > 1e-10 * std::abs(wanted)) {
          gear = false;
        }
      }
    }
    if (gear) net.torque_dropped[root] = 1;
  }
}

}  // namespace

void check_configuration(const Configuration& config, const RigidLimitOptions& options) {
  validate(config.cell);
  if (!(options.sigma1 > 0.0) || !std::isfinite(options.sigma1))
    throw std::invalid_argument("rigid_limit: options.sigma1 must be positive and finite");
  const Contacts& c = config.contacts;
  const auto n = static_cast<std::int64_t>(config.disks.size());
  if (c.j.size() != c.size() || c.k1.size() != c.size() || c.k2.size() != c.size())
    throw std::invalid_argument("rigid_limit: contacts.i, j, k1, k2 differ in length");
  for (std::size_t k = 0; k < c.size(); ++k) {
    const std::string where = "rigid_limit: contacts[" + std::to_string(k) + "]";
    if (c.i[k] < 0 || c.i[k] >= n) throw std::invalid_argument(where + ".i out of range");
    if (c.j[k] >= n || c.j[k] < wall_top) throw std::invalid_argument(where + ".j out of range");
    if (is_wall(c.j[k])) {
      if (config.cell.periodic())
        throw std::invalid_argument(where + " is a wall contact in a periodic cell");
    } else if (!config.cell.periodic() && (c.k1[k] != 0 || c.k2[k] != 0)) {
      throw std::invalid_argument(where + " has an image shift in a walled cell");
    }
    if (c.i[k] == c.j[k] && c.k1[k] == 0 && c.k2[k] == 0)
      throw std::invalid_argument(where + " joins a disk to itself");
  }
}

FrozenNetwork build_network(const Configuration& config) {
  const Contacts& c = config.contacts;
  FrozenNetwork net;
  net.frame.resize(c.size());
  net.mu.resize(c.size());
  net.active.assign(c.size(), 0);
  net.disk_active.assign(config.disks.size(), 0);
  net.pinned.assign(config.disks.size(), 0);
  net.torque_dropped.assign(config.disks.size(), 0);
  for (std::size_t k = 0; k < c.size(); ++k) {
    net.frame[k] = frame_of(config, k);
    net.mu[k] = is_wall(c.j[k]) ? config.material.mu_wall : config.material.mu;
    net.active[k] = net.frame[k].h > 0.0;  // the network: contacts with h > 0 (brief, §1.1)
  }
  remove_weak_disks(config, net);
  classify_components(config, net);
  drop_gear_torque_rows(config, net);
  return net;
}

}  // namespace granstab::statics::rigid
