#pragma once
// Rigid-limit bound of SPEC §4.5 / STATIC.md §S3.6: the largest deviator ratio q that admissible
// contact forces (F_N >= 0, |F_T| <= mu F_N) of a frozen contact network can balance, a linear
// program solved with Ipopt. It bounds the stability range from above: q_1 <= q_max.
// The LP, its normalisation and the handling of unbounded cases are described in docs/static.md
// ("Rigid-limit bound"). Ipopt stays out of this header (DEPS.md #9).
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "common/configuration.hpp"

namespace granstab::statics {

struct RigidLimitOptions {
  // sigma_1 = P of the returned force system, in units of P. The LP is homogeneous in the forces,
  // so q_max does not depend on it; only f_n, f_t scale with it.
  double sigma1 = 1.0;
  // Ipopt's convergence tolerance (its "tol", on the scaled NLP error).
  double tolerance = 1e-10;
  int max_iterations = 3000;
  // The normalised LP gives s1_min = sigma_1 / ((sigma_1 + sigma_2) / 2) at q_max, so
  // q_max = 2 / s1_min - 2; when s1_min falls below this threshold q_max is reported as +inf
  // (any q_max > 2 / threshold is indistinguishable from unbounded at the solver's accuracy).
  double unbounded_threshold = 1e-8;
  // Returned forces are re-checked against every balance row, recomputed from the configuration;
  // a larger violation (units of a sigma_1 for forces, a^2 sigma_1 for torques and A sigma rows)
  // is reported as a failure ("inaccurate: ...") rather than as a number.
  double residual_limit = 1e-7;
};

struct RigidLimitResult {
  // q_max = lambda*: finite when solved and bounded, +inf when unbounded, NaN on failure.
  double q_max = 0.0;
  bool solved = false;   // true for a finite optimum and for a proven unbounded q
  bool bounded = false;  // true when q_max is finite
  // "optimal", "unbounded", "infeasible: ...", or "ipopt: <return status>" on a solver failure.
  std::string status;

  // Per contact of config.contacts (zero for contacts outside the network: h <= 0, or removed as
  // carrying no force, see docs); the forces at q_max with sigma_1 = options.sigma1. F_T is the
  // tangential component of the force of i on j along t, as in common/contact_law.hpp.
  // Empty unless bounded.
  std::vector<double> f_n, f_t;
  // Per contact: 1 if it entered the LP (h > 0 and not removed), else 0.
  std::vector<std::uint8_t> in_lp;

  // Collapse mechanism (the LP's dual solution), empty unless bounded: per disk displacement
  // rates (mechanism_ux, mechanism_uy) and rotation rates (mechanism_theta), cell extension
  // rates (mechanism_e, L_a -> L_a (1 + e_a); with walls, wall displacement / L_a), normalised to
  // e_2 = -1 (unit axial compression rate; should Ipopt return a degenerate dual with e_2 >= 0,
  // the raw multipliers are left as they are). It is kinematically admissible for associated flow:
  // at every network contact the opening rate g_N and slip rate g_T obey g_N >= mu |g_T|.
  // Disks without a balance row (rattlers, removed disks) and undetermined components (a pinned
  // translation, rotations of frictionless disks) are reported as 0.
  std::vector<double> mechanism_ux, mechanism_uy, mechanism_theta;
  std::vector<double> mechanism_e;

  // Size of the LP actually solved, and the largest violation of force, torque and stress
  // balance by the returned forces (units of a sigma_1, or a^2 sigma_1 for torques and A sigma
  // rows; a = largest diameter).
  std::size_t n_disks = 0;     // disks with balance rows
  std::size_t n_contacts = 0;  // network contacts that entered the LP
  int iterations = 0;          // Ipopt iterations, summed over the solves
  double max_residual = 0.0;
};

// Throws std::invalid_argument on an inconsistent configuration (contact indices out of range,
// wall contacts in a periodic cell, image shifts in a walled cell, sigma1 <= 0).
RigidLimitResult rigid_limit(const Configuration& config, const RigidLimitOptions& options = {});

// Every Ipopt call in the process must hold this lock: Debian's sequential MUMPS is not
// thread-safe (DEPS.md #5). rigid_limit() takes it itself.
std::mutex& ipopt_mutex();

}  // namespace granstab::statics
