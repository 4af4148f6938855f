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
  const int n = static_cast<int>(disks.size());
  begin_rebuild(disks, cell, pairs, 1);
  find_rows(0, 0, n);
  size_list(pairs, disks.size());
  fill_rows(disks, cell, pairs, material, 0, 0, n);
  end_rebuild(cell, pairs);
}

void NeighbourList::begin_rebuild(const DiskArrays& disks, const CellState& cell, PairArrays& pairs,
                                  int parts) {
  const std::size_t n = disks.size();
  r_max_ = 0.0;
  for (std::size_t i = 0; i < n; ++i) r_max_ = std::max(r_max_, disks.radius[i]);
  search_.sort(disks.x.data(), disks.y.data(), disks.radius.data(), n, cell.cell(), skin_);
  parts_.resize(parts);
  found_start_.resize(parts + 1);
  // Keep the old list to carry delta_t of pairs present in both (both sorted by (i, j)).
  old_i_.swap(pairs.i);
  old_j_.swap(pairs.j);
  old_row_start_.swap(pairs.row_start);
  old_delta_t_.swap(pairs.delta_t);
  old_f_n_.swap(pairs.f_n);
  old_viscous_x_.swap(pairs.viscous_x);
  old_viscous_y_.swap(pairs.viscous_y);
  had_list_ = built_ && old_row_start_.size() == n + 1;
  ref_sx_.resize(n);
  ref_sy_.resize(n);
}

void NeighbourList::find_rows(int part, int first, int end) {
  search_.rows(first, end, parts_[part].found, parts_[part].scratch);
}

void NeighbourList::size_list(PairArrays& pairs, std::size_t n) {
  found_start_[0] = 0;
  for (std::size_t k = 0; k < parts_.size(); ++k)
    found_start_[k + 1] = found_start_[k] + parts_[k].found.size();
  const std::size_t m = found_start_.back();
  resize_in_room(m, pairs.i, pairs.j, pairs.active, pairs.alpha, pairs.delta_t, pairs.viscous_x,
                 pairs.viscous_y, pairs.nx, pairs.ny, pairs.lx, pairs.ly, pairs.f_n);
  pairs.row_start.resize(n + 1);
  pairs.row_start[0] = 0;
  pairs.team = 0;  // the crossing pairs and their mirrors depend on the list
}

void NeighbourList::fill_rows(const DiskArrays& disks, const CellState& cell, PairArrays& pairs,
                              const Material& material, int part, int first, int end) {
  const PairList& found = parts_[part].found;
  const int offset = static_cast<int>(found_start_[part]);
  const int count = static_cast<int>(found.size());
  std::copy(found.i.begin(), found.i.end(), pairs.i.begin() + offset);
  std::copy(found.j.begin(), found.j.end(), pairs.j.begin() + offset);
  for (int p = 0, i = first; i < end; ++i) {
    while (p < count && found.i[p] == i) ++p;
    pairs.row_start[i + 1] = offset + p;
  }
  const int pair_end = offset + count;
  for (auto* v : {&pairs.delta_t, &pairs.f_n, &pairs.viscous_x, &pairs.viscous_y, &pairs.nx,
                  &pairs.ny, &pairs.lx, &pairs.ly}) {
    std::fill(v->begin() + offset, v->begin() + pair_end, 0.0);
  }
  if (had_list_) {
    // Row i starts where row i - 1 ends: row_start[first] is the part before's to write.
    for (int i = first, row = offset; i < end; row = pairs.row_start[++i]) {
      int q = old_row_start_[i];
      const int q_end = old_row_start_[i + 1];
      for (int p = row; p < pairs.row_start[i + 1] && q < q_end; ++p) {
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
  for (int p = offset; p < pair_end; ++p) {
    pairs.alpha[p] = material.damping_coefficient(disks.mass[pairs.i[p]], disks.mass[pairs.j[p]]);
  }
  const double sx = cell.periodic() ? 1.0 / cell.length[0] : 1.0;
  const double sy = cell.periodic() ? 1.0 / cell.length[1] : 1.0;
  for (int i = first; i < end; ++i) {
    ref_sx_[i] = disks.x[i] * sx;
    ref_sy_[i] = disks.y[i] * sy;
  }
}

void NeighbourList::end_rebuild(const CellState& cell, PairArrays& pairs) {
  const std::size_t m = pairs.size();
  ref_length_ = cell.length;
  // The old list's arrays, which the next rebuild swaps in, and the parts' rows, with room to
  // grow (the new list's got theirs in size_list).
  for (auto* v : {&old_i_, &old_j_}) keep_room(*v, m);
  for (auto* v : {&old_delta_t_, &old_f_n_, &old_viscous_x_, &old_viscous_y_}) keep_room(*v, m);
  keep_room(old_row_start_, pairs.row_start.size());
  for (PartRows& part : parts_) {
    PairList& f = part.found;
    for (auto* v : {&f.i, &f.j, &f.k1, &f.k2}) keep_room(*v, f.size());
  }
  max_displacement2_ = 0.0;
  built_ = true;
  ++rebuilds_;
}

}  // namespace granstab::dynamic
