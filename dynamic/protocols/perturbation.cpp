#include "perturbation.hpp"

#include <stdexcept>
#include <vector>

#include "common/measurements.hpp"

namespace granstab::protocols {

void run_perturbations(Engine& engine, const PerturbationOptions& options, std::mt19937_64& rng,
                       Configuration& state,
                       const std::function<bool(const Engine&, const Configuration&,
                                                const PerturbationRecord&)>& on_record,
                       const EquilibrationObserver& observer) {
  if (!(options.f0 > 0.0)) throw std::invalid_argument("perturbation: f0 must be > 0");
  const std::size_t n = engine.size();
  std::vector<double> fx(n), fy(n);
  std::uniform_real_distribution<double> component(-options.f0, options.f0);
  for (int draw = 1; draw <= options.repetitions; ++draw) {
    PerturbationRecord record;
    record.draw = draw;
    engine.export_to(state);
    const auto before = strains(state);
    record.epsilon_2_before = before[1];
    record.epsilon_v_before = before[2];
    // Fresh draws, x then y for each disk in index order (reproducible from the seed).
    double mean_x = 0.0, mean_y = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      fx[i] = component(rng);
      fy[i] = component(rng);
      mean_x += fx[i];
      mean_y += fy[i];
    }
    // In a periodic cell nothing holds the sample against a net external force: it would
    // accelerate as a whole and never come to rest. Only the fluctuating part is applied there.
    if (state.cell.periodic()) {
      mean_x /= static_cast<double>(n);
      mean_y /= static_cast<double>(n);
      for (std::size_t i = 0; i < n; ++i) {
        fx[i] -= mean_x;
        fy[i] -= mean_y;
      }
    }
    engine.set_external_forces(fx, fy);
    record.loaded = run_to_equilibrium(engine, options.equilibration, state, observer, fx, fy);
    const auto loaded = strains(state);
    record.delta_epsilon_2 = loaded[1] - before[1];
    record.delta_epsilon_v = loaded[2] - before[2];
    if (options.release) {
      engine.clear_external_forces();
      record.released = run_to_equilibrium(engine, options.equilibration, state, observer);
      const auto released = strains(state);
      record.delta_epsilon_2_released = released[1] - before[1];
      record.delta_epsilon_v_released = released[2] - before[2];
    }
    const bool go_on = on_record(engine, state, record);
    if (!go_on || !record.loaded.reached || (options.release && !record.released.reached)) break;
  }
  engine.clear_external_forces();
  engine.export_to(state);
}

}  // namespace granstab::protocols
