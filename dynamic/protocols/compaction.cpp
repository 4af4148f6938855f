#include "compaction.hpp"

#include <stdexcept>

namespace granstab::protocols {

CompactionResult compact_isotropically(Engine& engine, const CompactionOptions& options,
                                       Configuration& state, const EquilibrationObserver& observer,
                                       const LoopControl& control) {
  if (!(options.pressure > 0.0)) throw std::invalid_argument("compaction: pressure must be > 0");
  if (!(options.strain_rate >= 0.0)) {
    throw std::invalid_argument("compaction: strain_rate must be >= 0");
  }
  CompactionResult result;
  const bool resume_phase_0 = control.resume && control.cursor.phase == 0;
  const bool resume_phase_1 = control.resume && control.cursor.phase == 1;
  if (options.strain_rate > 0.0 && !resume_phase_1) {
    if (resume_phase_0) {
      result.strain_rate_steps = control.cursor.steps;  // the stage is already set
    } else {
      engine.set_reference_lengths_to_current();
      engine.set_strain_rate_control(0, options.strain_rate);
      engine.set_strain_rate_control(1, options.strain_rate);
    }
    Cursor cursor;
    cursor.phase = 0;
    if (!resume_phase_0) control.safe_point(engine, cursor);  // the start, before any step
    // The stress is a cached sum of the last force pass: checking it every step costs nothing.
    for (;;) {
      const auto sigma = engine.stress();
      if (0.5 * (sigma[0][0] + sigma[1][1]) >= options.pressure) break;
      if (result.strain_rate_steps >= options.max_strain_rate_steps) {
        throw std::runtime_error("compaction: the mean stress did not reach the pressure within " +
                                 std::to_string(options.max_strain_rate_steps) +
                                 " strain-rate steps");
      }
      engine.step();
      ++result.strain_rate_steps;
      cursor.steps = result.strain_rate_steps;
      control.safe_point(engine, cursor);
    }
  }
  LoopControl wait{control.hooks, Cursor{}, resume_phase_1};
  if (resume_phase_1) {
    result.strain_rate_steps = control.cursor.done_steps;
    wait.cursor = control.cursor;  // the stage is already stress control at P
  } else {
    engine.set_stress_control(0, options.pressure);
    engine.set_stress_control(1, options.pressure);
  }
  wait.cursor.phase = 1;
  wait.cursor.done_steps = result.strain_rate_steps;
  const EquilibrationResult eq =
      run_to_equilibrium(engine, options.equilibration, state, observer, {}, {}, wait);
  result.reached = eq.reached;
  result.stress_steps = eq.steps;
  result.report = eq.report;
  engine.set_reference_lengths_to_current();
  engine.export_to(state);
  return result;
}

}  // namespace granstab::protocols
