#pragma once
// Static states handed to the dynamic engine (issue #6): the static solver's state at a load q
// written as a Configuration that the engine continues from, and a probe of its dynamic
// stability: hold q under SIC stress control (the creep hold of SPEC §3.4), then apply the random
// perturbations of SPEC §3.5 with release, and measure how far the state moves. A stable
// equilibrium stays within the strain uncertainty of the §3.1 tolerances (drivers/crosscheck.hpp,
// eps2_uncertainty); an unstable one rearranges. No physics here: the engine, the protocols and
// the measurements do the work.
#include <cstdint>
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

// The configuration without the marked disks (indices renumbered, their contacts dropped).
Configuration without_disks(const Configuration& config, const std::vector<char>& remove);

// The compare run's static stepping (same options as run_static_half) from `start`, stopped at the
// first state with load >= q (to round-off): result.network_at_q1 is that state, the last curve
// point its measurements.
statics::StabilityResult static_run_to(const Configuration& start, const CrosscheckOptions& options,
                                       double q);

struct ProbeOptions {
  double f0 = 1e-4;  // perturbation forces, units of aP (SPEC §3.5); 0: hold only
  int draws = 3;
  std::uint64_t seed = 1;
  // The hold and every wait: the compare run's dynamic settings.
  protocols::EquilibrationOptions equilibration{{}, 200, 2'000'000};
  EngineOptions engine;
  bool remove_overlapping_rattlers = true;
};

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

// Probes `state` (a static state at load q, as configuration_of_static_state writes it; the
// overlapping rattlers of `remove` are taken out first when options say so).
ProbeResult probe_static_state(const Configuration& state, const std::vector<char>& remove,
                               double q, double bound_eps2, const ProbeOptions& options);

// The largest probed load below which every probed state is stable (probes in increasing q):
// NaN when the first one is unstable.
double stable_up_to(const std::vector<ProbeResult>& probes);

}  // namespace granstab::crosscheck
