#pragma once
// Cell-list pair search (periodic-image aware): every pair of disks whose gap
// |l| - R_i - R_j is below a margin. The MD engine builds its Verlet lists with it; the static
// solver and the measurements use it to find contacts about to close (gap < margin).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cell.hpp"

namespace granstab {

// A pair (i < j) with the image of j that realises the gap: l = r_j + (k1 L1, k2 L2) - r_i.
// Periodic cells must be larger than twice the search reach 2 R_max + margin in each direction,
// so that at most one image of j is within reach of i (checked: std::invalid_argument).
struct PairList {
  std::vector<std::int32_t> i, j, k1, k2;
  std::size_t size() const { return i.size(); }
  void clear() {
    i.clear();
    j.clear();
    k1.clear();
    k2.clear();
  }
};

class PairSearch {
 public:
  // Pairs sorted by (i, j). Reuses its buffers: no allocation once they are large enough.
  void find(const double* x, const double* y, const double* radius, std::size_t n, const Cell& cell,
            double margin, PairList& out);

  // find() in two halves, so that threads can search the rows of disjoint ranges of i at once:
  // sort() the disks into cells (one thread), then rows(first, end) lists the pairs of
  // i in [first, end), sorted by (i, j), into `out` (cleared first). Concatenated in the order of
  // i, the rows of a partition of [0, n) are find()'s list. Each thread passes its own out and
  // scratch; rows() only reads the search.
  struct Scratch {
    std::vector<std::array<std::int32_t, 3>> partners;  // (j, k1, k2) of one disk
  };
  void sort(const double* x, const double* y, const double* radius, std::size_t n, const Cell& cell,
            double margin);
  void rows(std::size_t first, std::size_t end, PairList& out, Scratch& scratch) const;

 private:
  const double *x_ = nullptr, *y_ = nullptr, *radius_ = nullptr;
  Cell cell_;
  double margin_ = 0.0;
  int nb_[2] = {1, 1};
  std::vector<std::int32_t> cell_start_, cell_fill_, cell_disks_, disk_cell_;
  Scratch scratch_;
};

// Convenience for non-hot callers.
PairList find_pairs(const std::vector<double>& x, const std::vector<double>& y,
                    const std::vector<double>& radius, const Cell& cell, double margin);

}  // namespace granstab
