#pragma once
// Static stepping along a load path up to the loss of stability of the contact network
// (SPEC §4, STATIC.md §S3.3-§S3.4): the equilibrium curve, q1 bracketed to the step floor, the
// criterion that fired, the sliding contacts there and the unstable mode.
#include <array>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/configuration.hpp"
#include "static/load_step.hpp"

namespace granstab::statics {

enum class Control { stress, strain };

// §S3.3 step control. fixed: steps of dq, halved on failure and grown back to dq. adaptive: the
// same, and between status events steps beyond dq, to the multiple of dq before the next event
// predicted from the contact force rates (at most max_step_factor dq), while the stability
// indicators stay away from 0; an attempt above dq that changes a status is bisected, so events
// are crossed by steps of dq at most and q1 is bracketed as with fixed steps (docs/static.md).
enum class StepControl { fixed, adaptive };
const char* step_control_name(StepControl s);

// Which §S3.4 criterion ended the run.
enum class Criterion {
  none,         // the run stopped at load_stop or max_steps while stable
  existence,    // (a) no consistent equilibrium state down to the step floor
  bifurcation,  // (b) det K(active set) <= 0 on the consistent branch
};
const char* criterion_name(Criterion c);

// What the stepping reports after each attempt, for progress lines (drivers/static_progress.hpp).
struct StepProgress {
  double load = 0.0;      // the load parameter of the last accepted state
  int states = 0;         // accepted states so far, the start included
  int attempts = 0;       // steps tried (accepted + cut)
  int n_sliding = 0;      // sliding contacts at the last accepted state
  double step = 0.0;      // the current step of the load parameter
  bool finished = false;  // the last call, once the run has ended
  bool quiet = false;     // the last accepted step changed no contact status
};

struct CurvePoint;

struct Q1Options {
  double dq = 1e-3;      // step of the load parameter (q; epsilon_2 under strain control)
  double dq_min = 1e-7;  // step floor: q1 is bracketed to [q, q + 2 dq_min) at worst
  Control control = Control::stress;
  StepControl steps = StepControl::adaptive;
  double max_step_factor = 32.0;  // adaptive: the largest step, in units of dq
  int max_steps = 1000000;        // accepted steps (adaptive ones may span several dq)
  double load_stop = std::numeric_limits<double>::infinity();  // stop once the parameter passes it
  // Log the Hill indicator at the start and at every hill_every-th accepted state (0: never). It
  // is an indicator only: no decision depends on it, so the path is the same at any stride.
  std::size_t hill_every = 10;
  // Criterion (b) also fires when K(active set) has real negative eigenvalues with det K > 0 (an
  // even number crossed zero within one step): one LDL^T of (K + K^T)/2 per state, plus a few
  // shift-invert Arnoldi solves with the state's LU when that is indefinite.
  bool count_negative_eigenvalues = true;
  SolverOptions solver;
  // Called with every accepted state: the start once prepared, then the state after each accepted
  // step, with its load parameter; it is the state the run would return as network_at_q1 if it
  // stopped there (load_stop), so a caller can hand states of one run to other solvers instead of
  // re-running the stepping to each (drivers/stability_probe.hpp). A callback rather than a list
  // of loads to copy: compare picks its states at fractions of q1, known only once the run has
  // ended, while `granstab probe --at` knows its loads in advance; each keeps what it needs. It
  // sees the state read-only and does not change the stepping; unset, it costs one test per step.
  std::function<void(double load, const Network& net)> on_accepted;
  // Called after the start and after every attempt; unset, it costs one test per attempt.
  std::function<void(const StepProgress&)> on_progress;
  // Called with the curve point of every accepted step; true ends the run there as if it had
  // passed load_stop (criterion none): a stop on a measured quantity, e.g. the hybrid SIC's
  // epsilon_2 target (drivers/hybrid_sic.hpp).
  std::function<bool(const CurvePoint&)> stop_when;
};

struct CurvePoint {
  double load = 0.0;  // the load parameter (q prescribed, or epsilon_2 imposed)
  double q = 0.0;     // measured (sigma2 - sigma1) / sigma1 from the contact forces
  double eps1 = 0.0, eps2 = 0.0, epsv = 0.0;
  int n_sliding = 0;
  double hill = std::numeric_limits<double>::quiet_NaN();
  int determinant_sign = 0;      // of K on the consistent statuses of the next increment
  int negative_eigenvalues = 0;  // real negative eigenvalues of that K (-1: not counted)
  int newton_iterations = 0;
  int new_contacts = 0;
  // A row at a multiple of dq inside an adaptive step that changed no status: the columns above
  // interpolated linearly between the two accepted states around it (no solve at this load).
  bool interpolated = false;
};

struct SlidingContact {
  int i, j, k1, k2;
  double f_n, f_t;
};

// How far the §S3.0 polish moved the start to equilibrium (what --polish reports).
struct StartPolish {
  double max_displacement = 0.0;  // largest disk displacement, units of a
  std::size_t max_displacement_disk = 0;
  double max_rotation = 0.0;                           // largest disk rotation, radians
  double max_strain = 0.0;                             // largest |Delta L_a / L_a|
  double residual_before = 0.0, residual_after = 0.0;  // relative residuals of the polish
};

struct StabilityResult {
  std::vector<CurvePoint> curve;
  double q1 = 0.0;                     // last stable value of the load parameter
  std::array<double, 2> q1_bracket{};  // the loss of stability lies in [lo, hi]
  Criterion criterion = Criterion::none;
  std::string detail;  // the failure behind the criterion
  std::vector<SlidingContact> sliding_at_q1;
  // Unstable mode at q1 (per disk ux, uy, theta; then e1, e2): the eigenvector of K(active set)
  // with the smallest |eigenvalue|, by inverse iteration; near the bracket it is the null vector.
  std::vector<double> mode;
  std::array<double, 2> mode_cell{0.0, 0.0};
  // Per disk: 1 when the mode has degrees of freedom on it. Rattlers (also those created by the
  // statuses of the check) have none and a zero entry in mode that is no displacement.
  std::vector<char> mode_disk_active;
  Network network_at_q1;
  StartPolish polish;
  Timings timings;
  int steps = 0;              // accepted steps (the curve's rows that are not interpolated, less 1)
  int attempts = 0;           // steps tried: accepted + rejected
  int interpolated_rows = 0;  // rows of curve marked interpolated
  StepControl step_control = StepControl::fixed;  // the one of the run
  std::map<std::string, int> rejected;            // attempts cut by step control, by reason
};

// §S3.0 on net (statics::prepare: rattlers, dofs, the equilibrium polished) and how far it moved.
StartPolish polish_start(Network& net, const SolverOptions& options);

// Generic stepping from an equilibrium network (prepared here) along a load path.
// reference_length is the stage's reference for the strains.
StabilityResult trace_to_instability(Network net, double lambda0, const LoadPath& path,
                                     const std::array<double, 2>& reference_length,
                                     const Q1Options& options);

// Biaxial test of SPEC §3.3 by static means: sigma1 = stage sigma1 fixed, sigma2 = sigma1 (1 + q)
// raised by dq (stress control), or epsilon_2 raised by dq with the e2 direction imposed (strain
// control). Starts from the configuration's equilibrium under its stage stresses.
StabilityResult find_q1(const Configuration& config, const Q1Options& options);

}  // namespace granstab::statics
