#include "neighbour_list.hpp"

#include <algorithm>
#include <cmath>

namespace granstab::dynamic {

// A pair left out of the list had |l| >= R_i + R_j + skin at the build. Since then l has been
// stretched by at most the factor lambda_min = min_a L_a / L_a(build) (affine part) and each
// disk moved by at most D (non-affine part, measured in reduced coordinates times the current
// lengths), so |l| >= lambda_min (R_i + R_j + skin) - 2 D, which stays above R_i + R_j as long
// as 2 D + (1 - lambda_min) 2 R_max < lambda_min skin.
bool NeighbourList::RebuildTest::operator()(const CellState& cell, double max_displacement2) const {
  if (!built) return true;
  double lambda_min = 1.0;
  if (cell.periodic()) {
    for (int a = 0; a < 2; ++a) {
      lambda_min = std::min(lambda_min, cell.length[a] / reference_length[a]);
    }
  }
  const double d = std::sqrt(max_displacement2);
  return 2.0 * d + (1.0 - lambda_min) * 2.0 * r_max >= lambda_min * skin;
}

bool NeighbourList::update(DiskArrays& disks, const CellState& cell, PairArrays& pairs,
                           const Material& material) {
  if (!rebuild_test()(cell, max_displacement2_)) return false;
  rebuild(disks, cell, pairs, material);
  return true;
}

void NeighbourList::rebuild(DiskArrays& disks, const CellState& cell, PairArrays& pairs,
                            const Material& material) {
  const std::size_t n = disks.size();
  r_max_ = 0.0;
  for (std::size_t i = 0; i < n; ++i) r_max_ = std::max(r_max_, disks.radius[i]);
  search_.find(disks.x.data(), disks.y.data(), disks.radius.data(), n, cell.cell(), skin_, found_);

  // Keep the old list to carry delta_t of pairs present in both (both sorted by (i, j)).
  old_i_.swap(pairs.i);
  old_j_.swap(pairs.j);
  old_row_start_.swap(pairs.row_start);
  old_delta_t_.swap(pairs.delta_t);
  old_f_n_.swap(pairs.f_n);
  old_viscous_x_.swap(pairs.viscous_x);
  old_viscous_y_.swap(pairs.viscous_y);
  const bool had_list = built_ && old_row_start_.size() == n + 1;

  const std::size_t m = found_.size();
  pairs.i.assign(found_.i.begin(), found_.i.end());
  pairs.j.assign(found_.j.begin(), found_.j.end());
  pairs.row_start.assign(n + 1, 0);
  for (std::size_t p = 0; p < m; ++p) ++pairs.row_start[pairs.i[p] + 1];
  for (std::size_t i = 0; i < n; ++i) pairs.row_start[i + 1] += pairs.row_start[i];

  pairs.delta_t.assign(m, 0.0);
  pairs.f_n.assign(m, 0.0);
  pairs.viscous_x.assign(m, 0.0);
  pairs.viscous_y.assign(m, 0.0);
  pairs.team = 0;  // the crossing pairs and their mirrors depend on the list
  if (had_list) {
    for (std::size_t i = 0; i < n; ++i) {
      int q = old_row_start_[i];
      const int q_end = old_row_start_[i + 1];
      for (int p = pairs.row_start[i]; p < pairs.row_start[i + 1] && q < q_end; ++p) {
        while (q < q_end && old_j_[q] < pairs.j[p]) ++q;
        if (q < q_end && old_j_[q] == pairs.j[p]) {
          // The contact state of the synchronous state: tangential displacement, and whether
          // (and how hard) it was closed, which the next force pass needs.
          pairs.delta_t[p] = old_delta_t_[q];
          pairs.f_n[p] = old_f_n_[q];
          pairs.viscous_x[p] = old_viscous_x_[q];
          pairs.viscous_y[p] = old_viscous_y_[q];
        }
      }
    }
  }

  pairs.alpha.resize(m);
  for (std::size_t p = 0; p < m; ++p) {
    pairs.alpha[p] = material.damping_coefficient(disks.mass[pairs.i[p]], disks.mass[pairs.j[p]]);
  }
  pairs.active.resize(m);
  for (auto* v : {&pairs.nx, &pairs.ny, &pairs.lx, &pairs.ly}) {
    v->assign(m, 0.0);
  }

  ref_sx_.resize(n);
  ref_sy_.resize(n);
  const double sx = cell.periodic() ? 1.0 / cell.length[0] : 1.0;
  const double sy = cell.periodic() ? 1.0 / cell.length[1] : 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    ref_sx_[i] = disks.x[i] * sx;
    ref_sy_[i] = disks.y[i] * sy;
  }
  ref_length_ = cell.length;
  // Both lists' arrays (the next rebuild swaps them) and the search's, with room to grow.
  for (auto* v : {&pairs.i, &pairs.j, &pairs.active, &old_i_, &old_j_}) keep_room(*v, m);
  for (auto* v : {&pairs.alpha, &pairs.delta_t, &pairs.viscous_x, &pairs.viscous_y, &pairs.nx,
                  &pairs.ny, &pairs.lx, &pairs.ly, &pairs.f_n, &old_delta_t_, &old_f_n_,
                  &old_viscous_x_, &old_viscous_y_}) {
    keep_room(*v, m);
  }
  for (auto* v : {&found_.i, &found_.j, &found_.k1, &found_.k2}) keep_room(*v, m);
  keep_room(old_row_start_, n + 1);
  max_displacement2_ = 0.0;
  built_ = true;
  ++rebuilds_;
}

}  // namespace granstab::dynamic
