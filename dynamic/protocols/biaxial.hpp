#pragma once
// Biaxial compression (SPEC §3.3): sigma_1 = P held by stress control on axis 1 (index 0) while
// axis 2 (index 1, the axial direction) is loaded either at a constant strain rate (SRC) or by
// stress increments with a wait for equilibrium after each (SIC).
#include <cstdint>
#include <functional>
#include <string>

#include "equilibration.hpp"

namespace granstab::protocols {

// Switches the engine to the biaxial stage: the biaxial material (its mu may differ from the
// preparation's), strains measured from the current lengths, sigma_1 = sigma_2 = pressure under
// stress control (the loading of axis 2 is set by the SRC / SIC functions).
void begin_biaxial_stage(Engine& engine, const Material& material, double pressure = 1.0);

// epsilon_2 = 1 - L_2 / L_20 and q = (sigma_22 - sigma_11) / sigma_11 of the engine's current
// state (contact stress, SPEC §2), cheap: no export.
double axial_strain(const Engine& engine);
double deviator_ratio(const Engine& engine);

// --- SRC --------------------------------------------------------------------------------------
struct StrainRateOptions {
  double gamma = 1e-4;            // d epsilon_2 / dt in units of sqrt(P/m) (SPEC §1.2)
  double record_interval = 1e-4;  // strain between two recorded states
};

// Called with the exported state at every recorded strain; returns false to stop the run.
using StateObserver = std::function<bool(const Engine&, const Configuration&)>;
// Called after every step (cheap checks on the engine); returns true to stop the run.
using StepCondition = std::function<bool(const Engine&)>;

struct StrainRateResult {
  std::uint64_t steps = 0;
  bool stopped = false;  // by on_record or stop_when, before epsilon_2_end
};

// Imposes d epsilon_2 / dt = gamma (times sqrt(P/m) = 1) with sigma_1 held, from the current
// state until epsilon_2 >= epsilon_2_end. on_record sees the first state at or beyond each
// multiple of record_interval, and the final state.
//
// Safe points (control.hooks): after every step that does not end the run, past its record if
// any, with control.cursor's steps = steps of this call and next_record = the strain of the next
// record. control.resume continues from there (the engine's stage is already the SRC one).
// control.check sees every state before on_record.
StrainRateResult run_strain_rate(Engine& engine, const StrainRateOptions& options,
                                 double epsilon_2_end, double pressure, Configuration& state,
                                 const StateObserver& on_record,
                                 const StepCondition& stop_when = {},
                                 const LoopControl& control = {});

// --- SIC --------------------------------------------------------------------------------------
struct StressStepOptions {
  double delta_q = 1e-2;
  double q_max = 1.0;
  // The sample is taken to have failed (q above its peak: it flows) when epsilon_2 grows beyond
  // this during one increment, or when no equilibrium comes within equilibration.max_steps.
  double epsilon_2_max = 0.2;
  EquilibrationOptions equilibration;
};

struct StressStepRecord {
  double q_target = 0.0;
  std::uint64_t steps = 0;  // steps of this increment
  EquilibrationResult equilibrium;
};

struct StressStepResult {
  int increments = 0;       // increments that reached equilibrium (q = increments * delta_q)
  std::uint64_t steps = 0;  // all steps
  std::string stop_reason;  // "q_max", "no equilibrium", "epsilon_2_max"
};

// Starting from the current state (first brought to equilibrium at q = 0 and recorded), raises
// sigma_2 = P (1 + q) with q = k delta_q, k = 1, 2, ..., and waits for equilibrium after each
// step. on_equilibrium sees every recorded equilibrium state (and the last, failed one, whose
// record has equilibrium.reached = false); progress sees every check.
//
// Safe points (control.hooks): those of each wait (run_to_equilibrium), with control.cursor's
// index = k and done_steps = the steps of the increments before k. control.resume continues that
// wait.
StressStepResult run_stress_steps(
    Engine& engine, const StressStepOptions& options, double pressure, Configuration& state,
    const std::function<void(const Engine&, const Configuration&, const StressStepRecord&)>&
        on_equilibrium,
    const EquilibrationObserver& progress = {}, const LoopControl& control = {});

}  // namespace granstab::protocols
