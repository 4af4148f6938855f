#pragma once
// Verlet list with a skin over the cell-list pair search (common/pair_search.hpp), rebuilt when
// the disks' non-affine displacements or the cell's contraction since the last build could let
// an unlisted pair touch. Tangential state is carried over to the new list for persisting pairs.
#include <array>
#include <cstdint>
#include <vector>

#include "common/pair_search.hpp"
#include "common/material.hpp"
#include "state.hpp"

namespace granstab::dynamic {

class NeighbourList {
 public:
  // The rebuild test of the current list as a value: each thread of a team keeps a copy, so
  // that one thread may rebuild while the others still test (engine.cpp).
  struct RebuildTest {
    bool built = false;
    double skin = 0.0, r_max = 0.0;
    std::array<double, 2> reference_length{1.0, 1.0};
    // Whether an unlisted pair could touch, given the largest non-affine displacement since
    // the build (squared, in current lengths).
    bool operator()(const CellState& cell, double max_displacement2) const;
  };

  explicit NeighbourList(double skin = 0.1) : skin_(skin) {}
  double skin() const { return skin_; }
  std::uint64_t rebuild_count() const { return rebuilds_; }

  RebuildTest rebuild_test() const { return {built_, skin_, r_max_, ref_length_}; }
  // Rebuilds if needed; returns true if it did.
  bool update(DiskArrays& disks, const CellState& cell, PairArrays& pairs,
              const Material& material);
  void rebuild(DiskArrays& disks, const CellState& cell, PairArrays& pairs,
               const Material& material);

  // rebuild() in steps that a team shares (engine.cpp): each thread's part lists the rows of
  // its disks, the team meeting at a barrier between the steps. One thread: begin_rebuild with
  // `parts` parts; every part: find_rows; one thread: size_list; every part: fill_rows; one
  // thread: end_rebuild. Part k's disks [first, end), the parts covering [0, N) in order. The
  // list, and so the bits of a run, are rebuild()'s whatever the parts.
  void begin_rebuild(const DiskArrays& disks, const CellState& cell, PairArrays& pairs, int parts);
  void find_rows(int part, int first, int end);
  void size_list(PairArrays& pairs, std::size_t n);
  void fill_rows(const DiskArrays& disks, const CellState& cell, PairArrays& pairs,
                 const Material& material, int part, int first, int end);
  void end_rebuild(const CellState& cell, PairArrays& pairs);
  // Called by the integrator after the drift: the largest non-affine displacement since the
  // last build (squared, in current lengths).
  void set_max_displacement_squared(double d2) { max_displacement2_ = d2; }
  // Reduced positions at the last build (the reference of the displacement check).
  const LineVector<double>& reference_x() const { return ref_sx_; }
  const LineVector<double>& reference_y() const { return ref_sy_; }
  const std::array<double, 2>& reference_length() const { return ref_length_; }

 private:
  double skin_;
  double r_max_ = 0.0;
  double max_displacement2_ = 0.0;
  std::uint64_t rebuilds_ = 0;
  bool built_ = false;
  LineVector<double> ref_sx_, ref_sy_;
  std::array<double, 2> ref_length_{1.0, 1.0};
  PairSearch search_;
  // Per part: its rows and the search's scratch, on cache lines of their own (each push_back
  // writes the vector's end: side by side, two threads' rows made the search as slow on two
  // threads as on one), and where its rows start in the list.
  struct alignas(64) PartRows {
    PairList found;
    PairSearch::Scratch scratch;
  };
  std::vector<PartRows> parts_;
  std::vector<std::size_t> found_start_;
  bool had_list_ = false;  // the old list (old_*) carries state over to the new one
  LineVector<std::int32_t> old_i_, old_j_, old_row_start_;
  LineVector<double> old_delta_t_, old_f_n_, old_viscous_x_, old_viscous_y_;
};

}  // namespace granstab::dynamic
