#pragma once
// The container of SPEC §1.3: either a periodic rectangle L1 x L2 with fixed axes, or four walls.
// Both share one state: the rectangle [0, L1] x [0, L2], whose lengths are dynamical variables.
// With walls, the walls at x = 0 and y = 0 are fixed and the walls at x = L1 (right) and
// y = L2 (top) are the mobile bodies: their positions are L1, L2 and their velocities the rates.
#include <array>
#include <cmath>
#include <cstdint>

namespace granstab {

enum class Boundary : std::uint8_t { periodic, walls };

// A contact partner index j < 0 names a wall.
enum Wall : int { wall_left = -1, wall_right = -2, wall_bottom = -3, wall_top = -4 };
inline bool is_wall(int j) { return j < 0; }

struct Cell {
  Boundary boundary = Boundary::periodic;
  std::array<double, 2> length{1.0, 1.0};       // L1, L2
  std::array<double, 2> length_rate{0.0, 0.0};  // dL1/dt, dL2/dt
  // Inertia of each length's equation of motion (periodic: the cell "mass"; walls: the wall
  // mass). Results must not depend on it in the quasistatic limit (SPEC §1.3).
  std::array<double, 2> mass{1.0, 1.0};

  double area() const { return length[0] * length[1]; }
  bool periodic() const { return boundary == Boundary::periodic; }
  // Affine strain rate of direction a (periodic cells): (dL_a/dt) / L_a.
  double strain_rate(int a) const { return length_rate[a] / length[a]; }
};

// Image shift k_a that brings dx (a separation along axis a) to the minimum image.
inline int minimum_image_shift(double dx, double length) {
  return -static_cast<int>(std::nearbyint(dx / length));
}

// Throws std::invalid_argument naming the offending field (cell.length, ...).
void validate(const Cell& cell);

}  // namespace granstab
