#include "compaction.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

namespace granstab::protocols {

CompactionResult compact_isotropically(Engine& engine, const CompactionOptions& options,
                                       Configuration& state, const EquilibrationObserver& observer,
                                       const LoopControl& control) {
  if (!(options.pressure > 0.0)) throw std::invalid_argument("compaction: pressure must be > 0");
  if (!(options.strain_rate >= 0.0)) {
    throw std::invalid_argument("compaction: strain_rate must be >= 0");
  }
  if (!(options.cell_mass_factor > 0.0) || !std::isfinite(options.cell_mass_factor)) {
    throw std::invalid_argument("compaction: cell_mass_factor must be finite and > 0");
  }
  CompactionResult result;
  const bool resume_phase_0 = control.resume && control.cursor.phase == 0;
  const bool resume_phase_1 = control.resume && control.cursor.phase == 1;
  // The cell masses on entry, restored at the end; a resumed run finds them in its cursor (the
  // engine already holds the scaled ones).
  const bool scaled_mass = options.cell_mass_factor != 1.0;
  std::vector<double> entry_mass;
  if (scaled_mass) {
    if (control.resume) {
      if (control.cursor.values.size() != 2) {
        throw std::invalid_argument("compaction: the resumed cursor lacks the entry cell masses");
      }
      entry_mass = control.cursor.values;
    } else {
      const auto mass = engine.cell().mass;
      entry_mass = {mass[0], mass[1]};
      engine.set_cell_mass(
          {mass[0] * options.cell_mass_factor, mass[1] * options.cell_mass_factor});
    }
  }
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
    cursor.values = entry_mass;
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
  wait.cursor.values = entry_mass;
  const EquilibrationResult eq =
      run_to_equilibrium(engine, options.equilibration, state, observer, {}, {}, wait);
  result.reached = eq.reached;
  result.stress_steps = eq.steps;
  result.report = eq.report;
  if (scaled_mass) engine.set_cell_mass({entry_mass[0], entry_mass[1]});
  engine.set_reference_lengths_to_current();
  engine.export_to(state);
  return result;
}

}  // namespace granstab::protocols
