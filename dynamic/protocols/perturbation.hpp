#pragma once
// Random perturbation test (SPEC §3.5): from an equilibrium state under stress control, apply to
// every disk a constant external force with components uniform in [-f_0, f_0], run to the new
// equilibrium, record the strain changes; repeat with fresh draws.
#include <functional>
#include <random>

#include "equilibration.hpp"

namespace granstab::protocols {

struct PerturbationOptions {
  // Units of aP. In a periodic cell the mean of each component over the disks is subtracted
  // (a net force would accelerate the whole sample), so the applied forces slightly exceed f0.
  double f0 = 1e-3;
  int repetitions = 10;
  // Each draw replaces the previous forces and starts from the state the previous one left
  // (strains accumulate). With release, the forces are removed after each loaded equilibrium and
  // the sample is brought to equilibrium again: the remaining strain is the irreversible part.
  bool release = true;
  // A wait is abandoned (no equilibrium: the sample flows under the held stresses) when
  // epsilon_2 moves by more than this from its value before the draw.
  double failure_delta_epsilon_2 = 0.1;
  EquilibrationOptions equilibration;
};

struct PerturbationRecord {
  int draw = 0;
  double epsilon_2_before = 0.0, epsilon_v_before = 0.0;
  double delta_epsilon_2 = 0.0, delta_epsilon_v = 0.0;  // loaded equilibrium - before
  double delta_epsilon_2_released = 0.0, delta_epsilon_v_released = 0.0;  // released - before
  EquilibrationResult loaded, released;  // released: steps = 0 without release
};

// The engine's stage must be what the perturbations are applied under (stress control on both
// axes for SPEC §3.5). Returns false from on_record to stop early.
//
// Safe points: those of each wait, with control.cursor.index = the draw, phase = 1 (loaded) or 2
// (released), rng_state = the generator before the draw, values = the record so far
// (epsilon_2_before, epsilon_v_before, delta_epsilon_2, delta_epsilon_v, loaded steps, reached,
// aborted) and report = the loaded wait's report. control.resume continues that wait: the
// generator is set back and the draw repeated, which gives the same forces and generator state.
void run_perturbations(Engine& engine, const PerturbationOptions& options, std::mt19937_64& rng,
                       Configuration& state,
                       const std::function<bool(const Engine&, const Configuration&,
                                                const PerturbationRecord&)>& on_record,
                       const EquilibrationObserver& observer = {}, const LoopControl& control = {});

}  // namespace granstab::protocols
