#include "static/closing_contacts.hpp"

#include <cmath>
#include <set>
#include <tuple>

#include "common/contact_law.hpp"
#include "static/kinematics.hpp"

namespace granstab::statics {

std::vector<NewContact> closing_contacts(const Network& net, const Eigen::VectorXd& dq) {
  const DofMap& m = net.dofs;
  const std::size_t n = net.n_disks();
  const std::array<double, 2> e = cell_extension(net, dq);
  const double l1 = net.length[0] * (1.0 + e[0]), l2 = net.length[1] * (1.0 + e[1]);
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = (1.0 + e[0]) * net.x[i] + (m.ux[i] >= 0 ? dq[m.ux[i]] : 0.0);
    y[i] = (1.0 + e[1]) * net.y[i] + (m.uy[i] >= 0 ? dq[m.uy[i]] : 0.0);
  }
  // Existing pairs, in both orientations of (i, j, k).
  std::set<std::tuple<int, int, int, int>> known;
  const Contacts& k = net.contacts;
  for (std::size_t c = 0; c < k.size(); ++c) {
    known.insert({k.i[c], k.j[c], k.k1[c], k.k2[c]});
    if (!is_wall(k.j[c])) known.insert({k.j[c], k.i[c], -k.k1[c], -k.k2[c]});
  }
  std::vector<NewContact> found;
  const bool periodic = net.boundary == Boundary::periodic;
  Cell cell;
  cell.boundary = net.boundary;
  cell.length = {l1, l2};
  for (std::size_t i = 0; i < n; ++i) {
    if (!m.active(i)) continue;
    if (!periodic) {
      for (Wall w : {wall_left, wall_right, wall_bottom, wall_top})
        if (!known.count({static_cast<int>(i), w, 0, 0}) &&
            disk_wall_frame(x[i], y[i], net.radius[i], w, cell).h > 0.0)
          found.push_back({static_cast<int>(i), w, 0, 0});
    }
    for (std::size_t j = i + 1; j < n; ++j) {
      if (!m.active(j)) continue;
      double dx = x[j] - x[i], dy = y[j] - y[i];
      int k1 = 0, k2 = 0;
      if (periodic) {
        k1 = minimum_image_shift(dx, l1);
        k2 = minimum_image_shift(dy, l2);
        dx += k1 * l1;
        dy += k2 * l2;
      }
      const double reach = net.radius[i] + net.radius[j];
      if (std::abs(dx) >= reach || std::abs(dy) >= reach) continue;
      if (dx * dx + dy * dy >= reach * reach) continue;
      const int a = static_cast<int>(i), b = static_cast<int>(j);
      if (!known.count({a, b, k1, k2})) found.push_back({a, b, k1, k2});
    }
  }
  return found;
}

}  // namespace granstab::statics
