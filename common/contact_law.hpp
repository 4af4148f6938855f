#pragma once
// THE contact law of SPEC §1.1, written once. The dynamic module calls contact_force() for every
// contact at every step; the static module builds its residual from the same functions and its
// stiffness as their exact linearisation (STATIC.md §S1, checked by finite differences).
//
// Conventions (STATIC.md §S0): the branch vector l points from i to j, n = l/|l|, t = n rotated
// by +90 degrees; the force f = (F_N + F_v) n + F_T t is exerted BY i ON j (-f acts on i), applied
// at the contact point r_i + a_i n = r_j - a_j n with lever arms a = R - h/2. Then the torque of
// the contact is -a_i F_T on i and -a_j F_T on j.
#include <cmath>

#include "cell.hpp"

namespace granstab {

struct ContactFrame {
  double lx, ly;    // branch vector (disk-wall: from the centre to the foot on the wall, l = d n)
  double d;         // |l|
  double nx, ny;    // unit normal, from i to j
  double tx, ty;    // unit tangent, n rotated +90 degrees
  double h;         // normal deflection (overlap); contact iff h > 0
  double a_i, a_j;  // lever arms from each centre to the contact point
};

// Frame of a disk-disk contact from the branch vector l = r_j(image) - r_i.
inline ContactFrame disk_disk_frame(double lx, double ly, double r_i, double r_j) {
  ContactFrame f;
  f.lx = lx;
  f.ly = ly;
  f.d = std::sqrt(lx * lx + ly * ly);
  f.nx = lx / f.d;
  f.ny = ly / f.d;
  f.tx = -f.ny;
  f.ty = f.nx;
  f.h = r_i + r_j - f.d;
  // a_i + a_j = d, so a rigid rotation of the pair moves both contact points alike (§S0).
  f.a_i = r_i - 0.5 * f.h;
  f.a_j = r_j - 0.5 * f.h;
  return f;
}

// Frame of a contact between disk i (centre x, y, radius r) and a wall of the rectangle
// [0, L1] x [0, L2]. The wall is the partner j, an infinitely heavy body that does not rotate;
// n points from the disk into the wall.
inline ContactFrame disk_wall_frame(double x, double y, double r, Wall wall, const Cell& cell) {
  ContactFrame f;
  switch (wall) {
    case wall_left:
      f.nx = -1.0;
      f.ny = 0.0;
      f.d = x;
      break;
    case wall_right:
      f.nx = 1.0;
      f.ny = 0.0;
      f.d = cell.length[0] - x;
      break;
    case wall_bottom:
      f.nx = 0.0;
      f.ny = -1.0;
      f.d = y;
      break;
    case wall_top:
      f.nx = 0.0;
      f.ny = 1.0;
      f.d = cell.length[1] - y;
      break;
  }
  f.lx = f.d * f.nx;
  f.ly = f.d * f.ny;
  f.tx = -f.ny;
  f.ty = f.nx;
  f.h = r - f.d;
  f.a_i = r - 0.5 * f.h;
  f.a_j = 0.0;
  return f;
}

// Relative tangential displacement rate of j's contact point with respect to i's, along t:
// (v_j - v_i) . t - a_i omega_i - a_j omega_j (the B_T row of STATIC.md §S1).
inline double tangential_rate(const ContactFrame& f, double dvx, double dvy, double omega_i,
                              double omega_j) {
  return dvx * f.tx + dvy * f.ty - f.a_i * omega_i - f.a_j * omega_j;
}

// Normal deflection rate dh/dt = -(v_j - v_i) . n.
inline double deflection_rate(const ContactFrame& f, double dvx, double dvy) {
  return -(dvx * f.nx + dvy * f.ny);
}

struct TangentialForce {
  double f_t;      // tangential force along t, of i on j
  double delta_t;  // tangential elastic displacement after the Coulomb return
  bool sliding;    // the trial force was returned to the cone
};

// Coulomb return (SPEC §1.1): F_T = -K_T delta_t, clipped to |F_T| <= mu F_N with F_N the elastic
// normal force; on slip delta_t = -F_T / K_T so the stored state always reproduces F_T.
inline TangentialForce tangential_force(double k_t, double mu, double f_n, double delta_t_trial) {
  const double f_trial = -k_t * delta_t_trial;
  const double limit = f_n > 0.0 ? mu * f_n : 0.0;
  if (std::abs(f_trial) > limit) {
    const double f_t = std::copysign(limit, f_trial);
    return {f_t, -f_t / k_t, true};
  }
  return {f_trial, delta_t_trial, false};
}

// A contact whose |F_T| equals mu F_N to round-off is sliding (SPEC §1.1); the relative margin is
// the "critical" threshold of STATIC.md §S3.0.
inline constexpr double sliding_tolerance = 1e-9;
inline bool is_sliding(double f_t, double f_n, double mu) {
  return f_n > 0.0 && mu > 0.0 && std::abs(f_t) >= (1.0 - sliding_tolerance) * mu * f_n;
}

struct ContactForce {
  double f_n;      // elastic normal force K_N h: enters stresses and the Coulomb limit
  double f_v;      // viscous normal force alpha dh/dt: dissipative only, never in stresses
  double f_t;      // tangential force along t
  double delta_t;  // updated tangential elastic displacement
  bool sliding;
};

// The full law for one time step: h and h_rate from the frame, the tangential increment
// d_delta_t accumulated from tangential_rate() over the step, alpha from
// Material::damping_coefficient(). Viscosity is applied in full while h > 0 (SPEC §1.1).
inline ContactForce contact_force(double k_n, double k_t, double mu, double alpha, double h,
                                  double h_rate, double delta_t_previous, double d_delta_t) {
  const double f_n = k_n * h;
  const TangentialForce t = tangential_force(k_t, mu, f_n, delta_t_previous + d_delta_t);
  return {f_n, alpha * h_rate, t.f_t, t.delta_t, t.sliding};
}

}  // namespace granstab
