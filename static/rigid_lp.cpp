// The normalised LP of the rigid-limit bound, assembled on its own: Ipopt only sees the result.
#include "static/rigid_lp.hpp"

#include <algorithm>
#include <tuple>
#include <vector>

namespace granstab::statics::rigid {

LinearProgram assemble(const Configuration& config, const FrozenNetwork& net) {
  const Contacts& c = config.contacts;
  const Cell& cell = config.cell;
  const std::size_t n = config.disks.size();
  LinearProgram lp;
  double max_radius = 0.0;
  for (const double r : config.disks.radius) max_radius = std::max(max_radius, r);
  lp.length_unit = max_radius > 0.0 ? 2.0 * max_radius : 1.0;
  const double a = lp.length_unit;
  lp.area = cell.area() / (a * a);

  // Provisional rows: 3 per disk (x, y, torque), then S1, S2.
  const int s_row = static_cast<int>(3 * n);
  std::vector<std::tuple<int, int, double>> entries;
  auto add = [&](int r, int col, double v) { entries.emplace_back(r, col, v); };
  for (std::size_t k = 0; k < c.size(); ++k) {
    if (!net.active[k]) continue;
    const ContactFrame& f = net.frame[k];
    const int i = c.i[k], j = c.j[k];
    const double mu = net.mu[k];
    const int n_cone_edges = mu > 0.0 ? 2 : 1;
    for (int edge = 0; edge < n_cone_edges; ++edge) {
      const int s = mu > 0.0 ? 1 - 2 * edge : 0;
      const int col = lp.n_edges++;
      lp.edge_contact.push_back(static_cast<int>(k));
      lp.edge_sign.push_back(static_cast<signed char>(s));
      const double tau = s * mu;  // tangential component of the edge
      const double ex = f.nx + tau * f.tx, ey = f.ny + tau * f.ty;
      // -f acts on i, +f on j; the torque of the contact is -a F_T on both (contact_law.hpp).
      if (!net.pinned[i]) {
        add(3 * i, col, -ex);
        add(3 * i + 1, col, -ey);
      }
      if (!net.torque_dropped[i]) add(3 * i + 2, col, -(f.a_i / a) * tau);
      if (!is_wall(j)) {
        if (!net.pinned[j]) {
          add(3 * j, col, ex);
          add(3 * j + 1, col, ey);
        }
        if (!net.torque_dropped[j]) add(3 * j + 2, col, -(f.a_j / a) * tau);
        if (cell.periodic()) {
          add(s_row, col, (f.lx / a) * ex);
          add(s_row + 1, col, (f.ly / a) * ey);
        }
      } else if (j == wall_right) {
        // Balance of the mobile wall, times L_1: sum f_x L_1 = L_1 L_2 sigma_1 = A sigma_1.
        add(s_row, col, (cell.length[0] / a) * ex);
      } else if (j == wall_top) {
        add(s_row + 1, col, (cell.length[1] / a) * ey);
      }
    }
  }
  add(s_row, lp.s1_column(), -lp.area);
  add(s_row + 1, lp.s1_column(), lp.area);

  // Merge duplicates (a disk touching its own image gets +f and -f: they cancel exactly), drop
  // zeros, and keep only rows with entries: an empty row reads 0 = 0 (e.g. the torque row of a
  // disk whose contacts are all frictionless).
  std::sort(entries.begin(), entries.end(), [](const auto& p, const auto& q) {
    return std::tie(std::get<0>(p), std::get<1>(p)) < std::tie(std::get<0>(q), std::get<1>(q));
  });
  std::vector<int> new_row(3 * n + 2, -1);
  for (std::size_t e = 0; e < entries.size();) {
    const auto [r, col, v0] = entries[e];
    double v = v0;
    std::size_t next = e + 1;
    for (; next < entries.size() && std::get<0>(entries[next]) == r &&
           std::get<1>(entries[next]) == col;
         ++next)
      v += std::get<2>(entries[next]);
    e = next;
    if (v == 0.0) continue;
    if (new_row[r] < 0) {
      new_row[r] = lp.n_rows();
      const bool stress = r >= s_row;
      lp.rhs.push_back(r == s_row + 1 ? 2.0 * lp.area : 0.0);
      lp.row_kind.push_back(stress ? RowKind::stress : static_cast<RowKind>(r % 3));
      lp.row_index.push_back(stress ? r - s_row : r / 3);
    }
    lp.row.push_back(new_row[r]);
    lp.col.push_back(col);
    lp.val.push_back(v);
  }
  return lp;
}

}  // namespace granstab::statics::rigid
