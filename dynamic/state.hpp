#pragma once
// The engine's working arrays (structure of arrays). The pieces of the time step (neighbour
// list, contact forces, cell control, integrator) are free functions over these.
#include <array>
#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

#include "common/configuration.hpp"

namespace granstab::dynamic {

// Allocates whole cache lines: each array starts on a line of its own and no other allocation
// shares its last line. On a team, one thread writes the first disks of an array while another
// writes the last ones of the array before it; with malloc's packing such ends shared a line,
// which went back and forth between the cores in every pass (two threads 4-5 % slower at
// N = 1400 and 5600; aligned SIMD loads also make one thread ~2 % faster).
template <class T>
struct LineAllocator {
  using value_type = T;
  static constexpr std::size_t line = 64;
  LineAllocator() = default;
  template <class U>
  LineAllocator(const LineAllocator<U>&) {}
  T* allocate(std::size_t n) {
    const std::size_t bytes = (n * sizeof(T) + line - 1) / line * line;
    return static_cast<T*>(::operator new (bytes, std::align_val_t{line}));
  }
  void deallocate(T* p, std::size_t) { ::operator delete (p, std::align_val_t{line}); }
  template <class U>
  bool operator==(const LineAllocator<U>&) const {
    return true;
  }
};
template <class T>
using LineVector = std::vector<T, LineAllocator<T>>;

// Room for `size` elements and a quarter more, the pages written once here, where the array
// would otherwise grow: a list rebuild or a team's plan inside a run then fills its arrays without
// page faults. (A run's first two rebuilds at N = 22400 took ~960 and ~330 faults, ~10 us each on
// the VM of bench/README.md; a two-thread step there takes ~0.5 ms.) Keeps the contents.
template <class Vector>
void keep_room(Vector& v, std::size_t size) {
  if (v.capacity() >= size + size / 8) return;
  Vector room;
  room.reserve(size + size / 4);
  room.assign(v.begin(), v.end());
  const std::size_t kept = room.size();
  room.resize(room.capacity());  // writes every page
  room.resize(kept);
  v.swap(room);
}

// resize(size) within keep_room's room.
template <class... Vectors>
void resize_in_room(std::size_t size, Vectors&... vectors) {
  ((keep_room(vectors, size), vectors.resize(size)), ...);
}

// Forces and torques cached per disk belong to the current synchronous state (time t): they are
// a function of positions, velocities, delta_t and the cell only, so a state exported to a
// Configuration and read back continues to the bit.
struct DiskArrays {
  LineVector<double> x, y, vx, vy, omega, theta;
  LineVector<double> radius, mass, inertia, inv_mass, inv_inertia;
  LineVector<double> alpha_wall;  // damping coefficient against an infinitely heavy wall
  // Velocities predicted at the end of the step, used only by the viscous force (which depends
  // on the velocity it is meant to change).
  LineVector<double> vpx, vpy;
  LineVector<double> fx, fy, torque;  // elastic + frictional contact forces + external forces
  LineVector<double> fvx, fvy;        // viscous contact forces (normal, so no torque)
  LineVector<double> ext_fx, ext_fy;  // external forces; empty when none is applied
  // Contact state against each wall: tangential displacement, viscous force of the synchronous
  // state, and whether the contact was closed (the next step needs to know if it opens).
  std::array<LineVector<double>, 4> wall_delta_t, wall_f_v;
  std::array<LineVector<std::uint8_t>, 4> wall_closed;
  // The arrays a pass reads of a pair's partner (x, y, radius, vx, vy, omega, vpx, vpy) hold,
  // after the N disks, the ghost copies of a team's halo (Halo): mass does not.
  std::size_t size() const { return mass.size(); }
};

// A team's halo (plan_parts, halo.hpp): the disks of other parts that a part's passes read
// (the partners of its crossing pairs and the disks i of its mirrors), copied to ghost slots
// N + g of the disk arrays that the passes read. Part k's ghosts are g in [ghost_start[k],
// ghost_start[k + 1]), ascending by disk; its thread alone writes and reads them. Each step
// the owner of a ghosted disk packs its values into `buffer` after writing them, and the
// ghost's part copies them out after the barrier: one stream of whole lines instead of
// scattered lines of the other core's arrays (docs/dynamic.md, "Performance").
struct Halo {
  static constexpr int stride = 8;            // per ghost in `buffer`: 7 values, one line
  LineVector<std::int32_t> ghost_disk;        // per ghost: the disk it copies
  LineVector<std::int32_t> ghost_start;       // team + 1
  LineVector<std::int32_t> sent, sent_start;  // ghosts by the part that owns their disk
  LineVector<double> buffer;                  // stride per ghost: the values in transit
  LineVector<double> final_buffer;            // 2 per ghost: vx, vy after the force pass
  std::size_t size() const { return ghost_disk.size(); }
};

// The state of a listed pair that the force pass carries from step to step, and the frame of
// its last pass (F_T of a state is -K_T delta_t): of the listed pairs (PairArrays) and of their
// mirrors (PairArrays::mirrors), which evolve alike.
struct PairState {
  LineVector<std::int32_t> i, j;
  LineVector<double> alpha, delta_t;
  // Viscous force of i on j of the synchronous state (zero for open pairs): a pair that opens
  // during the next step keeps a share of it for the closing half kick.
  LineVector<double> viscous_x, viscous_y;
  LineVector<double> nx, ny, lx, ly, f_n;
  // The closed pairs of the last force pass from the start of a range in `active`, the pairs
  // that opened during the step from its end (per block, or per part for mirrors).
  LineVector<std::int32_t> active;
  std::size_t size() const { return i.size(); }
};

// Pairs of a team's part whose i lies in an earlier part: copies of those listed
// pairs, with a state of their own, which the part's thread computes again (the same inputs,
// the same operations, so the same bits as the listed pair) and adds to its disk j only, before
// its own rows. The listed pair adds to its i only. So no disk gets additions from two threads,
// and every disk's sums keep their order (docs/dynamic.md, "Determinism"). A mirror's i is the
// slot of disk i's ghost in j's part (Halo).
struct MirrorPairs : PairState {
  LineVector<std::int32_t> part_start;  // team + 1: part k's mirrors, in the list's order
  LineVector<std::int32_t> part_closed, part_opened;  // per part, as PairArrays::block_closed
};

// Pairs of the Verlet list, i < j, sorted by (i, j): CSR rows by i. Every disk sums its pair
// forces in ascending partner order whatever the list holds (see docs/dynamic.md,
// "Determinism"): the force pass adds each pair's force to both disks as it goes (rows in
// ascending i do exactly that order); across the parts of a team, through the mirrors.
struct PairArrays : PairState {
  LineVector<std::int32_t> row_start;  // N + 1
  // Per reduction block: the number of its closed pairs and of its opened ones in `active`.
  LineVector<std::int32_t> block_closed, block_opened;
  // Split of the blocks between `team` parts (part k: the blocks from part_block[k] on, each run
  // by one thread). team = 0: not planned for this list yet (plan_parts, parts.hpp).
  int team = 0;
  // The parts' first blocks and the block count (team + 1 entries): part k holds the blocks
  // [part_block[k], part_block[k + 1]). Even by default; the engine moves the boundaries to
  // balance its threads' work (EngineOptions::balance_steps). The sums do not depend on them.
  std::vector<std::int32_t> part_block;
  LineVector<std::uint8_t> crossing;        // per pair: j in a later part than i
  LineVector<std::uint8_t> block_crossing;  // per block: one of its rows has a crossing pair
  // Per pair: where the passes read disk j: j, or for a crossing pair its ghost slot in i's
  // part (N + g). (The mirrors' i are their ghost slots in j's part.)
  LineVector<std::int32_t> j_slot;
  MirrorPairs mirrors;
  Halo halo;
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
inline int block_count(std::size_t n) {
  return static_cast<int>((n + block_size - 1) / block_size);
}

}  // namespace granstab::dynamic
