#include "compaction.hpp"

#include <stdexcept>

namespace granstab::protocols {

CompactionResult compact_isotropically(Engine& engine, const CompactionOptions& options,
                                       Configuration& state,
                                       const EquilibrationObserver& observer) {
  if (!(options.pressure > 0.0)) throw std::invalid_argument("compaction: pressure must be > 0");
  if (!(options.strain_rate >= 0.0)) {
    throw std::invalid_argument("compaction: strain_rate must be >= 0");
  }
  CompactionResult result;
  if (options.strain_rate > 0.0) {
    engine.set_reference_lengths_to_current();
    engine.set_strain_rate_control(0, options.strain_rate);
    engine.set_strain_rate_control(1, options.strain_rate);
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
    }
  }
  engine.set_stress_control(0, options.pressure);
  engine.set_stress_control(1, options.pressure);
  const EquilibrationResult eq = run_to_equilibrium(engine, options.equilibration, state, observer);
  result.reached = eq.reached;
  result.stress_steps = eq.steps;
  result.report = eq.report;
  engine.set_reference_lengths_to_current();
  engine.export_to(state);
  return result;
}

}  // namespace granstab::protocols
