#pragma once
// THE contact law of SPEC §1.1, written once. The dynamic module calls contact_force() for every
// contact at every step; the static module builds its residual from the same functions and its
// stiffness as their exact linearisation (STATIC.md §S1, checked by finite differences).
//
// Conventions (STATIC.md §S0): the branch vector l points from i to j, n = l/|l|, t = n rotated
// by +90 degrees; the force f = (F_N + F_v) n + F_T t is exerted BY i ON j (-f acts on i), applied
// at the contact point r_i + a_i n = r_j - a_j n with lever arms a = R - h/2. Then the torque of
// the contact is -a_i F_T on i and -a_j F_T on j.
//
// The functions that the dynamic pair loop needs are templates over the number type T: double
// here and in static/, a SIMD type of several lanes in dynamic/contact_forces_simd.cpp, so that
// both run this one source. T provides + - * /, comparisons giving mask_t<T> (bool for double),
// and sqrt, abs, copysign, select found by argument-dependent lookup (std:: for double); every
// lane computes exactly what the double version computes. Where the law branches on a costly
// side (a division), it says so with select_lazy: the double instantiation branches as plain code
// would (only the side taken is computed), a SIMD type computes both sides and selects by lane.
#include <cmath>
#include <type_traits>
#include <utility>

#include "cell.hpp"

namespace granstab {

template <class T>
using mask_t = decltype(std::declval<T>() > std::declval<T>());

// cond ? a : b, lane by lane for a SIMD type (both sides are computed).
inline double select(bool cond, double a, double b) { return cond ? a : b; }

// cond ? a() : b(): for double (cond a bool) a branch, so only the side taken is computed; for a
// SIMD type both sides, selected lane by lane.
template <class M, class A, class B>
inline auto select_lazy(M cond, A a, B b) {
  if constexpr (std::is_same_v<M, bool>) {
    return cond ? a() : b();
  } else {
    return select(cond, a(), b());
  }
}

template <class T>
struct BasicContactFrame {
  T lx, ly;    // branch vector (disk-wall: from the centre to the foot on the wall, l = d n)
  T d;         // |l|
  T nx, ny;    // unit normal, from i to j
  T tx, ty;    // unit tangent, n rotated +90 degrees
  T h;         // normal deflection (overlap); contact iff h > 0
  T a_i, a_j;  // lever arms from each centre to the contact point
};
using ContactFrame = BasicContactFrame<double>;

// Frame of a disk-disk contact from the branch vector l = r_j(image) - r_i.
template <class T>
inline BasicContactFrame<T> disk_disk_frame(T lx, T ly, T r_i, T r_j) {
  using std::sqrt;
  BasicContactFrame<T> f;
  f.lx = lx;
  f.ly = ly;
  f.d = sqrt(lx * lx + ly * ly);
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
template <class T>
inline T tangential_rate(const BasicContactFrame<T>& f, T dvx, T dvy, T omega_i, T omega_j) {
  return dvx * f.tx + dvy * f.ty - f.a_i * omega_i - f.a_j * omega_j;
}

// Normal deflection rate dh/dt = -(v_j - v_i) . n.
template <class T>
inline T deflection_rate(const BasicContactFrame<T>& f, T dvx, T dvy) {
  return -(dvx * f.nx + dvy * f.ny);
}

template <class T>
struct BasicTangentialForce {
  T f_t;              // tangential force along t, of i on j
  T delta_t;          // tangential elastic displacement after the Coulomb return
  mask_t<T> sliding;  // the trial force was returned to the cone
};
using TangentialForce = BasicTangentialForce<double>;

// Coulomb return (SPEC §1.1): F_T = -K_T delta_t, clipped to |F_T| <= mu F_N with F_N the elastic
// normal force; on slip delta_t = -F_T / K_T so the stored state always reproduces F_T.
template <class T>
inline BasicTangentialForce<T> tangential_force(T k_t, T mu, T f_n, T delta_t_trial) {
  using std::abs, std::copysign;
  const T f_trial = -k_t * delta_t_trial;
  const T limit = select(f_n > 0.0, mu * f_n, T(0.0));
  const mask_t<T> slides = abs(f_trial) > limit;
  // Only on slip (for double a branch: sticking contacts, the most, skip the division).
  const T f_t = select_lazy(
      slides, [&] { return copysign(limit, f_trial); }, [&] { return f_trial; });
  const T delta_t = select_lazy(
      slides, [&] { return -f_t / k_t; }, [&] { return delta_t_trial; });
  return {f_t, delta_t, slides};
}

// A contact whose |F_T| equals mu F_N to round-off is sliding (SPEC §1.1); the relative margin is
// the "critical" threshold of STATIC.md §S3.0.
inline constexpr double sliding_tolerance = 1e-9;
inline bool is_sliding(double f_t, double f_n, double mu) {
  return f_n > 0.0 && mu > 0.0 && std::abs(f_t) >= (1.0 - sliding_tolerance) * mu * f_n;
}

template <class T>
struct BasicContactForce {
  T f_n;      // elastic normal force K_N h: enters stresses and the Coulomb limit
  T f_v;      // viscous normal force alpha dh/dt: dissipative only, never in stresses
  T f_t;      // tangential force along t
  T delta_t;  // updated tangential elastic displacement
  mask_t<T> sliding;
};
using ContactForce = BasicContactForce<double>;

// The full law for one time step: h and h_rate from the frame, the tangential increment
// d_delta_t accumulated from tangential_rate() over the step, alpha from
// Material::damping_coefficient(). Viscosity is applied in full while h > 0 (SPEC §1.1).
template <class T>
inline BasicContactForce<T> contact_force(T k_n, T k_t, T mu, T alpha, T h, T h_rate,
                                          T delta_t_previous, T d_delta_t) {
  const T f_n = k_n * h;
  const BasicTangentialForce<T> t = tangential_force(k_t, mu, f_n, delta_t_previous + d_delta_t);
  return {f_n, alpha * h_rate, t.f_t, t.delta_t, t.sliding};
}

}  // namespace granstab
