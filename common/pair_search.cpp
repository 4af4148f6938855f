#include "pair_search.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace granstab {
namespace {

// Neighbouring cell indices of cell c along one axis, without repeats (a periodic axis with
// fewer than 3 cells would otherwise visit a cell twice and list a pair twice).
int neighbour_cells(int c, int nb, bool periodic, int out[3]) {
  if (nb <= 3) {
    for (int k = 0; k < nb; ++k) out[k] = k;
    return nb;
  }
  int count = 0;
  for (int d = -1; d <= 1; ++d) {
    int k = c + d;
    if (periodic) {
      k = (k + nb) % nb;
    } else if (k < 0 || k >= nb) {
      continue;
    }
    out[count++] = k;
  }
  return count;
}

int cell_index(double x, double length, int nb) {
  const int k = static_cast<int>(std::floor(x / length * nb));
  return std::clamp(k, 0, nb - 1);
}

}  // namespace

void PairSearch::find(const double* x, const double* y, const double* radius, std::size_t n,
                      const Cell& cell, double margin, PairList& out) {
  sort(x, y, radius, n, cell, margin);
  rows(0, n, out, scratch_);
}

void PairSearch::sort(const double* x, const double* y, const double* radius, std::size_t n,
                      const Cell& cell, double margin) {
  x_ = x;
  y_ = y;
  radius_ = radius;
  cell_ = cell;
  margin_ = margin;
  disk_cell_.resize(n);
  if (n < 2) return;
  const bool periodic = cell.periodic();
  double r_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) r_max = std::max(r_max, radius[i]);
  const double reach = 2.0 * r_max + margin;
  for (int a = 0; a < 2; ++a) {
    const double length = cell.length[a];
    if (periodic && length <= 2.0 * reach) {
      throw std::invalid_argument(
          "pair search: periodic cell length L" + std::to_string(a + 1) + " = " +
          std::to_string(length) +
          " must exceed twice the search reach 2 R_max + margin = " + std::to_string(reach));
    }
    nb_[a] = std::max(1, static_cast<int>(std::floor(length / reach)));
  }
  const std::size_t n_cells = static_cast<std::size_t>(nb_[0]) * nb_[1];

  // Counting sort of the disks into cells (cells in row-major order, disks ascending inside).
  cell_start_.assign(n_cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int c = cell_index(y[i], cell.length[1], nb_[1]) * nb_[0] +
                  cell_index(x[i], cell.length[0], nb_[0]);
    disk_cell_[i] = c;
    ++cell_start_[c + 1];
  }
  for (std::size_t c = 0; c < n_cells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_disks_.resize(n);
  cell_fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i)
    cell_disks_[cell_fill_[disk_cell_[i]]++] = static_cast<int>(i);
}

void PairSearch::rows(std::size_t first, std::size_t end, PairList& out, Scratch& scratch) const {
  out.clear();
  if (disk_cell_.size() < 2) return;
  const bool periodic = cell_.periodic();
  const double* const x = x_;
  const double* const y = y_;
  const double* const radius = radius_;
  auto& partners = scratch.partners;
  const double l1 = cell_.length[0], l2 = cell_.length[1];
  for (std::size_t i = first; i < end; ++i) {
    partners.clear();
    const int cx = disk_cell_[i] % nb_[0], cy = disk_cell_[i] / nb_[0];
    int nx[3], ny[3];
    const int mx = neighbour_cells(cx, nb_[0], periodic, nx);
    const int my = neighbour_cells(cy, nb_[1], periodic, ny);
    for (int b = 0; b < my; ++b) {
      for (int a = 0; a < mx; ++a) {
        const int c = ny[b] * nb_[0] + nx[a];
        for (int s = cell_start_[c]; s < cell_start_[c + 1]; ++s) {
          const int j = cell_disks_[s];
          if (j <= static_cast<int>(i)) continue;
          double dx = x[j] - x[i], dy = y[j] - y[i];
          int k1 = 0, k2 = 0;
          if (periodic) {
            k1 = minimum_image_shift(dx, l1);
            k2 = minimum_image_shift(dy, l2);
            dx += k1 * l1;
            dy += k2 * l2;
          }
          const double reach_ij = radius[i] + radius[j] + margin_;
          if (dx * dx + dy * dy < reach_ij * reach_ij) partners.push_back({j, k1, k2});
        }
      }
    }
    std::sort(partners.begin(), partners.end(),
              [](const auto& p, const auto& q) { return p[0] < q[0]; });
    for (const auto& p : partners) {
      out.i.push_back(static_cast<int>(i));
      out.j.push_back(p[0]);
      out.k1.push_back(p[1]);
      out.k2.push_back(p[2]);
    }
  }
}

PairList find_pairs(const std::vector<double>& x, const std::vector<double>& y,
                    const std::vector<double>& radius, const Cell& cell, double margin) {
  if (y.size() != x.size() || radius.size() != x.size()) {
    throw std::invalid_argument("find_pairs: x, y and radius must have the same size");
  }
  PairSearch search;
  PairList out;
  search.find(x.data(), y.data(), radius.data(), x.size(), cell, margin, out);
  return out;
}

}  // namespace granstab
