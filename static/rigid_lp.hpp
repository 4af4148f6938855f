#pragma once
// The normalised LP of the rigid-limit bound, assembled on its own: Ipopt only sees the result.
#include <cstdint>
#include <vector>

#include "common/configuration.hpp"
#include "static/rigid_network.hpp"

namespace granstab::statics::rigid {

// The normalised LP (docs/static.md): columns x >= 0 are the edges of the friction cones,
// f = x (n + s mu t) with s = +-1 (one edge, s = 0, for frictionless contacts), plus the free
// column s1. Rows: force and torque balance of each active disk, and
//   S1: sum c1 x - A s1 = 0,   S2: sum c2 x + A s1 = 2 A   (sigma_1 + sigma_2 = 2, units of P).
// Lengths are in units of a (largest diameter), forces in units of a P.

enum class RowKind : std::uint8_t { force_x, force_y, torque, stress };

struct LinearProgram {
  int n_edges = 0;
  std::vector<int> edge_contact;
  std::vector<signed char> edge_sign;
  // Constraint matrix, COO sorted by (row, column), merged, without zeros.
  std::vector<int> row, col;
  std::vector<double> val;
  std::vector<double> rhs;
  std::vector<RowKind> row_kind;
  std::vector<int> row_index;  // disk of a balance row; direction (0, 1) of a stress row
  double length_unit = 1.0;    // a: the largest diameter
  double area = 1.0;           // A / a^2
  int n_columns() const { return n_edges + 1; }
  int s1_column() const { return n_edges; }
  int n_rows() const { return static_cast<int>(rhs.size()); }
};

// The LP of net's active contacts: entries merged, zeros and empty rows dropped.
LinearProgram assemble(const Configuration& config, const FrozenNetwork& net);

}  // namespace granstab::statics::rigid
