// The viscous pass of a time step: the viscous forces of the closed pairs at the end-of-step
// velocities, with the frames the force pass stored (docs/dynamic.md, "Integrator and time
// step").
#include "contact_forces.hpp"
#include "contact_forces_law.hpp"
#include "force_pass_team.hpp"

namespace granstab::dynamic {
namespace {

// Viscous force only, at the velocities of in, of the closed pairs of s listed in s.active
// [closed_begin, closed_end) by the force pass (whose frame it stored): stored in the pair and
// handed to add(p, i, j, fvx, fvy, dx, dy) in that order. The opened pairs listed in
// [opened_begin, opened_end) drop their share.
template <bool Periodic, class Add>
[[gnu::always_inline]] inline void viscous_sweep(PairState& s, const std::int32_t* read_j,
                                                 const ForceInputs& in, int closed_begin,
                                                 int closed_end, int opened_begin, int opened_end,
                                                 Add add) {
  const double rate_v1 = Periodic ? in.rate_viscous[0] : 0.0;
  const double rate_v2 = Periodic ? in.rate_viscous[1] : 0.0;
  const double* const vvx = in.vx_viscous;
  const double* const vvy = in.vy_viscous;
  for (int k = opened_begin; k < opened_end; ++k) {
    const int p = s.active[k];
    s.viscous_x[p] = s.viscous_y[p] = 0.0;
  }
  for (int k = closed_begin; k < closed_end; ++k) {
    const int p = s.active[k];
    const int i = s.i[p], j = read_j[p];
    const double dx = s.lx[p], dy = s.ly[p];
    ContactFrame f{};
    f.nx = s.nx[p];
    f.ny = s.ny[p];
    const double affine_vx = Periodic ? rate_v1 * dx : 0.0;
    const double affine_vy = Periodic ? rate_v2 * dy : 0.0;
    const double h_rate =
        deflection_rate(f, vvx[j] - vvx[i] + affine_vx, vvy[j] - vvy[i] + affine_vy);
    const double f_v = s.alpha[p] * h_rate;  // as contact_force() computes it
    const double fvx = f_v * f.nx, fvy = f_v * f.ny;
    s.viscous_x[p] = fvx;
    s.viscous_y[p] = fvy;
    add(p, i, j, fvx, fvy, dx, dy);
  }
}

// The viscous forces of block b's pairs (rows of the disks [first, end)).
template <bool Crossing, bool Periodic>
[[gnu::always_inline]] inline void pair_viscous(DiskArrays& d, PairArrays& pairs,
                                                const ForceInputs& in, int b, int first, int end,
                                                BlockSums& sums) {
  double* const fvx_sum = d.fvx.data();
  double* const fvy_sum = d.fvy.data();
  const int range_begin = pairs.row_start[first], range_end = pairs.row_start[end];
  viscous_sweep<Periodic>(pairs, pairs.j_slot.data(), in, range_begin,
                          range_begin + pairs.block_closed[b], range_end - pairs.block_opened[b],
                          range_end,
                          [&](int p, int i, int j, double fvx, double fvy, double dx, double dy) {
                            sums.sigma_viscous[0] += fvx * dx;
                            sums.sigma_viscous[1] += fvy * dy;
                            // Rows in ascending i: j's sum gets its column part, i's its row part,
                            // in order.
                            if (!Crossing || !pairs.crossing[p]) {
                              fvx_sum[j] += fvx;
                              fvy_sum[j] += fvy;
                            }
                            fvx_sum[i] -= fvx;
                            fvy_sum[i] -= fvy;
                          });
}

// The same for the mirrors of `part`, to their disk j only (before the part's rows).
template <bool Periodic>
[[gnu::always_inline]] inline void mirror_viscous(DiskArrays& d, MirrorPairs& m,
                                                  const ForceInputs& in, int part) {
  double* const fvx_sum = d.fvx.data();
  double* const fvy_sum = d.fvy.data();
  const int begin = m.part_start[part], end = m.part_start[part + 1];
  viscous_sweep<Periodic>(m, m.j.data(), in, begin, begin + m.part_closed[part],
                          end - m.part_opened[part], end,
                          [&](int, int, int j, double fvx, double fvy, double, double) {
                            fvx_sum[j] += fvx;
                            fvy_sum[j] += fvy;
                          });
}

}  // namespace

void viscous_forces_part(const TeamMember& member, DiskArrays& disks, PairArrays& pairs,
                         const ForceInputs& in, std::vector<BlockSums>& blocks) {
  const Cell cell = cell_of(in);
  const auto clear = [](int, int) {};  // the force pass with the kick left zeros
  const auto mirrors = [&](int part) {
    with_flags(false, in.periodic, [&]<bool, bool Periodic>() {
      mirror_viscous<Periodic>(disks, pairs.mirrors, in, part);
    });
  };
  const auto rows = [&](int b, int first, int end, BlockSums& sums) {
    with_flags(
        pairs.block_crossing[b],
        in.periodic, [&]<bool Crossing, bool Periodic>() __attribute__((noinline)) {
          pair_viscous<Crossing, Periodic>(disks, pairs, in, b, first, end, sums);
        });
  };
  const auto finish = [&](int i, BlockSums& sums) {
    finish_disk(disks, in, cell, i, true, RowSums{0.0, 0.0, disks.fvx[i], disks.fvy[i], 0.0}, sums);
  };
  // Periodic cells: the sums are complete after the rows; walls add their viscous forces.
  run_part(member, disks, pairs, blocks, clear, mirrors, rows, !in.periodic, finish);
}

}  // namespace granstab::dynamic
