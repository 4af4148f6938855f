#include "contact_forces.hpp"

#include <algorithm>
#include <cmath>

#include "common/contact_law.hpp"

namespace granstab::dynamic {
namespace {

constexpr Wall walls[4] = {wall_left, wall_right, wall_bottom, wall_top};

int block_count(std::size_t n) { return static_cast<int>((n + block_size - 1) / block_size); }

BlockSums add_blocks(const std::vector<BlockSums>& blocks, int count) {
  BlockSums total;
  for (int b = 0; b < count; ++b) {
    for (int k = 0; k < 4; ++k) total.sigma[k] += blocks[b].sigma[k];
    for (int k = 0; k < 2; ++k) {
      total.sigma_viscous[k] += blocks[b].sigma_viscous[k];
      total.wall_force[k] += blocks[b].wall_force[k];
      total.wall_force_viscous[k] += blocks[b].wall_force_viscous[k];
    }
  }
  return total;
}

// Velocity of the wall's material point (the mobile walls move perpendicular to themselves).
void wall_velocity(Wall w, const std::array<double, 2>& rate, double& vx, double& vy) {
  vx = w == wall_right ? rate[0] : 0.0;
  vy = w == wall_top ? rate[1] : 0.0;
}

// The contact law for one contact, with the tangential force read back from the stored state,
// F_T = -K_T delta_t (equal to the law's F_T up to one rounding on slip), so that the forces
// of a synchronous state are a function of that state alone and an exported state resumes to
// the bit. With dt = 0 (evaluating a given state) delta_t is kept as it is unless it lies
// outside the Coulomb cone by more than round-off (e.g. after mu was lowered).
inline ContactForce apply_law(const Material& m, double mu, double alpha, double h,
                              double h_rate, double delta_t, double dt, double rate) {
  ContactForce c = contact_force(m.k_n, m.k_t, mu, alpha, h, h_rate, delta_t, dt * rate);
  if (dt == 0.0 && std::abs(m.k_t * delta_t) <= (1.0 + sliding_tolerance) * mu * c.f_n) {
    c.delta_t = delta_t;
  }
  c.f_t = -m.k_t * c.delta_t;
  return c;
}

// The viscous force jumps when a contact closes or opens (SPEC §1.1: applied in full while
// h > 0). Velocity Verlet's trapezoidal impulse would place each jump at a step boundary + dt/2
// whatever its true time, an O(dt) error in the restitution coefficient. The time of the jump
// inside the step is estimated from h(t + dt) and the mid-step rate dh/dt, and the closing half
// kick gets the force scaled so that the impulse starts (or stops) at that time; the cached
// force of the synchronous state is not affected (the viscous pass recomputes it).
// Closing: the contact has been closed for tau = h / h_rate; impulse f tau = (dt/2) f share.
inline double viscous_share_closing(double h, double h_rate, double dt) {
  const double tau = h_rate > 0.0 ? std::min(h / h_rate, dt) : 0.5 * dt;
  return 2.0 * tau / dt;
}
// Opening: the contact has been open for tau = h / h_rate (both <= 0); the first half kick
// already applied f dt/2, so the closing half kick adds f (dt/2 - tau).
inline double viscous_share_opening(double h, double h_rate, double dt) {
  const double tau = h_rate < 0.0 ? std::min(h / h_rate, dt) : 0.5 * dt;
  return 1.0 - 2.0 * tau / dt;
}

// Minimum image of a separation of two wrapped positions (|dx| < L): a compare instead of a
// division and a rounding. Contacts are far shorter than L/2 (pair_search checks), so the
// image agrees with common/cell.hpp's minimum_image_shift used for the exported list.
inline double minimum_image(double dx, double length, double half_length) {
  if (dx > half_length) return dx - length;
  if (dx < -half_length) return dx + length;
  return dx;
}

// Pairs of the disks [first, end) of block b. Also lists the block's closed pairs (from the
// start of its pair range) and the pairs that opened during the step (from the end), for the
// viscous pass.
void pair_forces(const DiskArrays& d, PairArrays& pairs, const ForceInputs& in, int b, int first,
                 int end, BlockSums& sums) {
  const Material& mat = *in.material;
  const double half_l1 = 0.5 * in.length[0], half_l2 = 0.5 * in.length[1];
  const int range_begin = pairs.row_start[first], range_end = pairs.row_start[end];
  int next_closed = range_begin, next_opened = range_end;
  for (int p = range_begin; p < range_end; ++p) {
    const int i = pairs.i[p], j = pairs.j[p];
    const double xi = d.x[i], yi = d.y[i], ri = d.radius[i];
    double dx = d.x[j] - xi, dy = d.y[j] - yi;
    if (in.periodic) {
      dx = minimum_image(dx, in.length[0], half_l1);
      dy = minimum_image(dy, in.length[1], half_l2);
    }
    const double reach = ri + d.radius[j];
    const bool was_closed = pairs.f_n[p] > 0.0;
    PairArrays::Force& out = pairs.force[p];
    if (dx * dx + dy * dy >= reach * reach) {
      if (!was_closed) continue;  // open before and after: every slot is still zero
      // Opened during the step: the tangential state is dropped (SPEC §1.1), and the closing
      // half kick keeps the share of the viscous force of the part of the step it was closed.
      double share = 0.0;
      if (in.dt > 0.0) {
        const ContactFrame f = disk_disk_frame(dx, dy, ri, d.radius[j]);
        const double affine_x = in.periodic ? in.rate_tangential[0] * dx : 0.0;
        const double affine_y = in.periodic ? in.rate_tangential[1] * dy : 0.0;
        const double h_rate = deflection_rate(f, d.vx[j] - d.vx[i] + affine_x,
                                              d.vy[j] - d.vy[i] + affine_y);
        share = viscous_share_opening(f.h, h_rate, in.dt);
      }
      out = {0.0, 0.0, share * out.fvx, share * out.fvy, 0.0, 0.0};
      pairs.delta_t[p] = 0.0;
      pairs.f_n[p] = 0.0;
      pairs.active[--next_opened] = p;
      continue;
    }
    pairs.active[next_closed++] = p;
    const ContactFrame f = disk_disk_frame(dx, dy, ri, d.radius[j]);
    const double affine_tx = in.periodic ? in.rate_tangential[0] * dx : 0.0;
    const double affine_ty = in.periodic ? in.rate_tangential[1] * dy : 0.0;
    const double dvx = d.vx[j] - d.vx[i] + affine_tx, dvy = d.vy[j] - d.vy[i] + affine_ty;
    const double rate = tangential_rate(f, dvx, dvy, d.omega[i], d.omega[j]);
    const double affine_vx = in.periodic ? in.rate_viscous[0] * dx : 0.0;
    const double affine_vy = in.periodic ? in.rate_viscous[1] * dy : 0.0;
    const double h_rate =
        deflection_rate(f, in.vx_viscous[j] - in.vx_viscous[i] + affine_vx,
                        in.vy_viscous[j] - in.vy_viscous[i] + affine_vy);
    const ContactForce c =
        apply_law(mat, mat.mu, pairs.alpha[p], f.h, h_rate, pairs.delta_t[p], in.dt, rate);
    pairs.delta_t[p] = c.delta_t;
    pairs.f_n[p] = c.f_n;
    pairs.nx[p] = f.nx;
    pairs.ny[p] = f.ny;
    pairs.lx[p] = dx;
    pairs.ly[p] = dy;
    const double fx = c.f_n * f.nx + c.f_t * f.tx;
    const double fy = c.f_n * f.ny + c.f_t * f.ty;
    // A contact that closed during the step gets, for the closing half kick only, the share
    // of its viscous force of the part of the step it was closed.
    const double share =
        was_closed || in.dt == 0.0
            ? 1.0
            : viscous_share_closing(f.h, deflection_rate(f, dvx, dvy), in.dt);
    const double fvx = share * c.f_v * f.nx, fvy = share * c.f_v * f.ny;
    out = {fx, fy, fvx, fvy, -f.a_i * c.f_t, -f.a_j * c.f_t};
    sums.sigma[0] += fx * dx;
    sums.sigma[1] += fx * dy;
    sums.sigma[2] += fy * dx;
    sums.sigma[3] += fy * dy;
    sums.sigma_viscous[0] += fvx * dx;
    sums.sigma_viscous[1] += fvy * dy;
  }
  pairs.block_closed[b] = next_closed - range_begin;
  pairs.block_opened[b] = range_end - next_opened;
}

// Viscous force only, at the velocities of in, over the closed pairs listed by pair_forces
// (whose frame it stored); pairs that opened during the step drop their share.
void pair_viscous(const DiskArrays& /*disks*/, PairArrays& pairs, const ForceInputs& in, int b,
                  int first, int end, BlockSums& sums) {
  const int range_begin = pairs.row_start[first], range_end = pairs.row_start[end];
  for (int k = range_end - pairs.block_opened[b]; k < range_end; ++k) {
    PairArrays::Force& out = pairs.force[pairs.active[k]];
    out.fvx = out.fvy = 0.0;
  }
  for (int k = range_begin; k < range_begin + pairs.block_closed[b]; ++k) {
    const int p = pairs.active[k];
    const int i = pairs.i[p], j = pairs.j[p];
    const double dx = pairs.lx[p], dy = pairs.ly[p];
    ContactFrame f{};
    f.nx = pairs.nx[p];
    f.ny = pairs.ny[p];
    const double affine_vx = in.periodic ? in.rate_viscous[0] * dx : 0.0;
    const double affine_vy = in.periodic ? in.rate_viscous[1] * dy : 0.0;
    const double h_rate =
        deflection_rate(f, in.vx_viscous[j] - in.vx_viscous[i] + affine_vx,
                        in.vy_viscous[j] - in.vy_viscous[i] + affine_vy);
    const double f_v = pairs.alpha[p] * h_rate;  // as contact_force() computes it
    PairArrays::Force& out = pairs.force[p];
    out.fvx = f_v * f.nx;
    out.fvy = f_v * f.ny;
    sums.sigma_viscous[0] += out.fvx * dx;
    sums.sigma_viscous[1] += out.fvy * dy;
  }
}

// Disk-wall contacts of disk i (walls boundary): the wall is the partner j, infinitely heavy.
// Adds the forces on the disk to fx..torque and the forces on the walls to sums.
void wall_forces(DiskArrays& d, const ForceInputs& in, const Cell& cell, int i, bool viscous_only,
                 double& fx, double& fy, double& fvx, double& fvy, double& torque,
                 BlockSums& sums) {
  const Material& mat = *in.material;
  for (int w = 0; w < 4; ++w) {
    const ContactFrame f = disk_wall_frame(d.x[i], d.y[i], d.radius[i], walls[w], cell);
    const bool was_closed = d.wall_closed[w][i] != 0;
    double wvx, wvy;
    wall_velocity(walls[w], in.rate_tangential, wvx, wvy);
    const double dvx = wvx - d.vx[i], dvy = wvy - d.vy[i];  // mid-step, wall relative to disk
    double f_v;
    if (!(f.h > 0.0)) {
      if (viscous_only) continue;
      // Opening during the step: see viscous_share_opening.
      f_v = was_closed && in.dt > 0.0
                ? d.wall_f_v[w][i] * viscous_share_opening(f.h, deflection_rate(f, dvx, dvy), in.dt)
                : 0.0;
      d.wall_delta_t[w][i] = 0.0;
      d.wall_f_v[w][i] = 0.0;
      d.wall_closed[w][i] = 0;
      if (f_v == 0.0) continue;
    } else {
      wall_velocity(walls[w], in.rate_viscous, wvx, wvy);
      const double h_rate = deflection_rate(f, wvx - in.vx_viscous[i], wvy - in.vy_viscous[i]);
      if (viscous_only) {
        f_v = d.alpha_wall[i] * h_rate;  // as contact_force() computes it
        d.wall_f_v[w][i] = f_v;
      } else {
        const double rate = tangential_rate(f, dvx, dvy, d.omega[i], 0.0);
        const ContactForce c = apply_law(mat, mat.mu_wall, d.alpha_wall[i], f.h, h_rate,
                                         d.wall_delta_t[w][i], in.dt, rate);
        d.wall_delta_t[w][i] = c.delta_t;
        d.wall_f_v[w][i] = c.f_v;
        const double share =
            was_closed || in.dt == 0.0
                ? 1.0
                : viscous_share_closing(f.h, deflection_rate(f, dvx, dvy), in.dt);
        d.wall_closed[w][i] = 1;
        f_v = share * c.f_v;
        const double ex = c.f_n * f.nx + c.f_t * f.tx;  // of the disk on the wall
        const double ey = c.f_n * f.ny + c.f_t * f.ty;
        fx -= ex;
        fy -= ey;
        torque -= f.a_i * c.f_t;
        sums.sigma[0] += ex * f.lx;
        sums.sigma[1] += ex * f.ly;
        sums.sigma[2] += ey * f.lx;
        sums.sigma[3] += ey * f.ly;
        if (walls[w] == wall_right) sums.wall_force[0] += ex;
        if (walls[w] == wall_top) sums.wall_force[1] += ey;
      }
    }
    const double vx = f_v * f.nx, vy = f_v * f.ny;
    fvx -= vx;
    fvy -= vy;
    sums.sigma_viscous[0] += vx * f.lx;
    sums.sigma_viscous[1] += vy * f.ly;
    if (walls[w] == wall_right) sums.wall_force_viscous[0] += vx;
    if (walls[w] == wall_top) sums.wall_force_viscous[1] += vy;
  }
}

// Per-disk sums in ascending partner order: pairs where the disk is j (partners < i), then
// pairs where it is i (partners > i), then walls, then the external force.
void accumulate(DiskArrays& d, const PairArrays& pairs, const ForceInputs& in, const Cell& cell,
                int i, bool viscous_only, BlockSums& sums) {
  double fx = 0.0, fy = 0.0, fvx = 0.0, fvy = 0.0, torque = 0.0;
  for (int s = pairs.column_start[i]; s < pairs.column_start[i + 1]; ++s) {
    const PairArrays::Force& f = pairs.force[pairs.column_pair[s]];
    fx += f.fx;
    fy += f.fy;
    fvx += f.fvx;
    fvy += f.fvy;
    torque += f.torque_j;
  }
  for (int p = pairs.row_start[i]; p < pairs.row_start[i + 1]; ++p) {
    const PairArrays::Force& f = pairs.force[p];
    fx -= f.fx;
    fy -= f.fy;
    fvx -= f.fvx;
    fvy -= f.fvy;
    torque += f.torque_i;
  }
  if (!in.periodic) wall_forces(d, in, cell, i, viscous_only, fx, fy, fvx, fvy, torque, sums);
  d.fvx[i] = fvx;
  d.fvy[i] = fvy;
  if (viscous_only) return;
  if (!d.ext_fx.empty()) {
    fx += d.ext_fx[i];
    fy += d.ext_fy[i];
  }
  d.fx[i] = fx;
  d.fy[i] = fy;
  d.torque[i] = torque;
}

template <class PairPass>
BlockSums run(DiskArrays& disks, PairArrays& pairs, const ForceInputs& in,
              std::vector<BlockSums>& blocks, bool viscous_only, PairPass pair_pass) {
  const int n = static_cast<int>(disks.size());
  const int nb = block_count(disks.size());
  blocks.resize(2 * static_cast<std::size_t>(nb));
  pairs.block_closed.resize(nb);
  pairs.block_opened.resize(nb);
  Cell cell;
  cell.boundary = in.periodic ? Boundary::periodic : Boundary::walls;
  cell.length = in.length;
#pragma omp parallel if (in.parallel)
  {
#pragma omp for schedule(static)
    for (int b = 0; b < nb; ++b) {
      BlockSums sums;
      const int end = std::min(n, (b + 1) * block_size);
      pair_pass(disks, pairs, in, b, b * block_size, end, sums);
      blocks[b] = sums;
    }
#pragma omp for schedule(static)
    for (int b = 0; b < nb; ++b) {
      BlockSums sums;
      const int end = std::min(n, (b + 1) * block_size);
      for (int i = b * block_size; i < end; ++i) {
        accumulate(disks, pairs, in, cell, i, viscous_only, sums);
      }
      blocks[nb + b] = sums;
    }
  }
  return add_blocks(blocks, 2 * nb);
}

}  // namespace

BlockSums compute_contact_forces(DiskArrays& disks, PairArrays& pairs, const ForceInputs& in,
                                 std::vector<BlockSums>& blocks) {
  return run(disks, pairs, in, blocks, false, pair_forces);
}

BlockSums compute_viscous_forces(DiskArrays& disks, PairArrays& pairs, const ForceInputs& in,
                                 std::vector<BlockSums>& blocks) {
  return run(disks, pairs, in, blocks, true, pair_viscous);
}

}  // namespace granstab::dynamic
