#include "creep.hpp"

#include <stdexcept>

#include "common/measurements.hpp"

namespace granstab::protocols {

CreepResult hold_deviator(Engine& engine, double q_hold, double pressure,
                          const CreepOptions& options, Configuration& state,
                          const EquilibrationObserver& observer, const LoopControl& control) {
  CreepResult result;
  result.q_hold = q_hold;
  LoopControl wait = control;
  if (control.resume) {
    if (control.cursor.values.size() != 2) {
      throw std::invalid_argument("creep: a resumed hold needs the strains at the switch");
    }
    result.epsilon_2_switch = control.cursor.values[0];
    result.epsilon_v_switch = control.cursor.values[1];
  } else {
    engine.export_to(state);
    const auto start = strains(state);
    result.epsilon_2_switch = start[1];
    result.epsilon_v_switch = start[2];
    engine.set_stress_control(0, pressure);
    engine.set_stress_control(1, pressure * (1.0 + q_hold));
    wait.cursor.values = {result.epsilon_2_switch, result.epsilon_v_switch};
  }
  const auto guarded = [&](const Engine& e, const Configuration& s, const EquilibriumReport& r) {
    if (observer && !observer(e, s, r)) return false;
    return axial_strain(e) - result.epsilon_2_switch <= options.failure_delta_epsilon_2;
  };
  result.equilibrium =
      run_to_equilibrium(engine, options.equilibration, state, guarded, {}, {}, wait);
  const auto end = strains(state);
  result.epsilon_2_end = end[1];
  result.epsilon_v_end = end[2];
  return result;
}

}  // namespace granstab::protocols
