#pragma once
// Hybrid SIC (issue #24): a stress-increment biaxial test (SPEC §3.3) that steps q with the static
// method inside each stability interval of the contact network and hands over to the MD engine
// only across the rearrangements between them. From an equilibrium state the static stepping
// runs to its loss of stability (static/q1.hpp); the last stable state, with sigma_2 raised to
// the next increment q = k dq, goes to the engine (SIC settings, SPEC §3.1 tolerances), which
// either reaches the next equilibrium, the start of the next static interval, or does not (the
// sample fails). The same function runs the pure dynamic SIC (every increment by MD) as the
// reference the hybrid is judged against. No physics lives here: the stepping, the engine and
// the measurements do the work; this file only decides who takes the next increment.
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "common/configuration.hpp"
#include "dynamic/engine.hpp"
#include "dynamic/protocols/checkpoint.hpp"
#include "dynamic/protocols/equilibration.hpp"
#include "static/q1.hpp"

namespace granstab::hybrid {

struct SicOptions {
  double dq = 1e-2;  // the increment of q of the dynamic steps, and the static step
  // The run ends at the first state with q >= q_max or epsilon_2 >= epsilon_2_end.
  double q_max = std::numeric_limits<double>::infinity();
  double epsilon_2_end = 0.01;
  // Failure: an MD wait aborts when epsilon_2 passes this (the sample flows), or gets no
  // equilibrium within equilibration.max_steps.
  double epsilon_2_max = 0.2;
  bool hybrid = true;  // false: every increment by MD (pure dynamic SIC, SPEC §3.3)
  protocols::EquilibrationOptions equilibration{{}, 200, 2'000'000};
  EngineOptions engine;
  statics::Q1Options statics;  // its dq, load_stop and stop_when are set from the above
};

enum class Method { static_stepping, dynamics };
const char* method_name(Method m);  // "static", "dynamic"

// One equilibrium state of the curve.
struct SicPoint {
  Method method = Method::dynamics;
  double q_target = 0.0;  // prescribed q (the static load parameter, or k dq for MD)
  double q = 0.0;         // measured from the contact forces
  double eps1 = 0.0, eps2 = 0.0, epsv = 0.0;
  int n_sliding = 0;
  int interval = 0;            // stability interval (static) or rearrangement (MD) index
  std::uint64_t md_steps = 0;  // MD steps of this increment (0 for static states)
  bool on_grid = true;         // q_target a multiple of dq (static cuts near q1 are not)
  bool reached = true;         // SPEC §3.1 equilibrium reached (false: the failed last one)
  bool interpolated = false;   // a static state interpolated inside an adaptive step (Q1Options::steps)
};

// A stretch of static states: from its start (an MD equilibrium, or the sample) to the last
// stable state.
struct StabilityInterval {
  double q_start = 0.0, q_end = 0.0;  // q_end: the static q1 of the interval
  double eps2_start = 0.0, eps2_end = 0.0;
  int states = 0;              // accepted static states, the start included
  std::string end;             // the criterion that ended it, or "target" / "start refused: ..."
  double polish_strain = 0.0;  // how far the static polish moved the start (max |dL/L|)
  double polish_displacement = 0.0;
};

// The MD increments between two intervals: from the last stable state to the next equilibrium.
struct Rearrangement {
  double q_from = 0.0, q_to = 0.0;             // the last stable q, and the increment's k dq
  double eps2_before = 0.0, eps2_after = 0.0;  // eps2_after - eps2_before: the strain jump
  std::uint64_t md_steps = 0;
  int rattlers_freed = 0;  // overlapping rattlers moved out before the MD (push_out_rattlers)
  bool reached = false;
  Configuration before, after;  // the states on both sides (pictures of the largest jumps)
};

struct SicResult {
  std::vector<SicPoint> curve;
  std::vector<StabilityInterval> intervals;
  std::vector<Rearrangement> rearrangements;
  std::string stop_reason;  // "epsilon_2_end", "q_max", "no equilibrium", "epsilon_2_max"
  std::uint64_t md_steps = 0;
  int static_states = 0;
  double static_seconds = 0.0, dynamic_seconds = 0.0;
  Configuration final_state;
};

// Called after every static state and every MD check: (q, epsilon_2, method) for progress lines.
using SicObserver = std::function<void(double q, double eps2, Method method)>;

// Where a run stands after an MD equilibrium that does not end it (a restart point): all that a
// restart needs to continue to the bit. Rearrangements keep their `before` / `after` states only
// while they are among the `keep` largest jumps so far (the ones that can still be pictured).
struct SicRestart {
  Configuration current;  // that equilibrium
  double q = 0.0;         // its prescribed q
  int next = 0;           // the next interval (hybrid) or increment (dynamic)
  SicResult so_far;       // final_state and stop_reason unset
};
using RestartObserver = std::function<void(const SicRestart&)>;

// The biaxial SIC from `start` (an equilibrium under isotropic stress control, strains measured
// from its lengths: crosscheck::biaxial_start). Throws std::invalid_argument on bad options.
// on_restart_point sees every restart point; with `resume` (one of them, of a run with the same
// start and options) the run continues from there and ends with the bits of an uninterrupted
// run (seconds aside).
SicResult run_sic(const Configuration& start, const SicOptions& options,
                  const SicObserver& observer = {}, const RestartObserver& on_restart_point = {},
                  const SicRestart* resume = nullptr);

// A restart point in checkpoint entries named sic.*, keeping the states of the `keep` largest
// jumps, and back (throws std::runtime_error naming the checkpoint on a damaged entry).
void put_restart(protocols::Checkpoint& checkpoint, const SicRestart& restart, std::size_t keep);
SicRestart get_restart(const protocols::Checkpoint& checkpoint);

// The next SIC target above q: the smallest k dq > q (to round-off 1e-9 dq).
double next_increment(double q, double dq);

}  // namespace granstab::hybrid
