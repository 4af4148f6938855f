#include "static/backbone.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "common/cell.hpp"
#include "common/contact_law.hpp"

namespace granstab::statics {

std::vector<char> force_carrying_disks(const Network& net,
                                       const std::vector<ContactState>& states) {
  std::vector<char> carries(states.size());
  for (std::size_t c = 0; c < states.size(); ++c) carries[c] = states[c].f_n > 0.0;
  return force_carrying_disks(net, carries);
}

std::vector<char> force_carrying_disks(const Network& net, const std::vector<char>& carries) {
  const std::size_t n = net.n_disks();
  std::vector<char> carrying(n, 1);
  if (!net.constraints.remove_rattlers) return carrying;
  const auto fixed = [&](std::size_t i) {
    return !net.constraints.disk_fixed.empty() && net.constraints.disk_fixed[i];
  };
  // Each disk's force-carrying contacts (walls and fixed disks count and stay; a contact with the
  // disk's own periodic image counts twice and never goes). The disks left are the largest set
  // in which every other disk keeps two, whatever the order of removal, so a worklist finds
  // them, each removal visiting its own contacts only.
  const Contacts& k = net.contacts;
  std::vector<int> count(n, 0), start(n + 1, 0), neighbour;
  const auto between_disks = [&](std::size_t c) {
    return carries[c] && !is_wall(k.j[c]) && k.i[c] != k.j[c];
  };
  for (std::size_t c = 0; c < k.size(); ++c) {
    if (!carries[c]) continue;
    ++count[k.i[c]];
    if (!is_wall(k.j[c])) ++count[k.j[c]];
    if (!between_disks(c)) continue;
    ++start[k.i[c] + 1];
    ++start[k.j[c] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  neighbour.resize(start[n]);
  std::vector<int> next(start.begin(), start.end() - 1);
  for (std::size_t c = 0; c < k.size(); ++c) {
    if (!between_disks(c)) continue;
    neighbour[next[k.i[c]]++] = k.j[c];
    neighbour[next[k.j[c]]++] = k.i[c];
  }
  std::vector<int> leaving;
  const auto leaves = [&](int i) {
    if (!carrying[i] || fixed(i) || count[i] >= 2) return;
    carrying[i] = 0;
    leaving.push_back(i);
  };
  for (std::size_t i = 0; i < n; ++i) leaves(static_cast<int>(i));
  while (!leaving.empty()) {
    const int i = leaving.back();
    leaving.pop_back();
    for (int e = start[i]; e < start[i + 1]; ++e) {
      --count[neighbour[e]];
      leaves(neighbour[e]);
    }
  }
  return carrying;
}

std::vector<int> caught_rattlers(const Network& net, const std::vector<ContactState>& states) {
  // rebuild_degrees_of_freedom's rule at dq: with every disk active, a listed contact carries
  // force where it overlaps.
  std::vector<char> overlapping(states.size());
  for (std::size_t c = 0; c < states.size(); ++c) overlapping[c] = states[c].frame.h > 0.0;
  const std::vector<char> carrying = force_carrying_disks(net, overlapping);
  std::vector<int> caught;
  for (std::size_t i = 0; i < net.n_disks(); ++i)
    if (net.dofs.is_rattler(i) && carrying[i]) caught.push_back(static_cast<int>(i));
  return caught;
}

void rebuild_degrees_of_freedom(Network& net) {
  net.dofs = build_dof_map([&] {
    DofOptions o;
    o.active.assign(net.n_disks(), 1);
    o.cell = net.constraints.cell_free;
    return o;
  }());
  const std::vector<ContactState> states =
      evaluate_contacts(net, Eigen::VectorXd::Zero(net.dofs.size));
  DofOptions o;
  o.active = force_carrying_disks(net, states);
  const std::vector<char> carrying = o.active;
  bool any_fixed = false;
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    if (!net.constraints.disk_fixed.empty() && net.constraints.disk_fixed[i]) {
      o.active[i] = 0;
      any_fixed = true;
    }
  }
  o.rotation_fixed = net.constraints.rotation_fixed;
  o.cell = net.constraints.cell_free;
  if (net.boundary == Boundary::periodic && !any_fixed) {
    for (std::size_t i = 0; i < net.n_disks(); ++i)
      if (o.active[i]) {
        o.pinned_translation = static_cast<int>(i);
        break;
      }
  }
  net.dofs = build_dof_map(o);
  net.dofs.rattler.assign(net.n_disks(), 0);
  for (std::size_t i = 0; i < net.n_disks(); ++i)
    net.dofs.rattler[i] =
        !carrying[i] && (net.constraints.disk_fixed.empty() || !net.constraints.disk_fixed[i]);
}

namespace {

// activate_disks and make_rattlers: the listed disks get (or lose) their dofs, every other dof
// and the pinned translation kept, dq carried over to the new numbering. False if nothing changed
// or (making rattlers) a listed disk holds the pinned translation.
bool set_active(Network& net, const std::vector<int>& disks, bool active, Eigen::VectorXd& dq) {
  const DofMap old = net.dofs;
  DofOptions o;
  o.active.assign(net.n_disks(), 0);
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    o.active[i] = old.active(i);
    // The pinned translation: an active disk without u (rotation_fixed aside).
    if (old.ux[i] < 0 && old.theta[i] >= 0) o.pinned_translation = static_cast<int>(i);
  }
  bool changed = false;
  for (const int i : disks) {
    if (i < 0 || static_cast<std::size_t>(i) >= net.n_disks() || o.active[i] == active) continue;
    if (!active && i == o.pinned_translation) return false;
    o.active[i] = active;
    changed = true;
  }
  if (!changed) return false;
  if (!active) {
    // A new rattler keeps the displacement dq gives it (off its contacts, in the corrector: see
    // step_off_lone_contacts): put back at the step's start it would overlap its cage again and
    // be a disk with contacts at the next preparation.
    const std::array<double, 2> e = cell_extension(net, dq);
    for (const int i : disks) {
      if (i < 0 || static_cast<std::size_t>(i) >= net.n_disks()) continue;
      if (old.ux[i] >= 0) net.x[i] += dq[old.ux[i]] / (1.0 + e[0]);
      if (old.uy[i] >= 0) net.y[i] += dq[old.uy[i]] / (1.0 + e[1]);
      if (old.theta[i] >= 0) net.theta[i] += dq[old.theta[i]];
    }
  }
  o.rotation_fixed = net.constraints.rotation_fixed;
  o.cell = net.constraints.cell_free;
  net.dofs = build_dof_map(o);
  net.dofs.rattler = old.rattler;
  for (const int i : disks)
    if (i >= 0 && static_cast<std::size_t>(i) < net.dofs.rattler.size())
      net.dofs.rattler[i] = !active;
  Eigen::VectorXd moved = Eigen::VectorXd::Zero(net.dofs.size);
  const auto carry = [&](int from, int to) {
    if (from >= 0 && to >= 0) moved[to] = dq[from];
  };
  for (std::size_t i = 0; i < net.n_disks(); ++i) {
    carry(old.ux[i], net.dofs.ux[i]);
    carry(old.uy[i], net.dofs.uy[i]);
    carry(old.theta[i], net.dofs.theta[i]);
  }
  for (int a = 0; a < 2; ++a) carry(old.e[a], net.dofs.e[a]);
  dq = std::move(moved);
  return true;
}

}  // namespace

void activate_disks(Network& net, const std::vector<int>& disks, Eigen::VectorXd& dq) {
  set_active(net, disks, true, dq);
}

bool make_rattlers(Network& net, const std::vector<int>& disks, Eigen::VectorXd& dq) {
  return set_active(net, disks, false, dq);
}

std::vector<int> step_off_lone_contacts(const Network& net, const std::vector<int>& lone,
                                        const std::vector<ContactState>& states,
                                        Eigen::VectorXd& dq) {
  std::vector<int> disks;
  const DofMap& m = net.dofs;
  for (std::size_t i = 0; i < lone.size(); ++i) {
    if (lone[i] < 0) continue;
    disks.push_back(static_cast<int>(i));
    // n points from the contact's first disk to its second: the first moves against it.
    const ContactFrame& f = states[lone[i]].frame;
    const double away = (net.contacts.i[lone[i]] == static_cast<int>(i) ? -1.01 : 1.01) * f.h;
    dq[m.ux[i]] += away * f.nx;
    dq[m.uy[i]] += away * f.ny;
  }
  return disks;
}

int escaped_disk(const Network& before, const Network& after) {
  // The walls at 0 stay, the others move with the lengths: the affine map of both boundaries.
  const double s0 = after.length[0] / before.length[0], s1 = after.length[1] / before.length[1];
  for (std::size_t i = 0; i < before.n_disks() && i < after.n_disks(); ++i) {
    const double ux = after.x[i] - s0 * before.x[i], uy = after.y[i] - s1 * before.y[i];
    if (!(std::hypot(ux, uy) <= before.radius[i])) return static_cast<int>(i);
  }
  return -1;
}

namespace {

// What a rattler at displacement y (from where it is) must keep clear of: a disk whose centre is
// at c, at distance >= reach; or a wall, a . y >= reach with a the unit normal away from it.
struct Limit {
  bool wall;
  double cx, cy, reach;
};

bool clears(const std::vector<Limit>& limits, double yx, double yy) {
  for (const Limit& l : limits) {
    const double slack = 1e-14 * std::max(std::abs(l.reach), 1.0);
    if (l.wall ? l.cx * yx + l.cy * yy < l.reach - slack
               : std::hypot(yx - l.cx, yy - l.cy) < l.reach - slack)
      return false;
  }
  return true;
}

// The points of a limit's boundary (circle or line) that lie on another's: at most two.
int meet(const Limit& p, const Limit& q, std::array<double, 4>& y) {
  if (p.wall && q.wall) {
    const double det = p.cx * q.cy - p.cy * q.cx;
    if (std::abs(det) < 1e-12) return 0;
    y = {(p.reach * q.cy - q.reach * p.cy) / det, (p.cx * q.reach - q.cx * p.reach) / det};
    return 1;
  }
  if (p.wall || q.wall) {
    const Limit& line = p.wall ? p : q;
    const Limit& circle = p.wall ? q : p;
    const double off = line.reach - (line.cx * circle.cx + line.cy * circle.cy);
    if (std::abs(off) > circle.reach) return 0;
    const double half = std::sqrt(circle.reach * circle.reach - off * off);
    const double fx = circle.cx + off * line.cx, fy = circle.cy + off * line.cy;
    y = {fx - half * line.cy, fy + half * line.cx, fx + half * line.cy, fy - half * line.cx};
    return 2;
  }
  const double dx = q.cx - p.cx, dy = q.cy - p.cy, d = std::hypot(dx, dy);
  if (d == 0.0 || d > p.reach + q.reach || d < std::abs(p.reach - q.reach)) return 0;
  const double along = (p.reach * p.reach - q.reach * q.reach + d * d) / (2.0 * d);
  const double half = std::sqrt(std::max(p.reach * p.reach - along * along, 0.0));
  const double fx = p.cx + along * dx / d, fy = p.cy + along * dy / d;
  y = {fx - half * dy / d, fy + half * dx / d, fx + half * dy / d, fy - half * dx / d};
  return 2;
}

}  // namespace

std::vector<int> clear_rattler_overlaps(Network& net, const std::vector<int>& disks,
                                        const Eigen::VectorXd& dq,
                                        const std::vector<ContactState>& states,
                                        std::vector<int>& jammed) {
  std::vector<int> moved;
  const DofMap& m = net.dofs;
  const std::array<double, 2> e = cell_extension(net, dq);
  Cell cell;  // the cell at dq
  cell.boundary = net.boundary;
  cell.length = {net.length[0] * (1.0 + e[0]), net.length[1] * (1.0 + e[1])};
  const auto at = [&](std::size_t p, int a) {
    const double start = a == 0 ? net.x[p] : net.y[p];
    const int dof = a == 0 ? m.ux[p] : m.uy[p];
    return (1.0 + e[a]) * start + (dof >= 0 ? dq[dof] : 0.0);
  };
  std::vector<int> once = disks;  // a disk made a rattler twice in a step is listed twice
  std::sort(once.begin(), once.end());
  once.erase(std::unique(once.begin(), once.end()), once.end());
  std::vector<Limit> limits;
  std::vector<char> listed(net.n_disks(), 0);
  for (const int d : once) {
    if (!m.is_rattler(d)) continue;
    int overlaps = 0;
    for (std::size_t c = 0; c < net.contacts.size(); ++c) {
      const int i = net.contacts.i[c], j = net.contacts.j[c];
      if ((i != d && j != d) || i == j || !(states[c].frame.h > 0.0)) continue;
      ++overlaps;
      if (!is_wall(j)) listed[i == d ? j : i] = 1;
    }
    if (overlaps < 2) continue;
    // Every body within reach of a move of up to `cap` (the contact list does not hold a
    // rattler's new neighbours): a listed overlap h must open to a gap of 0.01 h, an unlisted
    // one may not deepen, a gap may lose half of itself.
    const double r = net.radius[d], cap = 0.1 * r;
    const auto margin = [](double h, bool in_list) {
      return h > 0.0 ? (in_list ? 1.01 * h : 0.0) : 0.5 * h;
    };
    const double x = at(d, 0), y = at(d, 1);
    limits.clear();
    for (std::size_t p = 0; p < net.n_disks(); ++p) {
      if (static_cast<int>(p) == d) continue;
      double dx = at(p, 0) - x, dy = at(p, 1) - y;
      if (cell.periodic()) {
        dx += minimum_image_shift(dx, cell.length[0]) * cell.length[0];
        dy += minimum_image_shift(dy, cell.length[1]) * cell.length[1];
      }
      const double dist = std::hypot(dx, dy), h = r + net.radius[p] - dist;
      if (h < -2.0 * cap) continue;
      limits.push_back({false, dx, dy, dist + margin(h, listed[p])});
    }
    for (Wall w : {wall_left, wall_right, wall_bottom, wall_top}) {
      if (cell.periodic()) continue;
      const ContactFrame f = disk_wall_frame(x, y, r, w, cell);  // n points into the wall
      if (f.h >= -2.0 * cap) limits.push_back({true, -f.nx, -f.ny, margin(f.h, f.h > 0.0)});
    }
    for (std::size_t c = 0; c < net.contacts.size(); ++c) {
      const int i = net.contacts.i[c], j = net.contacts.j[c];
      if ((i == d || j == d) && !is_wall(j)) listed[i == d ? j : i] = 0;
    }
    // The nearest clear point lies on one limit's boundary (straight away from it) or where two
    // boundaries meet.
    double best = cap, best_x = 0.0, best_y = 0.0;
    bool found = false;
    const auto consider = [&](double yx, double yy) {
      const double move = std::hypot(yx, yy);
      if (move <= best && clears(limits, yx, yy)) {
        best = move;
        best_x = yx;
        best_y = yy;
        found = true;
      }
    };
    std::array<double, 4> point{};
    for (std::size_t a = 0; a < limits.size(); ++a) {
      const Limit& p = limits[a];
      if (p.wall) {
        consider(p.reach * p.cx, p.reach * p.cy);
      } else {
        const double d0 = std::hypot(p.cx, p.cy);
        consider(-(p.reach - d0) * p.cx / d0, -(p.reach - d0) * p.cy / d0);
      }
      for (std::size_t b = a + 1; b < limits.size(); ++b)
        for (int k = 0, n = meet(p, limits[b], point); k < n; ++k)
          consider(point[2 * k], point[2 * k + 1]);
    }
    if (!found) {
      jammed.push_back(d);
      continue;
    }
    net.x[d] += best_x / (1.0 + e[0]);
    net.y[d] += best_y / (1.0 + e[1]);
    moved.push_back(d);
  }
  return moved;
}

std::vector<int> lone_contacts(const Network& net, const std::vector<char>& closed) {
  const std::size_t n = net.n_disks();
  std::vector<int> count(n, 0), last(n, -1);
  for (std::size_t c = 0; c < closed.size(); ++c) {
    if (!closed[c]) continue;
    for (const int d : {net.contacts.i[c], net.contacts.j[c]}) {
      if (is_wall(d)) continue;
      ++count[d];
      last[d] = static_cast<int>(c);
    }
  }
  // The disk that holds the pinned translation of a periodic cell is left alone: without it the
  // rest would have no gauge (make_rattlers refuses it too). So is a disk under a dead load, which
  // one contact can balance.
  const DofMap& m = net.dofs;
  const std::vector<double>& dead = net.loading.dead;
  const auto loaded = [&dead](std::size_t i) {
    for (std::size_t k = 3 * i; k < 3 * i + 3 && k < dead.size(); ++k)
      if (dead[k] != 0.0) return true;
    return false;
  };
  for (std::size_t i = 0; i < n; ++i)
    if (count[i] != 1 || m.ux[i] < 0 || m.uy[i] < 0 || loaded(i)) last[i] = -1;
  return last;
}

namespace {

// A sticking frictional force-carrying contact between two distinct disks with rotations: it
// couples their rotations in a gear mode (a_i theta_i + a_j theta_j = 0).
bool gear_link(const Network& net, const ContactState& s, ContactStatus status, std::size_t c) {
  const DofMap& m = net.dofs;
  const int i = net.contacts.i[c], j = net.contacts.j[c];
  return status == ContactStatus::stick && s.frictional && s.f_n > 0.0 && !s.wall && i != j &&
         m.theta[i] >= 0 && m.theta[j] >= 0;
}

}  // namespace

std::vector<char> kept_dofs(const Network& net, const std::vector<ContactState>& states,
                            const std::vector<ContactStatus>& statuses) {
  const DofMap& m = net.dofs;
  std::vector<char> keep(m.size, 1);
  const std::size_t n = net.n_disks();
  // Rotation graph over sticking frictional force-carrying contacts; ratio[i] = theta_i of the
  // cluster's gear mode relative to its root. Adjacency in CSR (links of disk i in contact
  // order), built in two passes: a vector per disk cost an allocation per disk and call (perf).
  std::vector<char> blocked(n, 0);
  std::vector<int> link_start(n + 1, 0);
  const auto each_link = [&](auto&& link) {
    for (std::size_t c = 0; c < states.size(); ++c) {
      const ContactState& s = states[c];
      if (statuses[c] == ContactStatus::open || !s.frictional || s.f_n <= 0.0) continue;
      const int i = net.contacts.i[c], j = net.contacts.j[c];
      if (statuses[c] != ContactStatus::stick) continue;  // slip leaves theta free
      if (!gear_link(net, s, statuses[c], c)) {
        // A sticking wall contact or a self-image contact (2 a theta = 0) forbids the gear mode.
        if (s.wall || i == j || m.theta[j] < 0) {
          blocked[i] = 1;
          if (!s.wall) blocked[j] = 1;
        } else {
          blocked[j] = 1;  // m.theta[i] < 0
        }
        continue;
      }
      link(i, j, s);
    }
  };
  each_link([&](int i, int j, const ContactState&) {
    ++link_start[i + 1];
    ++link_start[j + 1];
  });
  for (std::size_t i = 0; i < n; ++i) link_start[i + 1] += link_start[i];
  std::vector<std::pair<int, double>> links(static_cast<std::size_t>(link_start[n]));
  std::vector<int> next(link_start.begin(), link_start.end() - 1);
  each_link([&](int i, int j, const ContactState& s) {  // partner, theta_j / theta_i
    links[next[i]++] = {j, -s.frame.a_i / s.frame.a_j};
    links[next[j]++] = {i, -s.frame.a_j / s.frame.a_i};
  });
  std::vector<double> ratio(n, 0.0);
  std::vector<char> seen(n, 0);
  std::vector<int> cluster, stack;
  for (std::size_t root = 0; root < n; ++root) {
    if (seen[root] || m.theta[root] < 0) continue;
    cluster.clear();
    bool free = true;
    seen[root] = 1;
    ratio[root] = 1.0;
    stack.assign(1, static_cast<int>(root));
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      cluster.push_back(i);
      free = free && !blocked[i];
      for (int l = link_start[i]; l < link_start[i + 1]; ++l) {
        const auto [j, r] = links[l];
        const double expected = ratio[i] * r;
        if (!seen[j]) {
          seen[j] = 1;
          ratio[j] = expected;
          stack.push_back(j);
        } else if (std::abs(ratio[j] - expected) > 1e-9 * std::abs(expected)) {
          free = false;  // an odd loop frustrates the gears
        }
      }
    }
    if (free) keep[m.theta[root]] = 0;
  }
  // A disk whose contacts are all open under these statuses (e.g. a two-contact disk whose forces
  // tend to 0 and open together) becomes a rattler inside the step: its rows and columns hold only
  // the geometric terms of its vanishing start forces, so K would be singular on it. Its dofs are
  // dropped; the predictor's check of the dropped rows (misfit ~ F_N |dq| / d) still rejects the
  // set if those forces are not small.
  std::vector<int> closed(n, 0);
  for (std::size_t c = 0; c < states.size(); ++c) {
    if (statuses[c] == ContactStatus::open) continue;
    ++closed[net.contacts.i[c]];
    if (!states[c].wall) ++closed[net.contacts.j[c]];
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (closed[i] > 0) continue;
    for (const int d : {m.ux[i], m.uy[i], m.theta[i]})
      if (d >= 0) keep[d] = 0;
  }
  return keep;
}

}  // namespace granstab::statics

namespace granstab::statics {

std::vector<int> sliding_contacts_of_gear_clusters(const Network& net,
                                                   const std::vector<ContactState>& states,
                                                   const std::vector<ContactStatus>& statuses,
                                                   const std::vector<int>& disks) {
  const std::size_t n = net.n_disks();
  std::vector<std::vector<std::size_t>> touching(n);  // contacts of each disk
  for (std::size_t c = 0; c < states.size(); ++c) {
    touching[net.contacts.i[c]].push_back(c);
    if (!states[c].wall && net.contacts.j[c] != net.contacts.i[c])
      touching[net.contacts.j[c]].push_back(c);
  }
  std::vector<char> in_cluster(n, 0), taken(states.size(), 0);
  std::vector<int> stack, sliding;
  for (const int root : disks) {
    if (root < 0 || static_cast<std::size_t>(root) >= n || in_cluster[root]) continue;
    in_cluster[root] = 1;
    stack.assign(1, root);
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      for (const std::size_t c : touching[i]) {
        const ContactState& s = states[c];
        if (gear_link(net, s, statuses[c], c)) {
          const int other = net.contacts.i[c] == i ? net.contacts.j[c] : net.contacts.i[c];
          if (!in_cluster[other]) {
            in_cluster[other] = 1;
            stack.push_back(other);
          }
        } else if (!taken[c] && s.frictional && s.f_n > 0.0 && slides(statuses[c])) {
          taken[c] = 1;
          sliding.push_back(static_cast<int>(c));
        }
      }
    }
  }
  std::sort(sliding.begin(), sliding.end());
  return sliding;
}

}  // namespace granstab::statics
