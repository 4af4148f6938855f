#pragma once
#include "common/io/json_text.hpp"
// Cross-check of the static method and the dynamic SIC procedure (SPEC §5, STATIC.md §S4 T10):
// both run from the same equilibrium state with the same delta q; their equilibrium curves are
// matched at the same prescribed q and compared. No physics lives here: the static curve comes
// from static/q1.hpp, the dynamic one from dynamic/protocols/biaxial.hpp, and every measurement
// from common/measurements.hpp.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/configuration.hpp"
#include "dynamic/engine.hpp"
#include "dynamic/protocols/equilibration.hpp"
#include "dynamic/protocols/loop_hooks.hpp"
#include "static/q1.hpp"
#include "static/rigid_limit.hpp"

namespace granstab::crosscheck {

// The dynamic stability probe of one static state (drivers/stability_probe.hpp).
struct ProbeResult {
  double q = 0.0;            // load of the static state
  int rattler_overlaps = 0;  // rattlers overlapping a disk or wall in the static state
  int removed_rattlers = 0;
  double initial_max_net_force = 0.0;  // as the engine sees the exported state (non-rattlers)
  double initial_stress_error = 0.0;   // largest relative stress error of that state
  bool hold_reached = false;
  std::uint64_t hold_steps = 0;
  double hold_d_eps2 = 0.0, hold_d_epsv = 0.0;  // hold end - static state
  int draws_reached = 0;
  std::uint64_t perturbation_steps = 0;
  double max_loaded_d_eps2 = 0.0;                 // max over draws of |loaded - before|
  double max_released_d_eps2 = 0.0;               // max over draws of |released - before|
  double final_d_eps2 = 0.0, final_d_epsv = 0.0;  // last state - static state
  double bound_eps2 = std::numeric_limits<double>::quiet_NaN();
  // Every wait reached equilibrium and |final_d_eps2| <= bound_eps2 (and the hold moved no more).
  bool stable = false;
};

struct ProbeSettings {
  int states = 0;    // compare --probe-states K: probe K static states up to q1 (0: none)
  double f0 = 1e-4;  // perturbation forces (SPEC 3.5), units of aP; 0: hold only
  int draws = 2;
  std::uint64_t seed = 1;
  bool remove_overlapping_rattlers = true;
};

struct CrosscheckOptions {
  double dq = 1e-3;  // the one delta q of both methods
  // Highest q of both runs. Infinite: the static run goes to q1, the dynamic one
  // steps_after_q1 increments beyond it (to show where the curves part).
  double q_max = std::numeric_limits<double>::infinity();
  int steps_after_q1 = 3;
  // Friction of the biaxial stage, used by both methods (SPEC §3.2: it may differ from mu_prep).
  // NaN: the sample's material.mu.
  double mu = std::numeric_limits<double>::quiet_NaN();
  // Dynamic SIC: wait for equilibrium (SPEC §3.1 tolerances) after each increment.
  protocols::EquilibrationOptions equilibration{{}, 200, 2'000'000};
  double epsilon_2_max = 0.05;  // the dynamic run stops when the sample flows beyond this
  // The dynamic run applies each delta q as this many stress steps of delta q / n, each waited
  // for equilibrium, and records the states at q = k delta q only: a staircase ramp that shrinks
  // the transient overshoot of a stress step (docs/user-guide.md); 1 is SPEC §3.3 SIC with delta q.
  int dynamic_substeps = 1;
  // The static run steps by delta q / n (its states at q = k delta q are the ones compared): it
  // shrinks the static path error of one linear predictor per step with status changes inside.
  int static_substeps = 1;
  ProbeSettings probe;
  EngineOptions engine;
  // Static stepping (its dq is set from dq above).
  statics::Q1Options statics;
  bool rigid_limit = true;  // also compute q_max of the initial network (SPEC §4.5)
};

// One recorded state of the dynamic SIC run (SPEC §2 measurements of the exported state).
struct DynamicPoint {
  double q_target = 0.0;  // prescribed q = k dq
  double q = 0.0;         // measured (sigma_22 - sigma_11) / sigma_11
  double eps1 = 0.0, eps2 = 0.0, epsv = 0.0;
  std::size_t n_sliding = 0;
  std::uint64_t steps = 0;  // MD steps of this increment
  bool reached = false;     // SPEC §3.1 equilibrium reached
  double max_net_force = 0.0, max_net_torque = 0.0;
  double stress_error_1 = 0.0, stress_error_2 = 0.0;
};

struct DynamicRun {
  std::vector<DynamicPoint> curve;
  std::string stop_reason;  // "q_max", "no equilibrium", "epsilon_2_max"
  std::uint64_t steps = 0;
  // MD steps since the last recorded state (the substeps in between): with the curve, the part
  // of a checkpoint that is the run's own (dynamic_run_state below).
  std::uint64_t steps_since_record = 0;
};

// The dynamic point matched to a static state at the same prescribed q.
struct MatchedPoint {
  double q = 0.0;
  double eps2_static = 0.0, eps2_dynamic = 0.0;
  double epsv_static = 0.0, epsv_dynamic = 0.0;
  double eps1_static = 0.0, eps1_dynamic = 0.0;
  bool interpolated = false;  // no static state at exactly this q: linear interpolation
  // Strain uncertainty of the dynamic state allowed by the SPEC §3.1 tolerances (bound_eps2).
  double bound_eps2 = 0.0;
};

struct Comparison {
  std::vector<MatchedPoint> points;  // dynamic equilibria with 0 < q <= q1
  int n_steps_compared = 0;
  int n_interpolated = 0;
  double max_abs_diff_eps2 = 0.0;  // below q1
  double max_rel_diff_eps2 = 0.0;  // |diff| / |eps2_static|
  double max_abs_diff_epsv = 0.0;
  double max_abs_diff_eps1 = 0.0;
  double max_diff_over_bound_eps2 = 0.0;  // max over points of |diff eps2| / bound_eps2
  // eps2_dynamic - eps2_static at that point: which path strained more (NaN: nothing compared).
  double diff_eps2_at_max = std::numeric_limits<double>::quiet_NaN();
  // First static state with a sliding contact (NaN if none below q1), and the ratio above over the
  // matched states before it: sliding contacts are where the dynamic path (transient overshoot
  // after each stress step) can slip more than the quasistatic one (docs/user-guide.md).
  double q_first_static_sliding = std::numeric_limits<double>::quiet_NaN();
  double max_diff_over_bound_eps2_before_sliding = 0.0;
  int n_compared_before_sliding = 0;
  // First dynamic increment past q1: its strain jump eps2(q_k) - eps2(q_k - dq), and the same
  // jump on average over the dynamic increments below q1 (for scale).
  double dynamic_jump_after_q1 = std::numeric_limits<double>::quiet_NaN();
  double q_of_jump = std::numeric_limits<double>::quiet_NaN();
  bool jump_reached_equilibrium = false;
  double mean_dynamic_step_below_q1 = std::numeric_limits<double>::quiet_NaN();
  // The largest dynamic increment below q1 and its q (k dq): a rearrangement of the dynamic run
  // that the static path did not meet, or met within one dq of q1, so that the jump past q1 is
  // ordinary (issue #6: mu = 0.15, dq = 1e-3, 32 times the mean at q = 0.283 < q1 = 0.28339).
  double max_dynamic_step_below_q1 = std::numeric_limits<double>::quiet_NaN();
  double q_of_max_dynamic_step = std::numeric_limits<double>::quiet_NaN();
};

// Strain uncertainty that the SPEC §3.1 tolerances leave in an equilibrium state
// (docs/user-guide.md, "How close must the curves be"): the controlled stresses may be off by tol_s
// sigma_a, and net disk forces up to f_tol act like a stress error of order f_tol / a; through the
// macroscopic compliance S (d eps / d sigma, from the static curve; S_21 = S_12 by reciprocity)
// this gives
//   bound_eps2 = (|S_21| sigma_1 + |S_22| sigma_2) tol_s + (|S_21| + |S_22|) f_tol / a.
double eps2_uncertainty(double s21, double s22, double sigma1, double sigma2,
                        const EquilibriumTolerances& tolerances);

// bound_eps2 at the static state of `curve` nearest to load q, as compare_curves computes it.
double static_bound_eps2(const std::vector<statics::CurvePoint>& curve, double q, double sigma1,
                         const EquilibriumTolerances& tolerances);

// Matches the curves at the same prescribed q (static states are at the load q; step cuts of the
// static run near q1 give extra states, and the dynamic q = k dq then falls between two of them:
// linear interpolation, counted). Pure function of its inputs.
Comparison compare_curves(const std::vector<statics::CurvePoint>& static_curve, double q1,
                          const std::vector<DynamicPoint>& dynamic_curve, double sigma1,
                          const EquilibriumTolerances& tolerances);

// The common starting state of both methods: the sample with the biaxial friction mu, the
// strains measured from its current lengths, sigma_1 = sigma_2 = the sample's prescribed pressure
// under stress control. Throws std::invalid_argument when the sample is not under an isotropic
// stress-controlled stage or mu is not a finite number >= 0.
Configuration biaxial_start(const Configuration& sample, double mu);
// The same checks without the copy (for read_static_start's `require`).
void require_biaxial_start(const Configuration& sample);

// Dynamic SIC from the start state: q = k dq up to q_end (inclusive, to round-off), appended to
// `run` (empty at a start). Safe points (control.hooks) are those of run_stress_steps; at each,
// `run` holds the curve so far, so the engine's state, the cursor and `run` are all a resume
// needs: with control.resume, `from` is that engine state and `run` the stored curve, and the run
// continues to the bit (docs/reliability.md).
void run_dynamic(const Configuration& from, const CrosscheckOptions& options, double q_end,
                 DynamicRun& run, const protocols::LoopControl& control = {});

// The dynamic run's own state in a checkpoint (curve and steps since the last record; numbers as
// shortest round-trip decimals), and back. Throws std::runtime_error on a damaged text.
std::string dynamic_run_state(const DynamicRun& run);
DynamicRun parse_dynamic_run_state(const std::string& text);

// One accepted state of a static run (statics::Q1Options::on_accepted) and its load.
struct StaticState {
  double load = 0.0;
  statics::Network network;
};

struct CrosscheckResult {
  Configuration start;
  double mu = 0.0;
  double pressure = 1.0;
  statics::StabilityResult statics;
  statics::RigidLimitResult rigid;
  DynamicRun dynamic;
  Comparison comparison;
  double static_seconds = 0.0, dynamic_seconds = 0.0, rigid_seconds = 0.0;
  // With probe.states > 0: every accepted state of the static run, in load order (a copy of the
  // network each: 7 MB for the 835 states to q1 at N = 100, mu = 0.5), from which
  // probe_static_states takes its states once q1 is known instead of running the stepping again.
  std::vector<StaticState> static_states;
  std::vector<ProbeResult> probes;  // compare --probe-states
  double probe_seconds = 0.0;
};

// Runs both methods and compares them. Throws std::invalid_argument on bad options or sample.
// The three parts below in order; `granstab compare` calls them itself to checkpoint the
// dynamic half.
CrosscheckResult run_crosscheck(const Configuration& sample, const CrosscheckOptions& options);

// The static half: the start state, the static curve to q1 and the rigid limit (result.dynamic
// and result.comparison stay empty). Deterministic: the same sample and options give the same
// bits.
CrosscheckResult run_static_half(const Configuration& sample, const CrosscheckOptions& options);
// The highest q of the dynamic half: options.q_max, or steps_after_q1 increments beyond the
// static q1 when q_max is infinite.
double dynamic_q_end(const CrosscheckResult& static_half, const CrosscheckOptions& options);
// result.comparison from both curves.
void compare_halves(CrosscheckResult& result, const CrosscheckOptions& options);

// --- outputs (strings; the driver writes each through write_file_atomically) -----------------
// The static curve in the format of `granstab q1` (static_curve.csv).
std::string static_curve_csv(const statics::StabilityResult& result);
std::string dynamic_curve_csv(const DynamicRun& run);
// Matched points with their differences and bound (matched.csv).
std::string matched_csv(const Comparison& comparison);
// The sample at q1 for pictures: disks (x, y, r, rattler) and contacts (centres, f_n, f_t,
// sliding), from the static network at q1 through common/measurements.hpp.
std::string disks_at_q1_csv(const statics::StabilityResult& result);
std::string network_at_q1_csv(const statics::StabilityResult& result);
// The same two files of any state (the hybrid SIC's rearrangements).
std::string disks_csv(const Configuration& state);
std::string network_csv(const Configuration& state);
// The unstable mode at q1, one row per disk (ux, uy, theta), then e1, e2 (format of `granstab q1`).
std::string mode_csv(const statics::StabilityResult& result);

struct JsonContext {
  std::string sample;
  double dq = 0.0, q_max = 0.0;
  std::string start_fields;  // lines "  \"key\": value,\n" about the start (static_start.hpp)
};
std::string compare_json(const JsonContext& context, const CrosscheckOptions& options,
                         const CrosscheckResult& result);

// JSON number (shortest round trip; null for inf / nan) and string.
using granstab::json_number;
using granstab::json_string;

}  // namespace granstab::crosscheck
