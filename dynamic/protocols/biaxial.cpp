#include "biaxial.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace granstab::protocols {

void begin_biaxial_stage(Engine& engine, const Material& material, double pressure) {
  engine.set_material(material);
  engine.set_reference_lengths_to_current();
  engine.set_stress_control(0, pressure);
  engine.set_stress_control(1, pressure);
}

double axial_strain(const Engine& engine) {
  return 1.0 - engine.length()[1] / engine.stage().reference_length[1];
}

double deviator_ratio(const Engine& engine) {
  const auto sigma = engine.stress();
  return (sigma[1][1] - sigma[0][0]) / sigma[0][0];
}

StrainRateResult run_strain_rate(Engine& engine, const StrainRateOptions& options,
                                 double epsilon_2_end, double pressure, Configuration& state,
                                 const StateObserver& on_record, const StepCondition& stop_when,
                                 const LoopControl& control) {
  if (!(options.gamma > 0.0)) throw std::invalid_argument("SRC: gamma must be > 0");
  if (!(options.record_interval > 0.0)) {
    throw std::invalid_argument("SRC: record interval must be > 0");
  }
  StrainRateResult result;
  Cursor cursor = control.cursor;
  double next = 0.0;
  if (control.resume) {
    // The stage is already the SRC one; `next` is not recomputed from the strain, whose
    // floor could round differently just below a multiple of the interval.
    result.steps = cursor.steps;
    next = cursor.next_record;
  } else {
    engine.set_stress_control(0, pressure);
    // Units: sqrt(P/m) = sqrt(pressure) with m = 1.
    engine.set_strain_rate_control(1, options.gamma * std::sqrt(pressure));
    next = (std::floor(axial_strain(engine) / options.record_interval) + 1.0) *
           options.record_interval;
    cursor.steps = 0;
    cursor.next_record = next;
    control.safe_point(engine, cursor);  // the start: a last sane state before any step
  }
  while (axial_strain(engine) < epsilon_2_end) {
    engine.step();
    ++result.steps;
    if (stop_when && stop_when(engine)) {
      result.stopped = true;
      return result;
    }
    const double epsilon_2 = axial_strain(engine);
    if (epsilon_2 >= next || epsilon_2 >= epsilon_2_end) {
      next = (std::floor(epsilon_2 / options.record_interval) + 1.0) * options.record_interval;
      control.check(engine);
      engine.export_to(state);
      if (on_record && !on_record(engine, state)) {
        result.stopped = epsilon_2 < epsilon_2_end;
        return result;
      }
    }
    cursor.steps = result.steps;
    cursor.next_record = next;
    control.safe_point(engine, cursor);
  }
  return result;
}

StressStepResult run_stress_steps(
    Engine& engine, const StressStepOptions& options, double pressure, Configuration& state,
    const std::function<void(const Engine&, const Configuration&, const StressStepRecord&)>&
        on_equilibrium,
    const EquilibrationObserver& progress, const LoopControl& control) {
  if (!(options.delta_q > 0.0)) throw std::invalid_argument("SIC: delta_q must be > 0");
  StressStepResult result;
  const auto observer = [&](const Engine& e, const Configuration& s, const EquilibriumReport& r) {
    if (progress && !progress(e, s, r)) return false;
    return axial_strain(e) <= options.epsilon_2_max;
  };
  int k = 0;
  if (control.resume) {
    k = static_cast<int>(control.cursor.index);
    result.steps = control.cursor.done_steps;
    // Only increments that reached equilibrium lead to the next one.
    result.increments = std::max(0, k - 1);
  }
  for (;; ++k) {
    const bool resumed = control.resume && k == control.cursor.index;
    StressStepRecord record;
    // q_k from k, not by accumulation, so that round-off does not drift the targets.
    record.q_target = k * options.delta_q;
    if (record.q_target > options.q_max * (1.0 + 1e-12)) {
      result.stop_reason = "q_max";
      return result;
    }
    if (!resumed) {
      engine.set_stress_control(0, pressure);
      engine.set_stress_control(1, pressure * (1.0 + record.q_target));
    }
    LoopControl wait{control.hooks, resumed ? control.cursor : Cursor{}, resumed};
    wait.cursor.phase = control.cursor.phase;
    wait.cursor.index = k;
    wait.cursor.done_steps = result.steps;
    record.equilibrium =
        run_to_equilibrium(engine, options.equilibration, state, observer, {}, {}, wait);
    record.steps = record.equilibrium.steps;
    result.steps += record.steps;
    if (on_equilibrium) on_equilibrium(engine, state, record);
    if (!record.equilibrium.reached) {
      result.stop_reason = record.equilibrium.aborted ? "epsilon_2_max" : "no equilibrium";
      return result;
    }
    result.increments = k;
  }
}

}  // namespace granstab::protocols
