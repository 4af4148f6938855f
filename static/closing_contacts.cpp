#include "static/closing_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "common/contact_law.hpp"
#include "common/pair_search.hpp"
#include "static/kinematics.hpp"

namespace granstab::statics {

std::vector<NewContact> closing_contacts(const Network& net, const Eigen::VectorXd& dq,
                                         bool with_rattlers) {
  const DofMap& m = net.dofs;
  const std::size_t n = net.n_disks();
  const std::array<double, 2> e = cell_extension(net, dq);
  const double l1 = net.length[0] * (1.0 + e[0]), l2 = net.length[1] * (1.0 + e[1]);
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = (1.0 + e[0]) * net.x[i] + (m.ux[i] >= 0 ? dq[m.ux[i]] : 0.0);
    y[i] = (1.0 + e[1]) * net.y[i] + (m.uy[i] >= 0 ? dq[m.uy[i]] : 0.0);
  }
  // Existing pairs, in both orientations of (i, j, k): sorted, looked up by bisection.
  using Pair = std::tuple<int, int, int, int>;
  std::vector<Pair> pairs_known;
  const Contacts& k = net.contacts;
  pairs_known.reserve(2 * k.size());
  for (std::size_t c = 0; c < k.size(); ++c) {
    pairs_known.emplace_back(k.i[c], k.j[c], k.k1[c], k.k2[c]);
    if (!is_wall(k.j[c])) pairs_known.emplace_back(k.j[c], k.i[c], -k.k1[c], -k.k2[c]);
  }
  std::sort(pairs_known.begin(), pairs_known.end());
  const auto known = [&pairs_known](const Pair& p) {
    return std::binary_search(pairs_known.begin(), pairs_known.end(), p);
  };
  std::vector<NewContact> found;
  const bool periodic = net.boundary == Boundary::periodic;
  Cell cell;
  cell.boundary = net.boundary;
  cell.length = {l1, l2};
  for (std::size_t i = 0; i < n; ++i) {
    if (!m.active(i) || periodic) continue;
    // The overlap first: most disks touch no wall, and the lookup costs more (perf).
    for (Wall w : {wall_left, wall_right, wall_bottom, wall_top})
      if (disk_wall_frame(x[i], y[i], net.radius[i], w, cell).h > 0.0 &&
          !known({static_cast<int>(i), w, 0, 0}))
        found.push_back({static_cast<int>(i), w, 0, 0});
  }
  const auto consider = [&](int a, int b, int k1, int k2) {
    // With with_rattlers, a rattler (no dofs: it moves affinely) that an active disk closes on
    // is found too; the load step then gives it dofs (activate_disks). Two rattlers never push
    // each other.
    if (with_rattlers ? !m.active(a) && !m.active(b) : !m.active(a) || !m.active(b)) return;
    const double dx = x[b] + k1 * l1 - x[a], dy = y[b] + k2 * l2 - y[a];
    const double reach = net.radius[a] + net.radius[b];
    if (dx * dx + dy * dy < reach * reach && !known({a, b, k1, k2}))
      found.push_back({a, b, k1, k2});
  };
  double r_max = 0.0;
  for (double r : net.radius) r_max = std::max(r_max, r);
  if (periodic && std::min(l1, l2) <= 4.0 * r_max * (1.0 + 1e-9)) {
    // Cells too small for the cell list (lattice tests): every pair at its minimum image.
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j)
        consider(static_cast<int>(i), static_cast<int>(j), minimum_image_shift(x[j] - x[i], l1),
                 minimum_image_shift(y[j] - y[i], l2));
    return found;
  }
  // The common cell-list search on wrapped positions; image shifts are converted back to the
  // network's unwrapped coordinates: l = x_j - w_j L + k L - (x_i - w_i L).
  std::vector<double> xw(x), yw(y);
  std::vector<int> w1(n, 0), w2(n, 0);
  if (periodic) {
    for (std::size_t i = 0; i < n; ++i) {
      w1[i] = static_cast<int>(std::floor(x[i] / l1));
      w2[i] = static_cast<int>(std::floor(y[i] / l2));
      xw[i] = x[i] - w1[i] * l1;
      yw[i] = y[i] - w2[i] * l2;
    }
  }
  PairList pairs;
  PairSearch search;
  search.find(xw.data(), yw.data(), net.radius.data(), n, cell, 0.0, pairs);
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const int a = pairs.i[p], b = pairs.j[p];
    consider(a, b, pairs.k1[p] - w1[b] + w1[a], pairs.k2[p] - w2[b] + w2[a]);
  }
  return found;
}

}  // namespace granstab::statics
