#pragma once
// The disk-wall contacts of the force pass (walls boundary, SPEC §1.2): the wall is the partner,
// infinitely heavy, with the law of common/contact_law.hpp. Included by force_pass_team.hpp only,
// in an anonymous namespace: each pass stays one translation unit, so the compiler inlines these
// into the hot loop as it does the pair kernels.
#include <array>

#include "contact_forces.hpp"
#include "contact_forces_law.hpp"

namespace granstab::dynamic {
namespace {

constexpr Wall walls[4] = {wall_left, wall_right, wall_bottom, wall_top};

// Velocity of the wall's material point (the mobile walls move perpendicular to themselves).
void wall_velocity(Wall w, const std::array<double, 2>& rate, double& vx, double& vy) {
  vx = w == wall_right ? rate[0] : 0.0;
  vy = w == wall_top ? rate[1] : 0.0;
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
    const double dvx = wvx - in.vx[i], dvy = wvy - in.vy[i];  // mid-step, wall relative to disk
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
        const double rate = tangential_rate(f, dvx, dvy, in.omega[i], 0.0);
        const ContactForce c = apply_law(mat.k_n, mat.k_t, mat.mu_wall, d.alpha_wall[i], f.h,
                                         h_rate, d.wall_delta_t[w][i], in.dt, rate);
        d.wall_delta_t[w][i] = c.delta_t;
        d.wall_f_v[w][i] = c.f_v;
        const double share = was_closed || in.dt == 0.0
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

}  // namespace
}  // namespace granstab::dynamic
