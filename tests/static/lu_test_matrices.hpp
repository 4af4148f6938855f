#pragma once
// Random sparse test matrices for the LuFactor tests (symbolic reuse, low-rank updates).
#include <vector>

#include "static/tangent.hpp"

namespace granstab::statics::testing {

// A random unsymmetric matrix on the pattern of a 2D 5-point grid (side x side unknowns),
// diagonally weighted by `diagonal` (negative values make det < 0 for suitable seeds); extra adds
// one coupling (0, n - 1) outside the grid pattern.
inline SparseMatrix grid_matrix(int side, unsigned seed, double diagonal, bool extra = false) {
  const int n = side * side;
  std::vector<Eigen::Triplet<double>> t;
  unsigned state = seed;
  const auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) / double(1u << 24) - 0.5;
  };
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const int i = y * side + x;
      t.emplace_back(i, i, diagonal + next());
      if (x + 1 < side) {
        t.emplace_back(i, i + 1, next());
        t.emplace_back(i + 1, i, next());
      }
      if (y + 1 < side) {
        t.emplace_back(i, i + side, next());
        t.emplace_back(i + side, i, next());
      }
    }
  if (extra) t.emplace_back(0, n - 1, 0.25);
  SparseMatrix k(n, n);
  k.setFromTriplets(t.begin(), t.end());
  k.makeCompressed();
  return k;
}

}  // namespace granstab::statics::testing
