#pragma once
// Run to equilibrium (SPEC §3.1, issue #4): step the engine and check the criterion of
// common/equilibrium.hpp every `check_interval` steps, up to a step budget. Every protocol waits
// for equilibrium through this one function.
#include <cstdint>
#include <functional>
#include <span>

#include "common/configuration.hpp"
#include "common/equilibrium.hpp"
#include "dynamic/engine.hpp"
#include "loop_hooks.hpp"

namespace granstab::protocols {

struct EquilibrationOptions {
  EquilibriumTolerances tolerances;
  std::uint64_t check_interval = 200;    // steps between two checks
  std::uint64_t max_steps = 10'000'000;  // guard: give up after this many steps
};

struct EquilibrationResult {
  bool reached = false;
  bool aborted = false;      // the observer asked to stop
  std::uint64_t steps = 0;   // steps run by this call
  EquilibriumReport report;  // at the last check
};

// Called after every check with the exported state and its report (progress, records); returns
// false to abort the run (e.g. a strain guard: the sample flows, no equilibrium will come).
using EquilibrationObserver =
    std::function<bool(const Engine&, const Configuration&, const EquilibriumReport&)>;

// Checks first (a state already in equilibrium costs no step), then steps in chunks of
// check_interval. `state` receives the exported configuration of the last check (its storage is
// reused across checks). With constant external forces applied to the engine (SPEC §3.5), pass
// them as external_fx / external_fy so that the force test sees the full load.
EquilibrationResult run_to_equilibrium(Engine& engine, const EquilibrationOptions& options,
                                       Configuration& state,
                                       const EquilibrationObserver& observer = {},
                                       std::span<const double> external_fx = {},
                                       std::span<const double> external_fy = {},
                                       const LoopControl& control = {});
// Safe points (control.hooks): after every check that neither ended nor aborted the wait, with
// control.cursor whose steps are the steps of this wait so far. A resumed wait (control.resume)
// continues after that check: it steps first, within the budget max_steps - cursor.steps.
// control.check sees every state before it is checked.

// The SPEC §3.1 check of a state loaded by constant external forces on the disks (besides the
// contacts): common/equilibrium.hpp for torques and stresses, and the force test on the net
// force contacts + external over the non-rattler disks. Without external forces this is
// check_equilibrium itself.
EquilibriumReport check_loaded_equilibrium(const Configuration& state,
                                           const EquilibriumTolerances& tolerances,
                                           std::span<const double> external_fx,
                                           std::span<const double> external_fy);

}  // namespace granstab::protocols
