#pragma once
// The engine's use of the contact law for one listed disk-disk pair, as templates over the
// number type (double, or the SIMD type of contact_forces_simd.cpp): both pair loops of the
// force pass, the scalar one and the SIMD kernel, instantiate this one source, so they compute
// the same bits lane by lane (no FMA contraction: -ffp-contract=off, same operation order).
#include <algorithm>
#include <cmath>

#include "common/contact_law.hpp"

namespace granstab::dynamic {

// The contact law for one contact, with the tangential force read back from the stored state,
// F_T = -K_T delta_t (equal to the law's F_T up to one rounding on slip), so that the forces
// of a synchronous state are a function of that state alone and an exported state resumes to
// the bit. With dt = 0 (evaluating a given state) delta_t is kept as it is unless it lies
// outside the Coulomb cone by more than round-off (e.g. after mu was lowered).
template <class T>
inline BasicContactForce<T> apply_law(T k_n, T k_t, T mu, T alpha, T h, T h_rate, T delta_t,
                                      double dt, T rate) {
  using std::abs;
  BasicContactForce<T> c = contact_force(k_n, k_t, mu, alpha, h, h_rate, delta_t, dt * rate);
  if (dt == 0.0) {
    c.delta_t =
        select(abs(k_t * delta_t) <= (1.0 + sliding_tolerance) * mu * c.f_n, delta_t, c.delta_t);
  }
  c.f_t = -k_t * c.delta_t;
  return c;
}

// The viscous force jumps when a contact closes or opens (SPEC §1.1: applied in full while
// h > 0). Velocity Verlet's trapezoidal impulse would place each jump at a step boundary + dt/2
// whatever its true time, an O(dt) error in the restitution coefficient. The time of the jump
// inside the step is estimated from h(t + dt) and the mid-step rate dh/dt, and the closing half
// kick gets the force scaled so that the impulse starts (or stops) at that time; the cached
// force of the synchronous state is not affected (the viscous pass recomputes it).
// Closing: the contact has been closed for tau = h / h_rate; impulse f tau = (dt/2) f share.
// (select(dt < q, dt, q) is std::min(q, dt).)
template <class T>
inline T viscous_share_closing(T h, T h_rate, double dt) {
  const T tau = select_lazy(
      h_rate > 0.0,
      [&] {
        const T q = h / h_rate;
        return select(dt < q, T(dt), q);
      },
      [&] { return T(0.5 * dt); });
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
template <class T>
inline T minimum_image(T dx, double length, double half_length) {
  return select_lazy(
      dx > half_length, [&] { return dx - length; },
      [&] {
        return select_lazy(
            dx < -half_length, [&] { return dx + length; }, [&] { return dx; });
      });
}

// Constants of the pair law during one pass.
struct PairLawConstants {
  double k_n, k_t, mu, dt;
  double rate_t1, rate_t2;  // affine strain rates of the tangential increment (periodic cells)
  double rate_v1, rate_v2;  // and of the viscous force
};

// What the force pass adds to the disks of a closed pair: its force of i on j.
template <class T>
struct ClosedPair {
  T fx, fy, fvx, fvy;  // elastic + frictional, viscous (with the closing share)
  T torque_i, torque_j;
};

// The law of a listed pair found closed (|l| < r_i + r_j) with branch vector (dx, dy): disk
// values of i and j (mid-step v, omega; the viscous velocities vv), the pair's alpha and
// delta_t, and whether it was closed before the step (else the closing half kick gets the
// share of the viscous force of the part of the step it was closed). The pair's new state is
// handed to keep_state(delta_t, f_n, nx, ny) as soon as it is known (for double, the stores then
// come where the plain loop had them, which keeps fewer values live across the force terms).
template <bool Periodic, class T, class KeepState>
inline ClosedPair<T> closed_pair_law(const PairLawConstants& k, T dx, T dy, T ri, T rj, T vxi,
                                     T vyi, T omega_i, T vxj, T vyj, T omega_j, T vvxi, T vvyi,
                                     T vvxj, T vvyj, T alpha, T delta_t, mask_t<T> was_closed,
                                     KeepState keep_state) {
  const BasicContactFrame<T> f = disk_disk_frame(dx, dy, ri, rj);
  const T affine_tx = Periodic ? k.rate_t1 * dx : T(0.0);
  const T affine_ty = Periodic ? k.rate_t2 * dy : T(0.0);
  const T dvx = vxj - vxi + affine_tx, dvy = vyj - vyi + affine_ty;
  const T rate = tangential_rate(f, dvx, dvy, omega_i, omega_j);
  const T affine_vx = Periodic ? k.rate_v1 * dx : T(0.0);
  const T affine_vy = Periodic ? k.rate_v2 * dy : T(0.0);
  const T h_rate = deflection_rate(f, vvxj - vvxi + affine_vx, vvyj - vvyi + affine_vy);
  const BasicContactForce<T> c =
      apply_law(T(k.k_n), T(k.k_t), T(k.mu), alpha, f.h, h_rate, delta_t, k.dt, rate);
  keep_state(c.delta_t, c.f_n, f.nx, f.ny);
  ClosedPair<T> out;
  out.fx = c.f_n * f.nx + c.f_t * f.tx;
  out.fy = c.f_n * f.ny + c.f_t * f.ty;
  // (was_closed first: for double the one test most closed pairs take.)
  const T share = select_lazy(
      was_closed, [] { return T(1.0); },
      [&] {
        return k.dt == 0.0 ? T(1.0)
                           : viscous_share_closing(f.h, deflection_rate(f, dvx, dvy), k.dt);
      });
  out.fvx = share * c.f_v * f.nx;
  out.fvy = share * c.f_v * f.ny;
  out.torque_i = -f.a_i * c.f_t;
  out.torque_j = -f.a_j * c.f_t;
  return out;
}

}  // namespace granstab::dynamic
