#pragma once
// Static states handed to the dynamic engine (issue #6): the static solver's state at a load q
// written as a Configuration that the engine continues from, and a probe of its dynamic
// stability: hold q under SIC stress control (the creep hold of SPEC §3.4), then apply the random
// perturbations of SPEC §3.5 with release, and measure how far the state moves. A stable
// equilibrium stays within the strain uncertainty of the §3.1 tolerances (drivers/crosscheck.hpp,
// eps2_uncertainty); an unstable one rearranges. No physics here: the engine, the protocols and
// the measurements do the work.
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "common/configuration.hpp"
#include "crosscheck.hpp"
#include "dynamic/engine.hpp"
#include "dynamic/protocols/equilibration.hpp"
#include "static/network.hpp"
#include "static/q1.hpp"

namespace granstab::crosscheck {

// The static network as a configuration: positions wrapped into a periodic cell (contact images
// adjusted so that every branch vector is unchanged), rotations, contacts with their delta_t and
// statuses, the cell lengths; masses, inertias, cell masses and the stage's reference lengths from
// `start` (the state the static run began from); at rest, both lengths under stress control at the
// network's loads.
Configuration configuration_of_static_state(const statics::Network& net,
                                            const Configuration& start);

// Per disk: a rattler of the network (no degree of freedom) that overlaps another disk or a wall.
// The default static path never closes contacts with rattlers (docs/static.md), so these overlaps
// are forces the static state does not balance.
std::vector<char> overlapping_rattlers(const statics::Network& net, const Configuration& state);

// Moves each marked rattler (overlapping_rattlers) out of its overlaps, the other disks fixed:
// a rattler has no place in the static solution (any position in its cage is one), so the
// hybrid SIC hands the engine a state in which it touches nothing rather than one with forces
// the static state did not balance. Each push moves the rattler along the sum of its overlap
// normals by the overlaps (plus 1e-9 a), repeated until it is free (at most 100 times).
// Positions are wrapped back into a periodic cell and the rattler's contact images adjusted.
// Returns the number of marked rattlers still overlapping (a cage too small for the disk).
int push_out_rattlers(Configuration& state, const std::vector<char>& rattlers);

// The configuration without the marked disks (indices renumbered, their contacts dropped).
Configuration without_disks(const Configuration& config, const std::vector<char>& remove);

// The compare run's static stepping (same options as run_static_half) from `start`, stopped at the
// first state with load >= q (to round-off): result.network_at_q1 is that state, the last curve
// point its measurements. One run per state: compare and probe take their states from their own
// run instead (below); this is the reference the test of that checks against.
statics::StabilityResult static_run_to(const Configuration& start, const CrosscheckOptions& options,
                                       double q);

// Round-off of the static loads, sums of steps: a state within 1e-6 of the static step below q
// is the state at q (static_run_to stops there).
double static_load_tolerance(const CrosscheckOptions& options);

// statics::Q1Options::on_accepted that keeps, for each load q of `at`, a copy of the run's first
// accepted state with load >= q - tolerance: the state static_run_to(q) ends at. `states` (in load
// order, one per distinct state) must outlive the run.
std::function<void(double, const statics::Network&)> keep_static_states(
    std::vector<double> at, double tolerance, std::vector<StaticState>& states);

// The first of `states` (in load order) with load >= q - tolerance; nullptr when the run ended
// below q.
const StaticState* static_state_at(const std::vector<StaticState>& states, double q,
                                   double tolerance);

struct ProbeOptions {
  double f0 = 1e-4;  // perturbation forces, units of aP (SPEC §3.5); 0: hold only
  int draws = 3;
  std::uint64_t seed = 1;
  // The hold and every wait: the compare run's dynamic settings.
  protocols::EquilibrationOptions equilibration{{}, 200, 2'000'000};
  EngineOptions engine;
  bool remove_overlapping_rattlers = true;
};

// Probes `state` (a static state at load q, as configuration_of_static_state writes it; the
// overlapping rattlers of `remove` are taken out first when options say so).
ProbeResult probe_static_state(const Configuration& state, const std::vector<char>& remove,
                               double q, double bound_eps2, const ProbeOptions& options);

// The largest probed load below which every probed state is stable (probes in increasing q):
// NaN when the first one is unstable.
double stable_up_to(const std::vector<ProbeResult>& probes);

// compare --probe-states K: the static states of the compare run at q = k q1 / K (k = 1..K, on
// the static run's grid; k = K is the state at q1 itself), probed with options.probe. The states
// come from result.static_states (run_static_half keeps them when options.probe.states > 0).
std::vector<ProbeResult> probe_static_states(const CrosscheckResult& result,
                                             const CrosscheckOptions& options);

}  // namespace granstab::crosscheck
