#pragma once
// The engine's working arrays (structure of arrays). The pieces of the time step (neighbour
// list, contact forces, cell control, integrator) are free functions over these.
#include <array>
#include <cstdint>
#include <vector>

#include "common/configuration.hpp"

namespace granstab::dynamic {

// Forces and torques cached per disk belong to the current synchronous state (time t): they are
// a function of positions, velocities, delta_t and the cell only, so a state exported to a
// Configuration and read back continues to the bit.
struct DiskArrays {
  std::vector<double> x, y, vx, vy, omega, theta;
  std::vector<double> radius, mass, inertia, inv_mass, inv_inertia;
  std::vector<double> alpha_wall;  // damping coefficient against an infinitely heavy wall
  // Velocities predicted at the end of the step, used only by the viscous force (which depends
  // on the velocity it is meant to change).
  std::vector<double> vpx, vpy;
  std::vector<double> fx, fy, torque;  // elastic + frictional contact forces + external forces
  std::vector<double> fvx, fvy;        // viscous contact forces (normal, so no torque)
  std::vector<double> ext_fx, ext_fy;  // external forces; empty when none is applied
  // Contact state against each wall: tangential displacement, viscous force of the synchronous
  // state, and whether the contact was closed (the next step needs to know if it opens).
  std::array<std::vector<double>, 4> wall_delta_t, wall_f_v;
  std::array<std::vector<std::uint8_t>, 4> wall_closed;
  std::size_t size() const { return x.size(); }
};

// Pairs of the Verlet list, i < j, sorted by (i, j): CSR rows by i, plus the transposed
// incidence (for each disk, the pairs where it is j, ascending i). Every disk sums its pair
// forces in ascending partner order whatever the list holds (see docs/dynamic.md,
// "Determinism"): the force pass adds each pair's force to both disks as it goes (rows in
// ascending i do exactly that order), except for the "gathered" disks (below).
struct PairArrays {
  std::vector<std::int32_t> i, j;
  std::vector<std::int32_t> row_start;                  // N + 1
  std::vector<std::int32_t> column_start, column_pair;  // N + 1, size()
  std::vector<double> alpha, delta_t;
  // Viscous force of i on j of the synchronous state (zero for open pairs): a pair that opens
  // during the next step keeps a share of it for the closing half kick.
  std::vector<double> viscous_x, viscous_y;
  // Per-pair outputs of a pass, written only for pairs with a gathered disk (`slotted`), whose
  // sums are taken after the team's barrier through the incidence, in the same order.
  struct Force {
    double fx, fy;    // elastic + frictional force of i on j
    double fvx, fvy;  // viscous force of i on j
    double torque_i, torque_j;
  };
  std::vector<Force> force;
  // Frame and elastic normal force of the last force pass (F_T of a state is -K_T delta_t).
  std::vector<double> nx, ny, lx, ly, f_n;
  // Per reduction block: its closed pairs from the start of its pair range in `active`, the
  // pairs that opened during the step from the end (written by the force pass).
  std::vector<std::int32_t> active, block_closed, block_opened;
  // Split of the blocks between `team` parts (part k: the blocks from part_block[k] on, each run
  // by one thread). A disk is gathered when it has a partner in an earlier part: it
  // would receive forces from two threads. With walls whole blocks are gathered (whole_blocks),
  // so that a block's disk sums keep their order. team = 0: not planned for this list yet (see
  // contact_forces.cpp).
  int team = 0;
  // The parts' first blocks and the block count (team + 1 entries): part k holds the blocks
  // [part_block[k], part_block[k + 1]). Even by default; the engine moves the boundaries to
  // balance its threads' work (EngineOptions::balance_steps). The sums do not depend on them.
  std::vector<std::int32_t> part_block;
  bool any_gathered = false, whole_blocks = false;
  std::vector<std::uint8_t> gathered;        // per disk
  std::vector<std::uint8_t> block_gathered;  // per block: whether one of its disks is gathered
  std::vector<std::uint8_t> slotted;         // per pair: i or j gathered
  // Per block: whether one of its rows has a slotted pair. Only such blocks sweep their rows
  // with the checks for slots and gathered partners; the others (all but a few at the part
  // boundaries) take the plain sweep, which does the same additions.
  std::vector<std::uint8_t> block_slotted;
  std::size_t size() const { return i.size(); }
};

struct CellState {
  Boundary boundary = Boundary::periodic;
  std::array<double, 2> length{1.0, 1.0};
  std::array<double, 2> length_rate{0.0, 0.0};
  std::array<double, 2> length_acceleration{0.0, 0.0};  // from the state at t
  std::array<double, 2> rate_predicted{0.0, 0.0};       // end-of-step prediction (viscous)
  std::array<double, 2> mass{1.0, 1.0};
  bool periodic() const { return boundary == Boundary::periodic; }
  Cell cell() const {
    Cell c;
    c.boundary = boundary;
    c.length = length;
    c.length_rate = length_rate;
    c.mass = mass;
    return c;
  }
};

// Sums over the contacts of a fixed block of disks; blocks are added in index order, so every
// reduction is independent of the thread count.
struct BlockSums {
  std::array<double, 4> sigma{};          // sum f_a l_b (a, b) -> 2 a + b, elastic + frictional
  std::array<double, 2> sigma_viscous{};  // diagonal of the same for the viscous forces
  std::array<double, 2> wall_force{};     // elastic + frictional force of the disks on the
                                          // right (x) and top (y) walls
  std::array<double, 2> wall_force_viscous{};
  void clear() { *this = BlockSums{}; }
};

inline constexpr int block_size = 64;  // disks per reduction block (fixed, thread-independent)

}  // namespace granstab::dynamic
